//! Stage 2, check, incrementally: `material`, `mesh` and `texture` declarations added
//! (`material spare = phong { diffuse #888 }` typed on a new line, or a block of them pasted:
//! 2026-11-26, sixth session; what names them checked again) or removed (the lines of ones
//! nothing names deleted), checked alone and spliced into the [`CheckMemo`].
//!
//! Why the result is the full check's: what names a removed declaration (the whole-word
//! search of the new text through [`Dependents`]) has its uses taken out before the tables
//! change and is checked again once they have (seventh session, [`super::removed`]). What names an added one (it named an unknown one until now: an object whose
//! material is typed before the material is) is checked again once it is in, and so is every
//! statement with an unknown-name diagnostic of its namespace, whose did-you-mean lists the
//! namespace's names ([`CheckMemo::recheck_unknown_names`], 2026-11-26 fifth session; one of
//! another kind lists other names). A `group` naming an added one (sixth session; it
//! declined before) has the uses its objects counted under the names that resolved taken out
//! before the tables change (it is checked against them, as [`super::groups`] takes an old
//! group's out), and its uses counted anew when it is checked again; an area light (a
//! setting) among them declines. What
//! changes is the tables: a declaration's table index is its place among those of its kind in
//! statement order, so each added one is put at its place (in statement order) and every table
//! index after it (in statement records, use counts, index maps, texture lists, material
//! overrides, dropped declarations) moves up by one, or down by one after a removed one
//! ([`super::renumber`]). The
//! added declarations are lowered as the check lowers them, once all are in the tables
//! (textures, then materials, then meshes; their diagnostics, in their own text, join those
//! before the placement phase); then the IR is compacted again ([`super::compact`]): a new one
//! is unused, so it is left out with a warning, and a removed one's warning goes. Declined: a
//! name declared already, or twice among the added ones.

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::names::Namespace;
use super::super::StmtRecord;
use super::compact::Relowered;
use super::redo::redo;
use super::reevaluate::Failing;
use super::{CheckMemo, Dependents, Rechecked};
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{Decl, DeclKind, Stmt};

/// The declarations among `stmts`, when each is a declaration or an `object` (pasted or
/// deleted with them: 2026-11-26, seventh session).
fn decls_among(stmts: &[Stmt]) -> Option<Vec<&Decl>> {
    let mut decls = Vec::new();
    for s in stmts {
        match s {
            Stmt::Decl(d) => decls.push(&**d),
            // A version header and an include: an included file added or removed with the
            // include that reads it (they are checked in no phase).
            Stmt::Object(_) | Stmt::Version { .. } | Stmt::Include { .. } => {}
            _ => return None,
        }
    }
    (!decls.is_empty()).then_some(decls)
}

/// The namespace of a declaration the re-check may add or remove.
fn namespace(d: &Decl) -> Option<Namespace> {
    match d.kind {
        DeclKind::Material => Some(Namespace::Material),
        DeclKind::Mesh => Some(Namespace::Mesh),
        DeclKind::Texture => Some(Namespace::Texture),
        DeclKind::Light => None,
    }
}

