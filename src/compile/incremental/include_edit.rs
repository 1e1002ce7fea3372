//! The incremental compile's include edits: an `include "part.scn"` line added or removed in a
//! scene file (2026-11-29, fourteenth session; a full compile before). `scnc watch` on a scene
//! split over files, a part typed in or taken out.
//!
//! The driver expands an include in place: the included file's statements stand before the
//! include statement, and the file gets the next file id when it is first read. So an include
//! added is a block of added statements (the file's, then the include) at the include's
//! place, and an include removed a block of removed statements, checked by the paths that add
//! or remove statements: `object`s alone ([`CheckMemo::recheck_block`]), or `material`, `mesh`
//! and `texture` declarations with them ([`CheckMemo::add_or_remove_decl`]); the version
//! header and the include are checked in no phase.
//!
//! An include of a file read wholly before it (a line duplicated below itself: the driver reads
//! each file once) reads nothing: added or removed, it is one statement no phase checks, its
//! place kept (2026-11-29, seventeenth session). An include pointed at another file is the old
//! file's removal, then the new file's addition at the same place (with no shift: the edit's
//! moved every span already), each taken as above.
//!
//! Taken only where no other file changes its reading: the file added is not read yet, and
//! the one removed was read by this include and no other include names it (its file name occurs
//! in no other scene file); no `--define` (its file comes after the scene's). Where other files
//! are read after the include (an include added at a file's start or middle, or removed there:
//! full compiles before the eighteenth session), a fresh compile moves their ids up or down by
//! one: the memo's are renumbered first for an addition, after the removal's check for a
//! removal ([`super::file_ids`]). Declined (a full compile, which reports them): an include
//! that cannot be read, closes a cycle, names a file read already (but wholly before it) or
//! nests too deep; an included file with a syntax error, an include of its own, or a `let`,
//! camera, light or render block (statements these paths do not add), or `group`s beside
//! declarations. An included file of `group`s and `object`s is checked as an edit of them is
//! ([`CheckMemo::recheck_placements`]; eighteenth session, a full compile before).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{file_ids, scene_texts, supported_header, Memo};
use crate::assets::Loader;
use crate::check::{inert, CheckMemo};
use crate::compile::dependents::SceneStatements;
use crate::compile::edit::Region;
use crate::compile::{decode, normalise, MAX_INCLUDE_DEPTH};
use crate::source::{FileId, Renumber, SourceMap};
use crate::syntax::{self, Expr, ExprKind, Stmt};

impl Memo {
    /// The edit of `file` that replaced its old statements `old_stmts` (list indices `old`) by
    /// `new`, when one of them is an include added or removed alone; `sources` holds the new
    /// text. The number of statements checked again, or `None` when only a full compile can
    /// (the memo is then spoiled).
    #[allow(clippy::too_many_arguments)] // the edit's parts, as `Memo::edit` found them
    pub(super) fn include_edit(
        &mut self,
        file: FileId,
        loader: &dyn Loader,
        region: &Region,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        sources: SourceMap,
    ) -> Option<usize> {
        // A `--define`'s file is read after the scene's: a file added or removed moves its id.
        if self.sources.files().count() != self.scene_files {
            return None;
        }
        self.chunks_whole = None;
        match (old_stmts, new) {
            ([], [include @ Stmt::Include { path, .. }]) => {
                self.include_added(file, loader, region, old, include, path, sources)
            }
            ([include @ Stmt::Include { path, .. }], []) => {
                self.include_removed(file, region, old, include, path, sources)
            }
            ([was @ Stmt::Include { path: from, .. }], [now @ Stmt::Include { path: to, .. }]) => {
                // Pointed at another file: the old one's removal, then the new one's addition
                // at the same place, each as above (a fresh compile gives the new file the id
                // the old one had, when that was the last read).
                let before = self.spans.len();
                let removed =
                    self.include_removed(file, region, old.clone(), was, from, sources)?;
                // The list index the removed block (the file's statements and the include) began at.
                let at = old.end.checked_sub(before.checked_sub(self.spans.len())?)?;
                let place = now.span().start;
                let none = Region {
                    shift: crate::source::Shift {
                        file,
                        start: place,
                        old_end: place,
                        new_end: place,
                    },
                    stmts: at..at,
                    bytes: place as usize..place as usize,
                };
                let sources = self.sources.clone();
                let added = self.include_added(file, loader, &none, at..at, now, to, sources)?;
                Some(removed + added)
            }
            _ => None,
        }
    }

