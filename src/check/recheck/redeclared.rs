//! Stage 2, check, incrementally: an edit of a name declared twice, taken by the compile
//! (`compile::incremental`) before the other declaration edits, which decline while a
//! duplicate-name error stands. One `let`, `material`, `mesh` or `texture` statement that is
//! (or becomes) a second declaration of a name declared before it:
//! - its value edited (`material m = phong { diffuse #f00 }` after another `material m`,
//!   `... #0f0 }`): its name stays where it was;
//! - added alone after the first declaration of its name;
//! - removed alone (its duplicate-name error goes with it).
//!
//! Why the result is the full check's: the check registers a name when it meets its
//! declaration in statement order; a later one of the same name gets the duplicate-name
//! error ([`super::super::names::duplicate_name`], at its name, with the first's) and is
//! neither lowered nor evaluated, nor put in a table (a `let` is a duplicate only when the
//! first one evaluated: one that failed or has a reserved name leaves no constant, and the next
//! is evaluated, so the error itself is what tells the re-check that a statement was one). So
//! nothing else reads such a statement's body: editing it only moves spans; adding one (after
//! the first of its name, in a scene without includes, whose byte order is the reading order)
//! adds its error among the diagnostics before the placement phase; removing one takes its
//! error out. Every other span moves by the edit's [`Shift`].
//!
//! The first declaration of a duplicated name edited in its value is not this module's: it
//! is an ordinary declaration edit ([`super::decls`]), whose re-check of what names a changed
//! constant passes a second declaration over ([`super::redo`]; 2026-11-29).
//!
//! A `camera` or `light` declared twice is the settings path's ([`super::settings`]: the
//! tables made anew), a later `group` of a name [`super::groups`]' (2026-11-29).
//!
//! Still a full check: a second declaration
//! renamed, several statements at once, the first declaration of a duplicated name added,
//! removed or renamed.
//!
//! In a scene with includes (2026-11-29, fifteenth session; declined before): a second
//! declaration is taken as added only after the first of its name in the same file (bytes
//! order a file's statements as the reading order does); its error's place among the memo's
//! diagnostics need not be the reading order's, since the compile's result sorts them by file
//! and offset (`compile::reading_order`) and no other diagnostic lies at the new name.

use std::ops::Range;

use super::super::names::{duplicate_name, Namespace};
use super::super::StmtRecord;
use super::{CheckMemo, Rechecked};
use crate::diag::Code;
use crate::source::{Shift, Span};
use crate::syntax::{DeclKind, Ident, Stmt};

/// Which kind of declared name: a constant, or a table's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Declared {
    Let,
    Table(Namespace),
}

/// The name a `let`, `material`, `mesh` or `texture` statement declares, and its kind.
pub(super) fn declared(s: &Stmt) -> Option<(Declared, &Ident)> {
    match s {
        Stmt::Let { name, .. } => Some((Declared::Let, name)),
        Stmt::Decl(d) => {
            let ns = match d.kind {
                DeclKind::Material => Namespace::Material,
                DeclKind::Mesh => Namespace::Mesh,
                DeclKind::Texture => Namespace::Texture,
                DeclKind::Light => return None,
            };
            Some((Declared::Table(ns), &d.name))
        }
        _ => None,
    }
}

/// What an edit of a second declaration does.
enum Redeclared {
    /// Its value edited, its name where it was.
    Edited,
    /// Added: its duplicate-name error.
    Added(crate::diag::Diagnostic),
    /// Removed: the index of its duplicate-name error among the diagnostics.
    Removed(usize),
}

