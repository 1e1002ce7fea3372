//! Stage 2, check, incrementally: a `let` removed that other statements name (`let k = 2`
//! deleted or commented out while objects' transforms name `k`), or added (uncommented) while
//! they name it (2026-11-29, fifteenth session: a full check before). The constant leaves the table and what reads its name is checked
//! again in place: an object naming `k` now gets an "unknown name" error with a did-you-mean;
//! a `let` naming it now fails (poisoned, as the check leaves it), so what names that one
//! fails quietly ([`super::redo`] follows the chain through the constants whose value
//! changed). An added one is the second half of a rename: evaluated against the constants
//! before it (no diagnostic, a name not taken, reserved or poisoned), and what reads its name
//! (an unknown name until now) checked again.
//!
//! Why the result is the full check's: it is the first half of a `let` renamed
//! ([`super::let_renamed`], whose argument it shares): a constant's value is read by name only,
//! so the statements whose check the removal can change are those that name it (the whole-word
//! search of the new text through [`Dependents`]), those that name a constant whose value
//! changes in turn (followed by `redo`), and those whose diagnostic lists the constants (an
//! unknown name's did-you-mean, found by the name read at the diagnostic's label). Each `let`
//! among them is evaluated against the constants declared before it ([`Failing::Unknowns`]).
//! The removed statement's record (a `let`'s: no object, no use) leaves the records with its
//! own diagnostics before the re-check, and every other span moves by the edit; the re-check's
//! output is then spliced in with no further move. Declined (a full check) as the rename
//! declines: with a `--define`, while any name is declared twice, when the removed `let` is
//! not the one the table holds (it failed, or is a second declaration), and where the re-check
//! of the statements declines.

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::StmtRecord;
use super::let_renamed::evaluate_renamed;
use super::redo::redo;
use super::reevaluate::Failing;
use super::{CheckMemo, Dependents, Rechecked};
use crate::diag::Code;
use crate::source::{FileId, Shift, SourceMap};
use crate::syntax::{Expr, Ident, Stmt};

impl CheckMemo {
    /// Removes the `let` `old` (one statement; `old_stmts`, as parsed from the old text; `new`
    /// is empty) that other statements name, and checks again what reads its name; every other
    /// span moves by `shift`, and `sources` holds the new text. The number of statements
    /// checked again, or `None` when the result could differ from a full check's (the memo is
    /// then spoiled).
    pub(super) fn remove_named_let(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        let (
            [Stmt::Let {
                name: was,
                span: was_span,
                ..
            }],
            [],
        ) = (old_stmts, new)
        else {
            return None;
        };
        let twice = (self.diagnostics.iter()).any(|d| d.code == Code::CheckDuplicateName);
        let declared = self.lets.get(&was.name).map(|(_, at)| *at);
        if old.len() != 1 || !self.defines.is_empty() || twice || declared != Some(was.span) {
            return None;
        }
        // New list indices: the search is of the new text.
        let changed = self.reading(sources, &[&was.name], shift, dependents)?;
        // Its own diagnostics (none: it was evaluated), the constant and its record go; every
        // other span moves to the new text.
        self.drop_early(&[*was_span]);
        self.lets.remove(&was.name);
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records: Vec::new(),
        };
        if !self.splice(0..0, 0..0, old, nothing, shift) {
            return None;
        }
        self.redo_readers(sources, None, changed, dependents)
    }
    /// Adds the `let` `new` (one statement, at list index `old.start`; `old` is empty) that
    /// other statements name, and checks again what reads its name, as
    /// [`CheckMemo::remove_named_let`] does for one removed.
    pub(super) fn add_named_let(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        new: &[Stmt],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        let [Stmt::Let {
            name: now, value, ..
        }] = new
        else {
            return None;
        };
        let twice = (self.diagnostics.iter()).any(|d| d.code == Code::CheckDuplicateName);
        let reserved = matches!(now.name.as_str(), "true" | "false" | "frame");
        let taken =
            self.lets.contains_key(now.name.as_str()) || self.poisoned.contains(now.name.as_str());
        if !old.is_empty() || !self.defines.is_empty() || twice || reserved || taken {
            return None;
        }
        let own = old.start;
        let mut changed = self.reading(sources, &[&now.name], shift, dependents)?;
        changed.remove(&own);
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records: vec![StmtRecord::default()],
        };
        if !self.splice(0..0, 0..0, old, nothing, shift) {
            return None;
        }
        self.redo_readers(sources, Some((now, value)), changed, dependents)
    }

    /// The shared tail of [`CheckMemo::remove_named_let`] and [`CheckMemo::add_named_let`],
    /// once the `let`'s statement is spliced out or in: evaluates the added `let` (`added`, its
    /// name and value; counted among the statements checked), checks `changed` (what reads the
    /// name) again against the constants, and splices the result in.
    fn redo_readers(
        &mut self,
        sources: &SourceMap,
        added: Option<(&Ident, &Expr)>,
        changed: BTreeMap<usize, Stmt>,
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        let was_used = (self.used_meshes(), self.used_materials());
        let mut cx = self.lend(sources);
        let evaluated = match added {
            Some((name, value)) => evaluate_renamed(&mut cx, name, value),
            None => Some(()),
        };
        let redone = evaluated.and_then(|()| {
            let (records, textures) = (&self.records, &self.material_textures);
            redo(
                &mut cx,
                changed,
                records,
                textures,
                Failing::Unknowns,
                dependents,
                None,
                &[],
            )
        });
        self.take_back(&mut cx);
        let mut redone = redone?;
        redone.checked += usize::from(added.is_some());
        self.normal_maps_unchanged(&redone.relowered.textures, dependents)?;
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        let settings = self.settings_named(sources, &mut redone, false, dependents)?;
        self.splice_decls(sources, redone, &unmoved(), used_changed, settings)
    }
}

/// A shift that moves nothing (every span already the new text's).
fn unmoved() -> Shift {
    Shift {
        file: FileId(0),
        start: u32::MAX,
        old_end: u32::MAX,
        new_end: u32::MAX,
    }
}