    /// `include` (its file name `name`) added in `file` at the list index `old.start`.
    #[allow(clippy::too_many_arguments)] // as `include_edit`
    fn include_added(
        &mut self,
        file: FileId,
        loader: &dyn Loader,
        region: &Region,
        old: Range<usize>,
        include: &Stmt,
        name: &Expr,
        mut sources: SourceMap,
    ) -> Option<usize> {
        let path = resolve(&self.sources, file, name)?;
        if let Some(id) = self.sources.find(&path) {
            // Read wholly before this place: the driver reads nothing for it.
            self.read_before(id, file, old.start).then_some(())?;
            return self.inert_include(region, old, &[], std::slice::from_ref(include), sources);
        }
        // Too deep: the driver's business.
        let depth = self.check.order.depth(file);
        if depth + 1 >= MAX_INCLUDE_DEPTH {
            return None;
        }
        // The id after those of the files read before it (`file_ids`).
        let at = file_ids::read_before(&self.files, old.start, self.scene_files)?;
        let id = FileId(u32::try_from(at).ok()?);
        let bytes = loader.read(&path).ok()?;
        let text = decode(&bytes).ok()?;
        if text.trim().is_empty() {
            return None;
        }
        let (parsed, diags) = syntax::parse(id, text).into_parts();
        let mut block = parsed?.statements;
        match block.split_first() {
            Some((header, rest)) if diags.is_empty() && supported_header(header) => {
                rest.iter().all(|s| !inert(s)).then_some(())?
            }
            _ => return None,
        }
        if at < self.scene_files {
            // Files are read after it: each of their ids moves up by one.
            self.renumber(&Renumber::Inserted(id))?;
        }
        let shown = path.display().to_string();
        sources.insert(id, path, shown, Arc::<str>::from(text))?;
        block.push(include.clone());
        if self.files.is_empty() {
            self.files = vec![FileId(0); self.spans.len()];
        }
        self.move_spans(region, old.clone(), &block)?;
        self.check.order.set(id, name.span);
        self.scene_files += 1;
        let checked = self.check_block(&sources, old, &[], &block, &region.shift)?;
        self.sources = sources;
        Some(checked)
    }

    /// `include` (its file name `name`, the list index `old.start`) removed from `file`.
    fn include_removed(
        &mut self,
        file: FileId,
        region: &Region,
        old: Range<usize>,
        include: &Stmt,
        name: &Expr,
        mut sources: SourceMap,
    ) -> Option<usize> {
        let path = resolve(&self.sources, file, name)?;
        let id = self.sources.find(&path)?;
        let reader = self.check.order.included_at(id) == Some(name.span);
        if !reader && self.read_before(id, file, old.start) {
            // A later include of a file read before it: it read nothing.
            return self.inert_include(region, old, std::slice::from_ref(include), &[], sources);
        }
        // Read by this include (not one before it of the same file); when other files are
        // read after it, their ids move down by one once the removal is checked.
        let last = id.0 as usize + 1 == self.scene_files;
        let scene_file = id != FileId(0) && (id.0 as usize) < self.scene_files;
        if !scene_file || !reader {
            return None;
        }
        // No other include reads it once this one is gone.
        let needle = path.file_name()?.to_str()?.as_bytes();
        let named = |(f, text): (FileId, &str)| {
            if f == id {
                return false;
            }
            let mut hits = memchr::memmem::find_iter(text.as_bytes(), needle).peekable();
            // A block comment could close on a commented line and an include follow: then
            // no hit is passed over. Searched once per file, and only when it has a hit.
            if hits.peek().is_none() {
                return false;
            }
            let block_comment = memchr::memmem::find(text.as_bytes(), b"/*").is_some();
            hits.any(|at| block_comment || !in_line_comment(text, at))
        };
        let texts = sources.files().map(|(f, s)| (f, &*s.text));
        if texts.take(self.scene_files).any(named) {
            return None;
        }
        // Its statements: a run of the list just before the include (it includes nothing).
        let first = self.files.iter().position(|&f| f == id)?;
        let own = self.files.iter().filter(|&&f| f == id).count();
        if first + own != old.start {
            return None;
        }
        let block = first..old.end;
        let old_text = self.sources.get(id).text.clone();
        let records = self.check.records.get(first..old.start)?;
        let objects = records.iter().skip(1).all(|r| r.object);
        // The removed statements: parsed only when they are more than `object`s (the records
        // tell those; the first is the version header, which the driver requires).
        let old_stmts = match objects {
            true => None,
            false => {
                let (parsed, diags) = syntax::parse(id, &old_text).into_parts();
                let mut stmts = parsed?.statements;
                let whole = diags.is_empty() && stmts.len() == own;
                (whole && stmts.iter().skip(1).all(|s| !inert(s))).then_some(())?;
                stmts.push(include.clone());
                Some(stmts)
            }
        };
        if last {
            self.check.order.truncate(id.0 as usize);
            sources.truncate(id.0 as usize);
        } else {
            // Its entries stay until the removal is checked (the other files' ids with them).
            self.check.order.forget(id);
        }
        self.move_spans(region, block.clone(), &[])?;
        if last {
            self.scene_files -= 1;
            if self.scene_files == 1 {
                self.files.clear();
            }
        }
        let checked = match old_stmts {
            None => {
                let shift = &region.shift;
                let inert_at = [first, old.start];
                (self.check)
                    .recheck_block(&sources, block, &inert_at, &[], shift)
                    .then_some(0)?
            }
            Some(stmts) => self.check_block(&sources, block, &stmts, &[], &region.shift)?,
        };
        if !last {
            self.renumber(&Renumber::Removed(id))?;
            sources.remove(id)?;
            self.scene_files -= 1;
        }
        self.sources = sources;
        Some(checked)
    }

