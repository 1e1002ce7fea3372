//! Stage 2, check, incrementally: an edit of top-level `group`s (and `object`s beside them)
//! that keeps its groups (renamed or not) — `group row { transform { translate (0, 2, 0) } ... }` →
//! `... (0, 3, 0) ...`, an object inside a group moved, given another material, added or
//! removed — checked again in place and spliced into the [`CheckMemo`] as
//! [`CheckMemo::recheck`] splices `object`s. An included file of `group`s and `object`s added or
//! removed with its include is such an edit too, its version header and include checked in no
//! phase (2026-11-29, eighteenth session).
//!
//! Why the result is the full check's: a group is checked in the placement phase, as an
//! `object` is, and writes its diagnostics, its objects (flattened into the IR's list, one run
//! per statement) and the uses of the meshes and materials its objects name; beside those it
//! declares its name and its nested groups' names in the group table (for the duplicate
//! check only: nothing names a group). So:
//! - each old group name must be the first of its name (the table's entry). When the old and
//!   the new statements declare as many, the table keeps its entries and their spans become
//!   the new statements'; a renamed one takes the new name at the same place when no group has
//!   it (and no name anywhere is declared twice: a rename could change which declaration is
//!   the first). When they declare more or fewer (a group added or removed, 2026-11-26 fifth
//!   session), the old names leave the table and the new ones enter it, each one no group has,
//!   while no name anywhere is declared twice ([`replace_groups`]). The new statements
//!   are checked against an empty group table, which then reports nothing (their names are
//!   distinct, being the firsts of theirs), as the full check reports nothing for them;
//! - the old statements' uses of meshes and materials come out: the old statements are
//!   checked again against the old text (the same names resolve the same way) to count them,
//!   their diagnostics and objects thrown away. A use count reaching or leaving zero
//!   compacts the IR again ([`super::compact`]);
//! - an object in a group that names a declaration the IR does not hold (it failed to lower,
//!   or is unused until now) gets a 0 in its place, as `finish` gives it, and the entry
//!   [`super::Dropped`] keeps for the re-compaction to find its names by (a top-level object's
//!   are in its statement record); the old statements' entries go.

use std::ops::Range;

use super::super::names::Namespace;
use super::super::StmtRecord;
use super::CheckMemo;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{GroupStmt, Item, Stmt};

/// The group names `stmts` declare, in the order the check declares them (a group, then the
/// groups nested in it, depth first).
pub(super) fn declared_groups(stmts: &[Stmt]) -> Vec<(&str, Span)> {
    fn walk<'a>(g: &'a GroupStmt, out: &mut Vec<(&'a str, Span)>) {
        out.push((&g.name.name, g.name.span));
        for item in &g.body.items {
            if let Item::Group(child) = item {
                walk(child, out);
            }
        }
    }
    let mut out = Vec::new();
    for s in stmts {
        if let Stmt::Group(g) = s {
            walk(g, &mut out);
        }
    }
    out
}

/// Whether `stmts` are all top-level placements (`object`s and `group`s), or statements the
/// check reads in no phase: an included file's version header and the include that reads it,
/// added or removed with its placements (`compile::Incremental`'s include edits).
pub(super) fn placements(stmts: &[Stmt]) -> bool {
    (stmts.iter()).all(|s| matches!(s, Stmt::Object(_) | Stmt::Group(_)) || super::inert(s))
}

