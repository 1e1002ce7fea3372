//! Stage 2, check, incrementally: a `let` renamed that other statements name (`let k = 2` →
//! `let kk = 2` while objects' transforms name `k`): the constant leaves the table under its
//! old name and enters it under the new one, and what reads either name is checked again in
//! place (2026-11-26, sixth session; until then a full check). An object naming `k` now gets
//! an "unknown name" error with a did-you-mean; one naming `kk` (an unknown name until now)
//! resolves. A `let` naming the old name now fails (poisoned, as the check leaves it), so what
//! names that one fails quietly: [`super::redo`] follows the chain through the constants whose
//! value changed.
//!
//! Why the result is the full check's: a constant's value is read by name only, so the
//! statements whose check the rename can change are those that name the old or the new name
//! (the whole-word search of the new text through [`Dependents`]; it may find more, never
//! fewer), those that name a constant whose value changes in turn (followed by `redo`), and
//! those whose diagnostic lists the constants: an unknown name's did-you-mean
//! (`check::unknown_name`, in an expression or a material's colour), found by the name read at
//! the diagnostic's label. Each `let` among them is evaluated as the check evaluates it, in
//! statement order, against the constants declared before it ([`Failing::Unknowns`]); every
//! other statement after them, against all. It declines with a `--define` (an unused one's
//! did-you-mean lists the constants), while any name is declared twice (a rename could change
//! which declaration is the first), when the old `let` failed (it is not in the table), when
//! the new name is reserved, taken or a constant that failed, when the renamed `let`'s value
//! names a constant declared after it or gives a diagnostic, and where the re-check of the
//! statements declines (a camera, light or render block that comes to have a diagnostic).
//! A rename that nothing else reads (the old name nowhere, the new one only in its own `let`)
//! is a `let` removed and one added ([`CheckMemo::add_or_remove_lets`]).

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::Checker;
use super::redo::redo;
use super::reevaluate::{names_only_earlier, Failing};
use super::{CheckMemo, Dependents};
use crate::diag::Code;
use crate::source::{Shift, SourceMap};
use crate::syntax::{Expr, Ident, Stmt};

impl CheckMemo {
    /// Replaces the `let` `old` (one statement; `old_stmts`, as parsed from the old text) by
    /// `new`, the same `let` under another name, and checks again what reads either name;
    /// every other span moves by `shift`, and `sources` holds the new text. The number of
    /// statements checked again, or `None` when the result could differ from a full check's
    /// (the memo is then spoiled).
    pub(super) fn rename_let(
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
            [Stmt::Let {
                name: now, value, ..
            }],
        ) = (old_stmts, new)
        else {
            return None;
        };
        let own = old.start;
        let unread = dependents.naming(&was.name)?.is_empty()
            && matches!(dependents.naming(&now.name)?.as_slice(), [(i, _)] if *i == own);
        if unread {
            return self.add_or_remove_lets(sources, old, old_stmts, new, shift, dependents);
        }
        let twice = (self.diagnostics.iter()).any(|d| d.code == Code::CheckDuplicateName);
        let reserved = matches!(now.name.as_str(), "true" | "false" | "frame");
        let declared = self.lets.get(&was.name).map(|(_, at)| *at);
        let taken =
            self.lets.contains_key(now.name.as_str()) || self.poisoned.contains(now.name.as_str());
        if old.len() != 1 || !self.defines.is_empty() || twice || reserved || taken {
            return None;
        }
        if declared != Some(was.span) {
            return None;
        }
        let mut changed = self.reading(sources, &[&was.name, &now.name], shift, dependents)?;
        changed.remove(&own);
        // The old statement's diagnostics go (none: it was evaluated), then the constant leaves
        // the table and the names move to the new text.
        self.drop_early(&[*was_span]);
        self.lets.remove(&was.name);
        if !self.shift_names(shift) {
            return None;
        }
        let was_used = (self.used_meshes(), self.used_materials());
        let mut cx = self.lend(sources);
        let redone = evaluate_renamed(&mut cx, now, value).and_then(|()| {
            let (records, textures) = (&self.records, &self.material_textures);
            let failing = Failing::Unknowns;
            redo(
                &mut cx,
                changed,
                records,
                textures,
                failing,
                dependents,
                None,
                &[],
            )
        });
        self.take_back(&mut cx);
        let mut redone = redone?;
        redone.checked += 1;
        self.normal_maps_unchanged(&redone.relowered.textures, dependents)?;
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        // An unused `--define`'s did-you-mean lists the constants, which changed.
        let defines = !self.defines.is_empty();
        let settings = self.settings_named(sources, &mut redone, defines, dependents)?;
        self.splice_decls(sources, redone, shift, used_changed, settings)
    }

    /// The statements of the new text (index → statement) that read one of `names` or have an
    /// unknown-name diagnostic (its label moved by `shift` into the new text, which `sources`
    /// holds; its did-you-mean lists the constants). `None` when one cannot be parsed alone or
    /// a label lies in the edited bytes.
    pub(super) fn reading(
        &self,
        sources: &SourceMap,
        names: &[&str],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<BTreeMap<usize, Stmt>> {
        let unknown = |code| code == Code::CheckUnknownName;
        self.naming_or_listing(sources, names, unknown, shift, dependents)
    }
}

/// The renamed `let` (its name `now`, its value `value`) evaluated into the constants lent to
/// `cx`: it names only constants declared before it and gives no diagnostic, else `None`.
pub(super) fn evaluate_renamed(cx: &mut Checker, now: &Ident, value: &Expr) -> Option<()> {
    if !names_only_earlier(cx, value, now.span) {
        return None;
    }
    let v = cx.eval(value)?;
    if !cx.diags.is_empty() {
        return None;
    }
    cx.lets.insert(&now.name, v, now.span);
    Some(())
}
