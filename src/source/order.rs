//! Reading order across included files: which of two spans the compile reads first.
//!
//! The driver expands `include "file.scn"` in place: the included file's statements come
//! after every statement before the include and before the include statement itself (and all
//! after it). Byte offsets order the statements of one file; across files the order is that of
//! the include chains from the root. The incremental re-check asks it where the full check
//! relies on statement order (a `let` names only constants declared before it; a declaration
//! added takes its place among those of its kind); `compile::Incremental` keeps it, moving the
//! include statements' offsets with each edit.

use super::{MoveSpans, Renumber, Shift, Span};

/// Where each file was included from, to order spans of different files.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReadingOrder {
    /// Per file id: the span of the file name in the include statement that read it (in the
    /// including file; `None` for the root, and for files no include read: `--define`s, read
    /// after it all). Only the include's keyword lies between its statement's start and the
    /// name, so no other statement starts between them (the include statement itself sorts
    /// before its file's statements: nothing asks about it).
    included_at: Vec<Option<Span>>,
}

impl ReadingOrder {
    /// The order of files read through `included_at` (per file id, as [`ReadingOrder`] keeps).
    pub fn new(included_at: Vec<Option<Span>>) -> ReadingOrder {
        ReadingOrder { included_at }
    }

    /// Whether the compile reads `a`'s start before `b`'s.
    pub fn before(&self, a: Span, b: Span) -> bool {
        if a.file == b.file {
            return a.start < b.start;
        }
        self.key(a) < self.key(b)
    }

    /// The span of the include that read `file` (`None` for the root and `--define`s).
    pub fn included_at(&self, file: super::FileId) -> Option<Span> {
        self.included_at.get(file.0 as usize).copied().flatten()
    }

    /// How many includes lie between the root and `file` (0 for the root).
    pub fn depth(&self, file: super::FileId) -> usize {
        let mut file = file;
        let mut depth = 0;
        // Bounded as `key`'s walk is.
        for _ in 0..self.included_at.len() {
            match self.included_at(file) {
                Some(at) => {
                    depth += 1;
                    file = at.file;
                }
                None => break,
            }
        }
        depth
    }

    /// `file` read by the include whose file name is at `at` (an include added: the
    /// incremental compile reads the file it names as the last one).
    pub fn set(&mut self, file: super::FileId, at: Span) {
        let i = file.0 as usize;
        if self.included_at.len() <= i {
            self.included_at.resize(i + 1, None);
        }
        self.included_at[i] = Some(at);
    }

    /// Forgets the files from the `len`th on (an include removed that read the last file).
    pub fn truncate(&mut self, len: usize) {
        self.included_at.truncate(len);
    }

    /// Forgets which include read `file` (an include removed that read a file before others:
    /// its id goes when the check of the removal is done, [`ReadingOrder::renumber`]).
    pub fn forget(&mut self, file: super::FileId) {
        if let Some(at) = self.included_at.get_mut(file.0 as usize) {
            *at = None;
        }
    }

    /// The file ids renumbered: a file inserted gets an entry (none: the caller sets it), a
    /// file removed loses its own, and every include's span names its file by the new id;
    /// `false` when the table has no such place or an include lies in the file removed.
    pub fn renumber(&mut self, renumber: &Renumber) -> bool {
        match *renumber {
            Renumber::Inserted(at) if at.0 as usize <= self.included_at.len() => {
                self.included_at.insert(at.0 as usize, None);
            }
            Renumber::Removed(at) if (at.0 as usize) < self.included_at.len() => {
                self.included_at.remove(at.0 as usize);
            }
            _ => return false,
        }
        let mut ok = true;
        for span in self.included_at.iter_mut().flatten() {
            ok &= renumber.apply(span);
        }
        ok
    }

    /// Whether any file was included (else byte offsets of file 0 order everything).
    pub fn has_includes(&self) -> bool {
        self.included_at.iter().any(Option::is_some)
    }

    /// Moves the include statements' spans by `shift`; `false` when one reaches into the
    /// edited bytes (an edit of an include, which the caller declines anyway).
    pub fn shift(&mut self, shift: &Shift) -> bool {
        let mut ok = true;
        for span in self.included_at.iter_mut().flatten() {
            ok &= shift.apply(span);
        }
        ok
    }

    /// The span's place as (top file, then per level from the top: offset and whether it is
    /// the span's own file, 1, or a file included there, 0).
    fn key(&self, s: Span) -> (u32, Vec<(u32, u8)>) {
        let mut levels = vec![(s.start, 1)];
        let mut file = s.file;
        // An include chain is at most `MAX_INCLUDE_DEPTH` long and has no cycle; the bound
        // keeps a malformed table from looping.
        for _ in 0..self.included_at.len() {
            match self.included_at.get(file.0 as usize).copied().flatten() {
                Some(at) => {
                    levels.push((at.start, 0));
                    file = at.file;
                }
                None => break,
            }
        }
        levels.reverse();
        (file.0, levels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::FileId;

    #[test]
    fn an_included_file_is_read_where_its_include_stands() {
        // File 1 included from file 0 (`include` at 20, its name at 28..40); file 2 from file 1
        // (at 10, name 18..30); file 3 a define.
        let order = ReadingOrder::new(vec![
            None,
            Some(Span::new(FileId(0), 28, 40)),
            Some(Span::new(FileId(1), 18, 30)),
            None,
        ]);
        let at = |f: u32, s: usize| Span::new(FileId(f), s, s + 1);
        assert!(order.before(at(0, 7), at(1, 0)));
        assert!(
            order.before(at(1, 50), at(0, 41)),
            "before what follows the include"
        );
        assert!(order.before(at(0, 20), at(0, 41)));
        assert!(order.before(at(2, 90), at(1, 31)));
        assert!(order.before(at(1, 5), at(2, 0)));
        assert!(!order.before(at(0, 45), at(2, 0)));
        assert!(
            order.before(at(0, 900), at(3, 0)),
            "a define after everything"
        );
        assert!(order.has_includes());
        assert_eq!((order.depth(FileId(0)), order.depth(FileId(2))), (0, 2));
        assert_eq!(
            order.included_at(FileId(1)),
            Some(Span::new(FileId(0), 28, 40))
        );
        let mut fewer = order.clone();
        fewer.truncate(2);
        fewer.set(FileId(2), Span::new(FileId(1), 18, 30));
        let three = ReadingOrder::new(order.included_at[..3].to_vec());
        assert_eq!(fewer, three, "file 3 (the define) gone, file 2 read again");
        assert!(!ReadingOrder::default().has_includes());
    }
}