    /// Whether the scene file `id` is read wholly before the list index `at` of `file`'s
    /// statements (not the root, not `file`, none of its statements at or after `at`): then
    /// it is not `file` or a file that includes it (each of those has a statement after `at`,
    /// the include that reads the next file toward `file`), so an include of it at `at` closes
    /// no cycle, and the driver, which reads each file once, reads nothing for it.
    fn read_before(&self, id: FileId, file: FileId, at: usize) -> bool {
        let (before, after) = self.files.split_at(at.min(self.files.len()));
        id != FileId(0)
            && id != file
            && (id.0 as usize) < self.scene_files
            && before.contains(&id)
            && !after.contains(&id)
    }

    /// An include that reads nothing (`old_stmts` or `new`, one statement at the list range
    /// `old`) removed or added: a statement no phase checks, its place alone kept.
    fn inert_include(
        &mut self,
        region: &Region,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        sources: SourceMap,
    ) -> Option<usize> {
        self.move_spans(region, old.clone(), new)?;
        let checked = self.check_block(&sources, old, old_stmts, new, &region.shift)?;
        self.sources = sources;
        Some(checked)
    }

    /// Checks the block `new` in place of the old statements `old` (`old_stmts`): `object`s
    /// alone, `object`s and `group`s, or declarations with `object`s. The number of statements
    /// checked again.
    fn check_block(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &crate::source::Shift,
    ) -> Option<usize> {
        let placed = |s: &&Stmt| !inert(s);
        let kinds = || old_stmts.iter().chain(new).filter(placed);
        if kinds().all(|s| matches!(s, Stmt::Object(_))) {
            let inert_at: Vec<usize> = (old.start..)
                .zip(old_stmts)
                .filter(|(_, s)| inert(s))
                .map(|(i, _)| i)
                .collect();
            let check = &mut self.check;
            return check
                .recheck_block(sources, old, &inert_at, new, shift)
                .then_some(new.len());
        }
        if kinds().all(|s| matches!(s, Stmt::Object(_) | Stmt::Group(_))) {
            // `group`s among them (eighteenth session): checked as an edit of placements is, the
            // old statements' uses counted against the old text (the memo's sources).
            let old_sources = &self.sources;
            let check = &mut self.check;
            return check.recheck_placements(old_sources, sources, old, old_stmts, new, shift);
        }
        let files = scene_texts(&self.spans, &self.files, self.scene_files, sources);
        let mut naming = SceneStatements(files);
        let check = &mut self.check;
        CheckMemo::add_or_remove_decl(check, sources, old, old_stmts, new, shift, &mut naming)
    }
}

/// The path an include's file name `name` in `from` reads, as the driver resolves it.
fn resolve(sources: &SourceMap, from: FileId, name: &Expr) -> Option<PathBuf> {
    let ExprKind::Str(written) = &name.kind else {
        return None;
    };
    let file = &sources.get(from).path;
    let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
    Some(normalise(&dir.join(written)))
}

/// Whether byte `at` of `text` lies in a line comment that reads nothing: its line starts
/// (after blanks) with `//` and the line before it does not end with `\` (a string's escaped
/// newline). Only for a text with no `/*` (a block comment could close on that line and an
/// include follow): the caller searches for that once per file, not once per hit. The include
/// line commented out (`// include "part.scn"`) still names its file; this tells that such a
/// mention is not an include (fifteenth session).
fn in_line_comment(text: &str, at: usize) -> bool {
    let Some(head) = text.get(..at) else {
        return false;
    };
    let start = head.rfind('\n').map_or(0, |i| i + 1);
    let escaped = head[..start].trim_end_matches(['\n', '\r']).ends_with('\\');
    head[start..].trim_start().starts_with("//") && !escaped
}
