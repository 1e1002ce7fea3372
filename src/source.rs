//! Source files and spans: the bottom of the pipeline.
//!
//! Every `.scn` file the compiler reads (the root scene and each `include`) is stored once in a
//! [`SourceMap`] and named by a [`FileId`]. A [`Span`] is a byte range inside one of those files; it
//! travels from the AST through the IR (paths keep the span of their string literal) so that a
//! diagnostic raised in any later stage can point back at the text the user wrote.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use miette::{NamedSource, SourceSpan};
use serde::Serialize;

mod order;
mod renumber;

pub use order::ReadingOrder;
pub use renumber::Renumber;

/// Index of a file inside a [`SourceMap`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct FileId(pub u32);

/// A byte range `start..end` inside one source file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Span {
    /// The file the range lies in.
    pub file: FileId,
    /// Byte offset of the first byte, from the start of the file's text.
    pub start: u32,
    /// Byte offset one past the last byte; equal to `start` for an empty span.
    pub end: u32,
}

impl Span {
    /// The byte range `start..end` of `file` (`start ≤ end`, asserted in debug builds).
    pub fn new(file: FileId, start: usize, end: usize) -> Span {
        debug_assert!(start <= end, "span start {start} after end {end}");
        Span {
            file,
            start: start as u32,
            end: end as u32,
        }
    }

    /// The smallest span covering both `self` and `other` (same file assumed).
    pub fn join(self, other: Span) -> Span {
        debug_assert_eq!(self.file, other.file, "joining spans of different files");
        Span {
            file: self.file,
            start: self.start.min(other.start),
            end: self.end.max(other.end),
        }
    }

    /// Length in bytes.
    pub fn len(&self) -> usize {
        (self.end - self.start) as usize
    }

    /// Whether the span covers no bytes (a position, such as the end of the input).
    pub fn is_empty(&self) -> bool {
        self.start == self.end
    }

    /// The byte range, for slicing the file's text.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }

    /// The span as miette wants it.
    pub fn source_span(&self) -> SourceSpan {
        SourceSpan::new((self.start as usize).into(), self.len())
    }
}

/// Spans serialise as `file#start..end` so that IR snapshots stay readable.
impl Serialize for Span {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{}#{}..{}", self.file.0, self.start, self.end))
    }
}

/// One source file: where it lives, how it is shown in diagnostics, and its text.
#[derive(Debug, Clone)]
pub struct SourceFile {
    /// The path used to read the file (absolute or relative to the working directory).
    pub path: PathBuf,
    /// The name shown in diagnostics: the path as the user or the including file wrote it.
    pub name: String,
    /// The whole text as read; spans index it by byte. Shared with diagnostics without copying.
    pub text: Arc<str>,
    /// The byte offset of every line's start, made when a diagnostic is first placed in the
    /// file ([`SourceMap::line_col`]): 1,000 diagnostics in an 8.8 MB file each counted the
    /// newlines before their label, 9.5 s in `scnc watch` (docs/watch.md).
    line_starts: Arc<std::sync::OnceLock<Vec<u32>>>,
}

/// All source files of one compile, indexed by [`FileId`].
#[derive(Debug, Clone, Default)]
pub struct SourceMap {
    files: Vec<SourceFile>,
}

impl SourceMap {
    /// An empty map.
    pub fn new() -> SourceMap {
        SourceMap::default()
    }

    /// Stores a file and returns its id; ids count up from 0 in the order files are added.
    pub fn add(
        &mut self,
        path: impl Into<PathBuf>,
        name: impl Into<String>,
        text: impl Into<Arc<str>>,
    ) -> FileId {
        let id = FileId(self.files.len() as u32);
        self.files.push(SourceFile {
            path: path.into(),
            name: name.into(),
            text: text.into(),
            line_starts: Arc::default(),
        });
        id
    }

    /// The map with file `id`'s text replaced by `text` (its line index made again when
    /// needed); every other file's entry, line index included, is shared, not made again (an
    /// edit of one included file of a scene split over many).
    pub fn with_text(&self, id: FileId, text: impl Into<Arc<str>>) -> SourceMap {
        let mut map = self.clone();
        if let Some(f) = map.files.get_mut(id.0 as usize) {
            f.text = text.into();
            f.line_starts = Arc::default();
        }
        map
    }

