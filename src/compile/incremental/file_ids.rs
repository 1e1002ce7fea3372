//! The incremental compile's file ids after an include edit that reads a file before others,
//! or no longer reads one that was (2026-11-29, eighteenth session; a full compile before).
//!
//! The driver gives each file the next id when it first reads it: the ids are the order in
//! which the files' statements first appear in the statement list (each file starts with its
//! version header, so each has one). A file included at a list index gets the id after those
//! of the files read before that index ([`read_before`]); when files are read after it, each
//! of their ids moves up by one, and when such a file is no longer read, each later id moves
//! down by one. [`Memo::renumber`] moves them in the memo (the statements' files, and through
//! [`CheckMemo::renumber_files`](crate::check::CheckMemo::renumber_files) every span the
//! check keeps: diagnostics, IR, constants, name tables, the reading order); the caller
//! inserts or removes the file's entry in the sources.

use super::Memo;
use crate::source::{FileId, Renumber};

impl Memo {
    /// Every file id of the memo moved by `renumber`; `None` (the memo spoiled) when a
    /// statement or a span is of the file removed, or the check declines.
    pub(super) fn renumber(&mut self, renumber: &Renumber) -> Option<()> {
        for f in &mut self.files {
            *f = renumber.id(*f)?;
        }
        self.check.renumber_files(renumber).then_some(())
    }
}

/// How many files are read before the list index `at` (`files`: each statement's file, empty
/// for a scene of one file, `scene_files` of them): the id a fresh compile gives a file first
/// read at `at`. `None` when the ids before `at` are not the first ones (a memo whose ids are
/// not the reading order: the caller compiles in full).
pub(super) fn read_before(files: &[FileId], at: usize, scene_files: usize) -> Option<usize> {
    if files.is_empty() {
        return Some(1);
    }
    let mut seen = vec![false; scene_files];
    let mut count = 0usize;
    for f in files.get(..at.min(files.len()))? {
        let s = seen.get_mut(f.0 as usize)?;
        if !*s {
            *s = true;
            count += 1;
        }
    }
    seen.get(..count)?.iter().all(|&s| s).then_some(count)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_included_gets_the_id_after_the_files_read_before_it() {
        // File 0: statements 0, 1, (file 1: 2, 3), 4 (the include), 5; then (file 2: 6), 7.
        let files = [0, 0, 1, 1, 0, 0, 2, 0].map(FileId);
        assert_eq!(read_before(&files, 1, 3), Some(1), "files 1 and 2 after");
        assert_eq!(read_before(&files, 2, 3), Some(1));
        assert_eq!(read_before(&files, 5, 3), Some(2), "file 2 after");
        assert_eq!(read_before(&files, 7, 3), Some(3), "read last");
        assert_eq!(read_before(&files, 8, 3), Some(3));
        assert_eq!(read_before(&[], 3, 1), Some(1), "one file");
        // Ids not in reading order, or past the scene's files: declined.
        let swapped = [0, 2, 2, 0, 1].map(FileId);
        assert_eq!(read_before(&swapped, 3, 3), None);
        assert_eq!(read_before(&files, 8, 2), None);
    }
}