impl CheckMemo {
    /// Replaces the check of the statements `old` (indices into the old list; `old_stmts`, as
    /// parsed from the old text, which `old_sources` holds) by that of `new`, all of them
    /// `object`s and `group`s that declare the same group names; every other span moves by
    /// `shift`, and `sources` holds the new text. The number of statements checked again, or
    /// `None` when the result could differ from a full check's (the memo is then spoiled).
    pub fn recheck_placements(
        &mut self,
        old_sources: &SourceMap,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
    ) -> Option<usize> {
        if old.len() != old_stmts.len() || !placements(old_stmts) || !placements(new) {
            return None;
        }
        // Later declarations of group names added, edited or removed (2026-11-29): the table
        // keeps its firsts; added ones are checked against it, for their duplicate-name errors.
        let later = self.later_groups(old_stmts, new, shift);
        let renamed = match later {
            Some(_) => Vec::new(),
            None => self.rename_groups(old_stmts, new)?,
        };
        // `old` lies inside the memo (`output_ranges` indexes it), and what the check reads in
        // no phase gave nothing.
        let old_records = self.records.get(old.clone())?;
        let nothing =
            |(s, r): (&Stmt, &StmtRecord)| !super::inert(s) || *r == StmtRecord::default();
        old_stmts
            .iter()
            .zip(old_records)
            .all(nothing)
            .then_some(())?;
        let (diag_range, object_range) = self.output_ranges(&old);
        let was_used = (self.used_meshes(), self.used_materials());
        self.forget_uses(old_sources, old_stmts)?;
        // The old statements' objects that named an unlowered declaration: their entries go.
        let old_spans: Vec<Span> = old_stmts.iter().map(Stmt::span).collect();
        let inside_old = |s: &Span| {
            (old_spans.iter()).any(|o| o.file == s.file && (o.start..o.end).contains(&s.start))
        };
        self.dropped.unresolved.retain(|(s, _, _)| !inside_old(s));
        let rechecked = self.check_placements(sources, new, later == Some(true));
        let unresolved = self.unresolved_in_groups(&rechecked.records, &rechecked.objects);
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        // The group table's spans: the renamed entries take the new statements' spans.
        let mut groups = std::mem::take(&mut self.tables[Namespace::Group as usize]);
        let mut ok = self.splice(diag_range, object_range, old, rechecked, shift);
        for (at, span) in groups.spans.iter_mut().enumerate() {
            match renamed.iter().find(|(k, _)| *k == at) {
                Some((_, new_span)) => *span = *new_span,
                None => ok &= shift.apply(span),
            }
        }
        self.tables[Namespace::Group as usize] = groups;
        self.dropped.unresolved.extend(unresolved);
        if !ok || (used_changed && self.recompact(sources, Default::default()).is_none()) {
            return None;
        }
        Some(new.len())
    }

    /// Whether `new` declares groups (they are checked against the table), when every group
    /// name `old` and `new` declare (nested ones too; added, edited or removed) is a later
    /// declaration of a name the table holds: its first read before it (in the edited
    /// file, before the edited bytes, so that the table's old offset orders it). Then the
    /// table stays as it is (the check declares a name at its first declaration only), and
    /// the groups' duplicate-name errors lie in their own output: an added one's made by
    /// checking it against the table, a removed one's cut out with it.
    fn later_groups(&self, old: &[Stmt], new: &[Stmt], shift: &Shift) -> Option<bool> {
        let (was, now) = (declared_groups(old), declared_groups(new));
        if was.is_empty() && now.is_empty() {
            return None;
        }
        let adding = !now.is_empty();
        let names = was.iter().chain(&now);
        let groups = &self.tables[Namespace::Group as usize];
        let later = |&(name, span): &(&str, Span)| {
            let first = groups.get(name).and_then(|at| groups.spans.get(at));
            first.is_some_and(|&first| {
                let unmoved = first.file != shift.file || first.start < shift.start;
                first != span && unmoved && self.order.before(first, span)
            })
        };
        names.into_iter().all(later).then_some(adding)
    }