    /// [`SourceMap::with_text`] for an edit that `shift` describes (the old and new texts agree
    /// before `shift.start` and after its ends): when the old text's line index was made, the
    /// new one is made from it (the lines before the edit kept, those after it moved, the
    /// edited bytes searched), not from the whole text again: 1.6 ms for an 8.8 MB file, which
    /// every edit's diagnostics paid (2026-11-26, seventh session).
    pub fn with_edit(&self, shift: &Shift, text: impl Into<Arc<str>>) -> SourceMap {
        let mut map = self.with_text(shift.file, text);
        let (Some(old), Some(new)) = (
            self.files.get(shift.file.0 as usize),
            map.files.get_mut(shift.file.0 as usize),
        ) else {
            return map;
        };
        let Some(starts) = old.line_starts.get() else {
            return map;
        };
        let (start, old_end, new_end) = (shift.start, shift.old_end, shift.new_end);
        let old_tail = old.text.len().checked_sub(old_end as usize);
        let agree = start <= old_end && old_tail.is_some();
        let new_tail = new.text.len().checked_sub(new_end as usize);
        let edited = new.text.as_bytes().get(start as usize..new_end as usize);
        let Some(edited) = edited.filter(|_| agree && old_tail == new_tail) else {
            return map;
        };
        let kept = starts.partition_point(|&s| s <= start);
        let after = starts.partition_point(|&s| s <= old_end);
        let mut moved = Vec::with_capacity(starts.len() - after + kept + 16);
        moved.extend_from_slice(&starts[..kept]);
        moved.extend(memchr::memchr_iter(b'\n', edited).map(|i| start + i as u32 + 1));
        moved.extend(starts[after..].iter().map(|&s| s - old_end + new_end));
        new.line_starts = Arc::new(std::sync::OnceLock::from(moved));
        map
    }

    /// Drops the files from the `len`th on: an included file no longer read (the incremental
    /// compile's include removed, when it was the last file read).
    pub fn truncate(&mut self, len: usize) {
        self.files.truncate(len);
    }

    /// Stores a file as the `at`th, every file from `at` on moving up by one (the incremental
    /// compile's include added before other files are read: [`Renumber::Inserted`]); `None`
    /// when `at` is past the last file.
    pub fn insert(
        &mut self,
        at: FileId,
        path: impl Into<PathBuf>,
        name: impl Into<String>,
        text: impl Into<Arc<str>>,
    ) -> Option<()> {
        let at = at.0 as usize;
        if at > self.files.len() {
            return None;
        }
        let file = SourceFile {
            path: path.into(),
            name: name.into(),
            text: text.into(),
            line_starts: Arc::default(),
        };
        self.files.insert(at, file);
        Some(())
    }

    /// Drops file `id`, every later file moving down by one (an included file no longer read,
    /// read before others: [`Renumber::Removed`]); `None` when there is no such file.
    pub fn remove(&mut self, id: FileId) -> Option<()> {
        let at = id.0 as usize;
        (at < self.files.len()).then(|| {
            self.files.remove(at);
        })
    }

    /// The file `id` names. `id` must come from this map's [`SourceMap::add`].
    pub fn get(&self, id: FileId) -> &SourceFile {
        // ok: FileIds are only minted by `add` on this map.
        &self.files[id.0 as usize]
    }

    /// Every file with its id, in the order they were added.
    pub fn files(&self) -> impl Iterator<Item = (FileId, &SourceFile)> {
        self.files
            .iter()
            .enumerate()
            .map(|(i, f)| (FileId(i as u32), f))
    }

    /// The id of the file read from `path` (compared as written, not canonicalised).
    pub fn find(&self, path: &Path) -> Option<FileId> {
        self.files
            .iter()
            .position(|f| f.path == path)
            .map(|i| FileId(i as u32))
    }

    /// The text a span covers.
    pub fn snippet(&self, span: Span) -> &str {
        self.get(span.file).text.get(span.range()).unwrap_or("")
    }

    /// The file as a miette source, for diagnostics that label spans in it.
    pub fn named_source(&self, id: FileId) -> NamedSource<Arc<str>> {
        let f = self.get(id);
        NamedSource::new(f.name.clone(), f.text.clone())
    }

