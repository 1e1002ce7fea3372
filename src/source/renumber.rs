//! File ids renumbered: the incremental compile's include added before other files are read,
//! or removed while others are read after it (2026-11-29, eighteenth session).
//!
//! The driver gives each file the next [`FileId`] when it first reads it, so the ids are the
//! files' reading order. An include added at a place where other files are read after it reads
//! its file before them: a fresh compile gives it the id the first of them had, and each of
//! them the next. An include removed that read a file before others gives each of them the id
//! before. Every span of those files (in the IR, the diagnostics, the check's memo, the reading
//! order) then names its file by the new id, as the fresh compile's do: [`Renumber`] is that
//! move, applied through [`MoveSpans`] by everything that moves spans after an edit.

use super::{FileId, MoveSpans, Span};

/// A change of file ids: one file read at `at` before the files that had the ids from `at` on,
/// or the file `at` no longer read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Renumber {
    /// A file read as the `at`th: every id from `at` on moves up by one.
    Inserted(FileId),
    /// The file `at` no longer read: every later id moves down by one, and no span may name it.
    Removed(FileId),
}

impl Renumber {
    /// The new id of the file `id`; `None` for the file removed (or an id past the last one a
    /// `u32` counts).
    pub fn id(&self, id: FileId) -> Option<FileId> {
        match *self {
            Renumber::Inserted(at) if id >= at => id.0.checked_add(1).map(FileId),
            Renumber::Removed(at) if id == at => None,
            Renumber::Removed(at) if id > at => id.0.checked_sub(1).map(FileId),
            _ => Some(id),
        }
    }
}

impl MoveSpans for Renumber {
    fn apply(&self, span: &mut Span) -> bool {
        match self.id(span.file) {
            Some(file) => {
                span.file = file;
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_from_an_inserted_file_on_move_up_and_after_a_removed_one_down() {
        let ids = |r: Renumber| -> Vec<Option<u32>> {
            (0..4).map(|i| r.id(FileId(i)).map(|f| f.0)).collect()
        };
        let inserted = Renumber::Inserted(FileId(1));
        assert_eq!(ids(inserted), vec![Some(0), Some(2), Some(3), Some(4)]);
        let removed = Renumber::Removed(FileId(1));
        assert_eq!(ids(removed), vec![Some(0), None, Some(1), Some(2)]);
        let mut span = Span::new(FileId(2), 3, 5);
        assert!(inserted.apply(&mut span));
        assert_eq!(span, Span::new(FileId(3), 3, 5));
        assert!(removed.apply(&mut span) && span.file == FileId(2));
        let mut gone = Span::new(FileId(1), 0, 1);
        assert!(
            !removed.apply(&mut gone),
            "a span of the file removed has no place"
        );
        assert_eq!(gone.file, FileId(1), "and is left as it was");
        assert_eq!(Renumber::Inserted(FileId(0)).id(FileId(u32::MAX)), None);
    }
}