    /// Puts the group names `new` declares in place of those `old` declares (as many, each old
    /// one the first of its name), in the group table: a renamed one at the same place (when
    /// no other group has its new name, and no name is declared twice anywhere, whose first
    /// declaration a rename could change). Each table place and the new span there.
    fn rename_groups(&mut self, old: &[Stmt], new: &[Stmt]) -> Option<Vec<(usize, Span)>> {
        let (was, now) = (declared_groups(old), declared_groups(new));
        let groups = &mut self.tables[Namespace::Group as usize];
        let first = |&(name, span): &(&str, Span)| {
            let at = groups.get(name)?;
            (groups.spans.get(at) == Some(&span)).then_some(at)
        };
        let places: Vec<usize> = was.iter().map(first).collect::<Option<_>>()?;
        let twice = |d: &crate::diag::Diagnostic| d.code == crate::diag::Code::CheckDuplicateName;
        if was.len() != now.len() {
            // Groups added or removed: the old names go, the new ones come.
            if self.diagnostics.iter().any(twice) {
                return None;
            }
            return replace_groups(groups, places, &now);
        }
        let renames = was.iter().zip(&now).any(|(a, b)| a.0 != b.0);
        if renames && self.diagnostics.iter().any(twice) {
            return None;
        }
        for (&at, ((old_name, _), &(name, span))) in places.iter().zip(was.iter().zip(&now)) {
            if *old_name != name {
                groups.get(name).is_none().then_some(())?;
                groups.remove_at(at);
                groups.insert_at(at, name, span);
            }
        }
        Some(places.into_iter().zip(now.iter().map(|n| n.1)).collect())
    }

    /// Takes out the uses of meshes and materials that `stmts` (placements of the old text,
    /// which `old_sources` holds) counted: they are checked again to count them.
    pub(super) fn forget_uses(&mut self, old_sources: &SourceMap, stmts: &[Stmt]) -> Option<()> {
        let before = (self.mesh_uses.clone(), self.material_uses.clone());
        let _ = self.check_objects(old_sources, stmts);
        let forget = |uses: &mut [u32], before: &[u32]| -> Option<()> {
            (uses.len() == before.len()).then_some(())?;
            for (u, &b) in uses.iter_mut().zip(before) {
                let counted = u.checked_sub(b)?;
                *u = b.checked_sub(counted)?;
            }
            Some(())
        };
        forget(&mut self.mesh_uses, &before.0)?;
        forget(&mut self.material_uses, &before.1)
    }

    /// The objects of `objects` (table indices; one run per statement of `records`) placed by
    /// a `group` that name a mesh or material the IR does not hold: span, mesh and material,
    /// as `finish` notes them.
    pub(super) fn unresolved_in_groups(
        &self,
        records: &[StmtRecord],
        objects: &[crate::ir::Object],
    ) -> Vec<(Span, u32, u32)> {
        let mut out = Vec::new();
        let mut placed = objects.iter();
        let missing =
            |map: &[Option<u32>], i: u32| map.get(i as usize).copied().flatten().is_none();
        for r in records {
            for o in placed.by_ref().take(r.objects as usize) {
                let unheld =
                    missing(&self.mesh_map, o.mesh) || missing(&self.material_map, o.material);
                if !r.object && unheld {
                    out.push((o.span, o.mesh, o.material));
                }
            }
        }
        out
    }
}

/// The group table with the names at `places` (the old statements', each the first of its
/// name, while no name anywhere is declared twice) taken out and the names `now` (the new
/// statements') declared, each one no group has (else it would be a duplicate, or make a
/// later one the first: a diagnostic added or removed). The table's order is not the full
/// check's (the new names come last), but nothing reads it: a group is found by its name (the
/// duplicate check, [`CheckMemo::rename_groups`]) and no message lists group names. Each new
/// name's place and span.
fn replace_groups(
    groups: &mut super::super::names::Table,
    mut places: Vec<usize>,
    now: &[(&str, Span)],
) -> Option<Vec<(usize, Span)>> {
    places.sort_unstable();
    for &at in places.iter().rev() {
        groups.remove_at(at);
    }
    let mut out = Vec::with_capacity(now.len());
    for &(name, span) in now {
        if groups.declare(name, span).is_some() {
            return None;
        }
        out.push((groups.len() - 1, span));
    }
    Some(out)
}