    /// 1-based line and column (in bytes) of a byte offset, for plain messages.
    pub fn line_col(&self, id: FileId, offset: usize) -> (usize, usize) {
        let file = self.get(id);
        let text = &file.text;
        let offset = text.floor_char_boundary_compat(offset.min(text.len()));
        let starts = file.line_starts.get_or_init(|| {
            let newlines = memchr::memchr_iter(b'\n', text.as_bytes());
            std::iter::once(0)
                .chain(newlines.map(|i| i as u32 + 1))
                .collect()
        });
        let line = starts.partition_point(|&s| s as usize <= offset);
        let start = starts.get(line.wrapping_sub(1)).copied().unwrap_or(0) as usize;
        (line.max(1), offset - start + 1)
    }
}

trait FloorCharBoundary {
    fn floor_char_boundary_compat(&self, i: usize) -> usize;
}

impl FloorCharBoundary for str {
    fn floor_char_boundary_compat(&self, mut i: usize) -> usize {
        while i > 0 && !self.is_char_boundary(i) {
            i -= 1;
        }
        i
    }
}

/// How the spans of one file move after an edit replaced its bytes `start..old_end` by
/// `new_len` others (the incremental compile): spans before the edit stay, spans after it move
/// by the change in length, and a span that reaches into the edited bytes has no new place.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shift {
    /// The edited file.
    pub file: FileId,
    /// First edited byte (old and new text agree before it).
    pub start: u32,
    /// One past the last edited byte of the old text (they agree after it).
    pub old_end: u32,
    /// One past the last edited byte of the new text.
    pub new_end: u32,
}

impl Shift {
    /// Moves `span` to where its bytes are in the new text; `false` (span unchanged) when it
    /// reaches into the edited bytes.
    pub fn apply(&self, span: &mut Span) -> bool {
        if span.file != self.file || span.end <= self.start {
            return true;
        }
        if span.start < self.old_end {
            return false;
        }
        // Both are past `old_end`, so neither goes below `new_end`.
        span.start = span.start - self.old_end + self.new_end;
        span.end = span.end - self.old_end + self.new_end;
        true
    }
}

/// How spans move after a change of the sources: an edit's [`Shift`] (bytes of one file), or a
/// file read before others, or no longer read, whose later files' ids move ([`Renumber`]). What
/// holds spans (the IR, diagnostics, the check's memo) moves them through this, whichever it is.
pub trait MoveSpans {
    /// Moves `span` to its new place; `false` (span unchanged) when it has none.
    fn apply(&self, span: &mut Span) -> bool;
}

impl MoveSpans for Shift {
    fn apply(&self, span: &mut Span) -> bool {
        Shift::apply(self, span)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Seeded edits (lines and characters inserted, deleted, replaced) of a text whose line
    /// index was made: the index made from the old one places every offset as a fresh map's.
    #[test]
    fn a_line_index_made_from_the_old_one_is_a_fresh_ones() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: usize| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % n as u64) as usize
        };
        let pieces = ["a", "\n", "bc\n", "\n\n", "é", "xyz", ""];
        let mut text: String = (0..40).map(|_| pieces[next(pieces.len())]).collect();
        for _ in 0..500 {
            let mut map = SourceMap::new();
            let file = map.add("t.scn", "t.scn", text.as_str());
            map.line_col(file, 0);
            let mut start = next(text.len() + 1);
            while !text.is_char_boundary(start) {
                start -= 1;
            }
            let mut old_end = (start + next(6)).min(text.len());
            while !text.is_char_boundary(old_end) {
                old_end += 1;
            }
            let inserted: String = (0..next(4)).map(|_| pieces[next(pieces.len())]).collect();
            let new_text = format!("{}{inserted}{}", &text[..start], &text[old_end..]);
            let shift = Shift {
                file,
                start: start as u32,
                old_end: old_end as u32,
                new_end: (start + inserted.len()) as u32,
            };
            let edited = map.with_edit(&shift, new_text.as_str());
            assert!(
                edited.get(file).line_starts.get().is_some(),
                "made from the old"
            );
            let mut fresh = SourceMap::new();
            fresh.add("t.scn", "t.scn", new_text.as_str());
            for offset in 0..=new_text.len() + 1 {
                assert_eq!(
                    edited.line_col(file, offset),
                    fresh.line_col(file, offset),
                    "{text:?} -> {new_text:?} at {offset}"
                );
            }
            text = new_text;
        }
    }
}
