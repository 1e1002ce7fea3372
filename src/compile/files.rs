//! The incremental compile's view of a scene split over included files: one file's top-level
//! statements out of the statement list the check reads.
//!
//! The driver expands `include "file.scn"` in place: the included file's statements stand
//! before the include statement, after everything before it. The memo keeps the byte range
//! and the file of every statement in that order; an edit of one file is found and parsed in
//! that file's statements alone ([`super::edit`] works on one text) and its statement indices
//! are then mapped back to the list's (a run of one file's statements with no include in it is
//! a run of the list, which the mapping checks).

use std::ops::Range;

use crate::source::FileId;

/// One file's statements: their byte ranges in order, and their indices in the list.
pub(super) struct FileStatements {
    pub spans: Vec<(u32, u32)>,
    pub flat: Vec<usize>,
}

/// The statements of `file` among `spans` (every statement's byte range, in list order) whose
/// files are `files`.
pub(super) fn of_file(spans: &[(u32, u32)], files: &[FileId], file: FileId) -> FileStatements {
    let mut view = FileStatements {
        spans: Vec::new(),
        flat: Vec::new(),
    };
    for (i, (&span, &f)) in spans.iter().zip(files).enumerate() {
        if f == file {
            view.spans.push(span);
            view.flat.push(i);
        }
    }
    view
}

impl FileStatements {
    /// The list indices of the file's statements `range` (its own indices); for an empty range,
    /// the place after its statement before (where statements inserted there go, before an
    /// included file's statements when an include follows). `None` when the statements are not
    /// one run of the list (an included file's statements lie among them).
    pub fn list_range(&self, range: Range<usize>) -> Option<Range<usize>> {
        if range.is_empty() {
            let at = match range.start.checked_sub(1) {
                Some(before) => self.flat.get(before)? + 1,
                None => self.flat.first().copied().unwrap_or(0),
            };
            return Some(at..at);
        }
        let first = *self.flat.get(range.start)?;
        let last = *self.flat.get(range.end - 1)?;
        (last - first + 1 == range.len()).then_some(first..last + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_of_one_file_maps_to_the_list_unless_an_include_splits_it() {
        // File 0: statements 0, 1, (file 1: 2, 3), 4 (the include), 5.
        let files = [0, 0, 1, 1, 0, 0].map(FileId);
        let spans = [(0, 6), (7, 10), (0, 6), (7, 9), (11, 30), (31, 40)];
        let root = of_file(&spans, &files, FileId(0));
        assert_eq!(root.spans, vec![(0, 6), (7, 10), (11, 30), (31, 40)]);
        assert_eq!(root.list_range(0..2), Some(0..2));
        assert_eq!(root.list_range(2..4), Some(4..6));
        assert_eq!(root.list_range(1..3), None, "file 1's statements between");
        assert_eq!(
            root.list_range(2..2),
            Some(2..2),
            "before the included statements"
        );
        assert_eq!(root.list_range(4..4), Some(6..6));
        let included = of_file(&spans, &files, FileId(1));
        assert_eq!(included.list_range(1..2), Some(3..4));
        assert_eq!(included.list_range(2..2), Some(4..4), "before the include");
    }
}