impl CheckMemo {
    /// Re-checks the edit of the statements `old` (list indices; `old_stmts` as parsed from the
    /// old text) into `new` when it is one of a second declaration ([`self`]'s module doc):
    /// `None` when it is not one (the memo untouched, for the other re-checks to try), else
    /// whether it could be spliced in (`Some(None)`: the memo is spoiled, a full check).
    pub fn recheck_redeclared(
        &mut self,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
    ) -> Option<Option<usize>> {
        let kind = self.redeclared(&old, old_stmts, new, shift)?;
        let (diag_range, diags, records) = match kind {
            Redeclared::Edited => {
                let records = self.records.get(old.clone())?.to_vec();
                (0..0, Vec::new(), records)
            }
            Redeclared::Added(d) => {
                let at = self.early_place(d.primary.as_ref()?.span, shift);
                (at..at, vec![d], vec![StmtRecord::default()])
            }
            Redeclared::Removed(at) => (at..at + 1, Vec::new(), Vec::new()),
        };
        let early = self.used_before.diags - diag_range.len() + diags.len();
        let rechecked = Rechecked {
            diags,
            objects: Vec::new(),
            records,
        };
        let ok = self.splice(diag_range, 0..0, old, rechecked, shift);
        self.used_before.diags = early;
        Some(ok.then_some(new.len()))
    }

    /// Which edit of a second declaration `old_stmts` → `new` is, if it is one the module
    /// takes; reads only.
    fn redeclared(
        &self,
        old: &Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
    ) -> Option<Redeclared> {
        if old.len() != old_stmts.len() {
            return None;
        }
        let plain = |r: &StmtRecord| *r == StmtRecord::default();
        if !self.records.get(old.clone())?.iter().all(plain) {
            return None;
        }
        match (old_stmts, new) {
            ([was], [now]) => {
                let (kind, name) = declared(was)?;
                let (kind_now, name_now) = declared(now)?;
                let mut moved = name.span;
                let same = kind == kind_now && name.name == name_now.name;
                if !same || !shift.apply(&mut moved) || moved != name_now.span {
                    return None;
                }
                self.duplicate_error(name.span)?;
                Some(Redeclared::Edited)
            }
            ([], [now]) => {
                let (kind, name) = declared(now)?;
                let (what, first) = match kind {
                    Declared::Let => ("constant", self.lets.get(&name.name)?.1),
                    Declared::Table(ns) => {
                        let table = &self.tables[ns as usize];
                        (ns.what(), *table.spans.get(table.get(&name.name)?)?)
                    }
                };
                let mut first_now = first;
                let moved = shift.apply(&mut first_now);
                let before = first_now.file == name.span.file && first_now.end <= name.span.start;
                if !moved || !before {
                    return None;
                }
                let error = duplicate_name(what, &name.name, name.span, first_now);
                Some(Redeclared::Added(error))
            }
            ([was], []) => {
                let (_, name) = declared(was)?;
                Some(Redeclared::Removed(self.duplicate_error(name.span)?))
            }
            _ => None,
        }
    }

    /// The index of the duplicate-name error at `name` (a declared name's span) among the
    /// diagnostics before the placement phase, if there is one: that declaration was not the
    /// first of its name, and the check read no more of it.
    fn duplicate_error(&self, name: Span) -> Option<usize> {
        let early = self.diagnostics.get(..self.used_before.diags)?;
        early.iter().position(|d| {
            d.code == Code::CheckDuplicateName && d.primary.as_ref().is_some_and(|l| l.span == name)
        })
    }

    /// Where a diagnostic at `span` (new text) goes among those before the placement phase
    /// (old text, moved by `shift`): before the first that starts after it (the compile's
    /// result is in reading order; the place keeps the memo's list in that order where it was).
    fn early_place(&self, span: Span, shift: &Shift) -> usize {
        let early = &self.diagnostics[..self.used_before.diags.min(self.diagnostics.len())];
        let after = |d: &crate::diag::Diagnostic| {
            d.primary.as_ref().is_some_and(|l| {
                let mut at = l.span;
                shift.apply(&mut at);
                (at.file.0, at.start) > (span.file.0, span.start)
            })
        };
        early.iter().position(after).unwrap_or(early.len())
    }
}
