//! Stage 2, check, incrementally: `let` statements added or removed that nothing else names
//! (`let q = 3` typed on a new line, or a line of an unused constant deleted), or one such
//! `let` renamed (removed and added: nothing names the old name or the new one), checked in
//! place and spliced into the [`CheckMemo`] without a full check.
//!
//! Why the result is the full check's: the memo is of a check without an error (its warnings
//! move with the edit), so no message lists the constants (only errors do: an unknown name's
//! and an unused `--define`'s help) and no name is poisoned. A
//! constant nothing names changes nothing but the constant table: no other statement reads it
//! (the whole-word search of the new text through [`Dependents`] finds only its own `let`, else
//! the edit declines), and the table's order is not part of any result (the check sorts names
//! by span where it lists them). An added `let` is evaluated as the check would evaluate it:
//! against the constants declared before it (it may name no later one), with no diagnostic, a
//! name not yet declared, not reserved and not overridden by a `--define`; a removed one must
//! be the declaration the table holds (not a redeclaration). Its statement record is the
//! check's for a `let` (no diagnostic, no object, no use), and every other span moves by the
//! edit.

use std::ops::Range;

use super::super::StmtRecord;
use super::{CheckMemo, Dependents, Rechecked};
use crate::diag::Diagnostic;
use crate::source::{Shift, SourceMap};
use crate::syntax::Stmt;

impl CheckMemo {
    /// Replaces the statements `old` (indices into the old list; `old_stmts`, as parsed from the
    /// old text) by `new`, when one of the two is empty and the other holds only `let`s that no
    /// other statement names; every other span moves by `shift`, and `sources` holds the new
    /// text. The number of statements checked again, or `None` when the result could differ from
    /// a full check's: the memo is then spoiled, and the caller checks in full.
    pub fn add_or_remove_lets(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        // One that something names: what names it is checked again (`let_removed`).
        if let ([Stmt::Let { name, .. }], []) = (old_stmts, new) {
            if !dependents.naming(&name.name)?.is_empty() {
                return self.remove_named_let(sources, old, old_stmts, new, shift, dependents);
            }
        }
        // One added that something names (an uncommented line): the same, the other way.
        if let ([], [Stmt::Let { name, .. }]) = (old_stmts, new) {
            let named = dependents.naming(&name.name)?;
            if named.iter().any(|(i, _)| *i != old.start) {
                return self.add_named_let(sources, old, new, shift, dependents);
            }
        }
        let lets = |s: &[Stmt]| s.iter().all(|s| matches!(s, Stmt::Let { .. }));
        let one_side = old_stmts.is_empty() != new.is_empty();
        if !(one_side || renamed_let(old_stmts, new))
            || !lets(old_stmts)
            || !lets(new)
            || old.len() != old_stmts.len()
        {
            return None;
        }
        if self.diagnostics.iter().any(Diagnostic::is_error) || !self.poisoned.is_empty() {
            return None;
        }
        // Nothing in the new text names a removed constant; an added one only its own `let`.
        for (at, stmt) in (old.start..).zip(new) {
            let Stmt::Let { name, .. } = stmt else {
                return None;
            };
            let named = dependents.naming(&name.name)?;
            if !matches!(named.as_slice(), [(i, _)] if *i == at) {
                return None;
            }
        }
        for stmt in old_stmts {
            let Stmt::Let { name, .. } = stmt else {
                return None;
            };
            let declared = self.lets.get(&name.name).map(|(_, at)| *at);
            let overridden = self.defines.contains_key(name.name.as_str());
            if declared != Some(name.span)
                || overridden
                || !dependents.naming(&name.name)?.is_empty()
            {
                return None;
            }
        }
        // Out of the table before the spans move (a removed one's lies in the edited bytes).
        for stmt in old_stmts {
            if let Stmt::Let { name, .. } = stmt {
                self.lets.remove(&name.name);
            }
        }
        let records = vec![StmtRecord::default(); new.len()];
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records,
        };
        if !self.splice(0..0, 0..0, old, nothing, shift) {
            return None;
        }
        let mut cx = self.lend(sources);
        let added = new.iter().all(|stmt| {
            let Stmt::Let { name, value, .. } = stmt else {
                return false;
            };
            let reserved = matches!(name.name.as_str(), "true" | "false" | "frame");
            let taken = cx.lets.contains_key(name.name.as_str())
                || cx.defines.contains_key(name.name.as_str());
            if reserved || taken || !super::reevaluate::names_only_earlier(&cx, value, name.span) {
                return false;
            }
            match cx.eval(value) {
                Some(v) if cx.diags.is_empty() => {
                    cx.lets.insert(&name.name, v, name.span);
                    true
                }
                _ => false,
            }
        });
        self.take_back(&mut cx);
        added.then_some(new.len())
    }
}

/// Whether `old` → `new` is one `let` renamed (`let k = 2` → `let kk = 2`): the old constant
/// removed and the new one added, each as [`CheckMemo::add_or_remove_lets`] removes and adds
/// one that nothing names.
pub(super) fn renamed_let(old: &[Stmt], new: &[Stmt]) -> bool {
    matches!((old, new), ([Stmt::Let { name: a, .. }], [Stmt::Let { name: b, .. }]) if a.name != b.name)
}