impl CheckMemo {
    /// Replaces the statements `old` (indices into the old list; `old_stmts`, as parsed from the
    /// old text) by `new` when one of the two is empty and the other is `material`, `mesh` or
    /// `texture` declarations: any number removed (what names them checked again), or added (a
    /// pasted block); every other span moves by `shift`, and `sources` holds the new text. The
    /// number of statements checked again, or `None` when the result could differ from a full
    /// check's (the memo is then spoiled).
    pub fn add_or_remove_decl(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        let (added, decls): (bool, Vec<&Decl>) = match (old_stmts, new) {
            ([], [_, ..]) => (true, decls_among(new)?),
            ([_, ..], []) => (false, decls_among(old_stmts)?),
            _ => return None,
        };
        let mut namespaces = Vec::new();
        for d in &decls {
            let ns = namespace(d)?;
            if !namespaces.contains(&ns) {
                namespaces.push(ns);
            }
        }
        if old.len() != old_stmts.len() {
            return None;
        }
        // The added declarations' indices (the `object`s pasted with them are checked again
        // once they are in, as what names them is).
        let own: Vec<usize> = (old.start..)
            .zip(new)
            .filter(|(_, s)| matches!(s, Stmt::Decl(_)))
            .map(|(i, _)| i)
            .collect();
        // What names an added one (it had an unknown name): checked again once it is in.
        let mut naming = BTreeMap::new();
        // The groups among them, whose uses are counted again.
        let mut fresh = Vec::new();
        if added {
            for d in &decls {
                let ns = namespace(d)?;
                let same = |e: &&&Decl| namespace(e) == Some(ns) && e.name.name == d.name.name;
                let twice = decls.iter().filter(same).count() > 1;
                if twice || self.tables[ns as usize].get(&d.name.name).is_some() {
                    return None;
                }
                let named = dependents.naming(&d.name.name)?;
                let named = named.into_iter().filter(|(_, s)| !super::inert(s));
                naming.extend(named.filter(|(i, _)| !own.contains(i)));
            }
            // A group naming an added one counted its objects' uses under the names that
            // resolved: those are taken out now (the tables are the old ones), and its uses
            // counted anew when it is checked again (`redo`'s `fresh`).
            fresh = self.forget_group_uses(sources, &naming)?;
            let pasted = (old.start..)
                .zip(new)
                .filter(|(i, s)| !own.contains(i) && !super::inert(s));
            naming.extend(pasted.map(|(i, s)| (i, s.clone())));
        } else {
            // `object`s removed with them: their uses and output go.
            self.forget_removed_objects(&old)?;
            // What names a removed one: checked again once they are out (src/check/recheck/
            // removed.rs), its uses taken out first.
            for d in &decls {
                let named = dependents.naming(&d.name.name)?;
                naming.extend(named.into_iter().filter(|(_, s)| !super::inert(s)));
            }
            if !naming.is_empty() {
                self.may_remove_named().then_some(())?;
                fresh = self.forget_group_uses(sources, &naming)?;
            }
            // Out of the memo before the spans move (their own lie in the edited bytes).
            for d in &decls {
                let ns = namespace(d)?;
                let at = self.tables[ns as usize].get(&d.name.name)?;
                if self.tables[ns as usize].spans.get(at) != Some(&d.name.span) {
                    return None;
                }
                self.release_removed(ns, at, &old, &naming)?;
                self.tables[ns as usize].remove_at(at);
                self.renumber(ns, at, false)?;
            }
            let spans: Vec<Span> = decls.iter().map(|d| d.span).collect();
            self.drop_early(&spans);
            // Their unused-declaration warnings (the re-compaction below gives the others
            // again).
            let end = self.diagnostics.len();
            let finish = self
                .diagnostics
                .split_off(end.checked_sub(self.finish_diags)?);
            let inside = |s: Span| {
                (spans.iter()).any(|d| s.file == d.file && (d.start..d.end).contains(&s.start))
            };
            let (own, kept): (Vec<_>, Vec<_>) = finish
                .into_iter()
                .partition(|e| e.primary.as_ref().is_some_and(|l| inside(l.span)));
            (own.len() <= decls.len()).then_some(())?;
            self.finish_diags = kept.len();
            self.diagnostics.extend(kept);
        }
        // Where the removed `object`s' diagnostics and IR objects are (after the declarations'
        // own diagnostics, out now).
        let outputs = match added {
            true => (0..0, 0..0),
            false => self.output_ranges(&old),
        };
        let records = (new.iter())
            .map(|s| StmtRecord {
                object: matches!(s, Stmt::Object(_)),
                ..StmtRecord::default()
            })
            .collect();
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records,
        };
        if !self.splice(outputs.0, outputs.1, old, nothing, shift) {
            return None;
        }
        let mut relowered = Relowered::default();
        if added {
            // Each at its place among its kind, in statement order.
            for d in &decls {
                let ns = namespace(d)?;
                let (table, order) = (&mut self.tables[ns as usize], &self.order);
                let at = table
                    .spans
                    .partition_point(|s| order.before(*s, d.name.span));
                table.insert_at(at, &d.name.name, d.name.span);
                self.renumber(ns, at, true)?;
            }
            // Lowered as the check lowers them: textures, then materials, then meshes.
            for ns in [Namespace::Texture, Namespace::Material, Namespace::Mesh] {
                for d in decls.iter().filter(|d| namespace(d) == Some(ns)) {
                    let at = self.tables[ns as usize].get(&d.name.name)?;
                    self.lower_added(sources, ns, at, d, &mut relowered)?;
                }
            }
        }
        // Removed ones that something names: the objects naming them hold no index until
        // checked again, and the re-compaction comes after that. Pasted `object`s: they are
        // checked again anyway, so the IR is compacted once, after them, with the added
        // declarations' IR.
        let named_removed = !added && !naming.is_empty();
        let pasted_objects = added && own.len() < new.len();
        let compact = match named_removed || pasted_objects {
            true => Some(relowered),
            false => {
                self.recompact(sources, relowered)?;
                None
            }
        };
        let rechecked = self.recheck_unknown_names(
            sources,
            &namespaces,
            naming,
            &own,
            &fresh,
            dependents,
            compact,
        )?;
        Some(own.len() + rechecked)
    }

    /// After declarations of `namespaces` were added or removed (every span already the new
    /// text's): the statements `naming` (they name an added one; the `group`s among them at
    /// `fresh`, their uses taken out) and those with an unknown-name diagnostic of one of
    /// `namespaces` (its did-you-mean lists the names, which changed; found as a rename finds
    /// them, [`CheckMemo::rename_dependents`]), but the statements `own`, checked again in
    /// place ([`super::redo`], [`CheckMemo::splice_decls`]). How many, or `None` when one of
    /// them is a setting (an area light naming an unknown mesh) or the re-check declines.
    /// With `compact` the IR is compacted again whatever changed, with those declarations
    /// lowered (removed declarations that something named, [`super::removed`]; added ones
    /// pasted with `object`s).
    #[allow(clippy::too_many_arguments)] // the edit's parts, as the caller found them
    fn recheck_unknown_names(
        &mut self,
        sources: &SourceMap,
        namespaces: &[Namespace],
        mut naming: BTreeMap<usize, Stmt>,
        own: &[usize],
        fresh: &[usize],
        dependents: &mut dyn Dependents,
        compact: Option<Relowered>,
    ) -> Option<usize> {
        let unmoved = Shift {
            file: crate::source::FileId(0),
            start: u32::MAX,
            old_end: u32::MAX,
            new_end: u32::MAX,
        };
        for &ns in namespaces {
            naming.extend(self.rename_dependents(sources, ns, &[], &unmoved, dependents)?);
        }
        naming.retain(|i, _| !own.contains(i));
        if naming.is_empty() {
            return match compact {
                Some(relowered) => self.recompact(sources, relowered).map(|()| 0),
                None => Some(0),
            };
        }
        let was_used = (self.used_meshes(), self.used_materials());
        let mut cx = self.lend(sources);
        let (records, textures) = (&self.records, &self.material_textures);
        let failing = Failing::Declined;
        let redone = redo(
            &mut cx, naming, records, textures, failing, dependents, None, fresh,
        );
        self.take_back(&mut cx);
        let mut redone = redone?;
        self.normal_maps_unchanged(&redone.relowered.textures, dependents)?;
        let settings = self.settings_named(sources, &mut redone, false, dependents)?;
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        let force = compact.is_some();
        if let Some(r) = compact {
            let into = &mut redone.relowered;
            into.textures.extend(r.textures);
            into.materials.extend(r.materials);
            into.meshes.extend(r.meshes);
        }
        self.splice_decls(sources, redone, &unmoved, used_changed || force, settings)
    }

    /// Lowers the added declaration `d` (table index `at` of `ns`): its IR into `relowered`, its
    /// diagnostics among those before the placement phase.
    fn lower_added(
        &mut self,
        sources: &SourceMap,
        ns: Namespace,
        at: usize,
        d: &Decl,
        relowered: &mut Relowered,
    ) -> Option<()> {
        if ns == Namespace::Material && super::redo::names_a_normal_map(d) {
            return None;
        }
        let mut cx = self.lend(sources);
        match ns {
            Namespace::Material => {
                let (material, textures) = cx.material(d);
                if !textures.is_empty() {
                    let list = &mut self.material_textures;
                    let k = list.partition_point(|(m, _)| (*m as usize) < at);
                    list.insert(k, (at as u32, textures));
                }
                relowered.materials.push((at, material));
            }
            Namespace::Mesh => relowered.meshes.push((at, cx.mesh(d))),
            _ => relowered.textures.push((at, cx.texture(d))),
        }
        self.take_back(&mut cx);
        let inside = |l: &crate::diag::Label| {
            l.span.file == d.span.file && (d.span.start..d.span.end).contains(&l.span.start)
        };
        if !cx
            .diags
            .iter()
            .all(|e| e.primary.as_ref().is_some_and(inside))
        {
            return None;
        }
        let early = self.used_before.diags;
        let n = cx.diags.len();
        self.diagnostics.splice(early..early, cx.diags.drain(..));
        self.used_before.diags += n;
        Some(())
    }
}
