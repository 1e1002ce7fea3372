//! Stage 2, check, incrementally: one `material`, `mesh` or `texture` declaration added
//! (`material spare = phong { diffuse #888 }` typed on a new line; what names it checked
//! again) or removed (the line of one nothing names deleted), checked alone and spliced into
//! the [`CheckMemo`].
//!
//! Why the result is the full check's: nothing names a removed declaration (the whole-word
//! search of the new text through [`Dependents`] finds none), so no other statement checks
//! differently. What names an added one (it named an unknown one until now: an object whose
//! material is typed before the material is) is checked again once it is in, and so is every
//! statement with an unknown-name diagnostic of its namespace, whose did-you-mean lists the
//! namespace's names ([`CheckMemo::recheck_unknown_names`], 2026-11-26 fifth session; one of
//! another kind lists other names); a `group` naming an added one declines (its uses under
//! the name it did not resolve are not known one by one), and so does an area light (a
//! setting) among them. What
//! changes is its table: a declaration's table index is its place among those of its kind in
//! statement order, so the added one is put at its place and every table index after it (in
//! statement records, use counts, index maps, texture lists, dropped declarations) moves up by
//! one, or down by one after a removed one. An added declaration is lowered as the check lowers
//! it (its diagnostics, in its own text, join those before the placement phase); then the IR is
//! compacted again ([`super::compact`]): the new one is unused, so it is left out with a
//! warning, and a removed one's warning goes.

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::names::Namespace;
use super::super::StmtRecord;
use super::compact::Relowered;
use super::redo::redo;
use super::{CheckMemo, Dependents, Rechecked};
use crate::source::{Shift, SourceMap};
use crate::syntax::{Decl, DeclKind, Stmt};

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
    /// old text) by `new` when one of the two is empty and the other is one `material`, `mesh`
    /// or `texture` declaration that nothing else names; every other span moves by `shift`, and
    /// `sources` holds the new text. The number of statements checked again, or `None` when the
    /// result could differ from a full check's (the memo is then spoiled).
    pub fn add_or_remove_decl(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
        dependents: &mut Dependents,
    ) -> Option<usize> {
        let (added, d) = match (old_stmts, new) {
            ([], [Stmt::Decl(d)]) => (true, d),
            ([Stmt::Decl(d)], []) => (false, d),
            _ => return None,
        };
        let ns = namespace(d)?;
        if old.len() != old_stmts.len() {
            return None;
        }
        let named = dependents(&d.name.name)?;
        let table = &mut self.tables[ns as usize];
        // What names an added one (it had an unknown name): checked again once it is in.
        let mut naming = BTreeMap::new();
        if added {
            naming.extend(named.into_iter().filter(|(i, _)| *i != old.start));
            // A group's uses under the name it did not resolve are not known one by one.
            let group = naming.values().any(|s| matches!(s, Stmt::Group(_)));
            if group || table.get(&d.name.name).is_some() {
                return None;
            }
        } else {
            // Out of the memo before the spans move (its own lie in the edited bytes).
            let at = table.get(&d.name.name)?;
            if table.spans.get(at) != Some(&d.name.span) || !named.is_empty() {
                return None;
            }
            table.remove_at(at);
            self.drop_early(&[d.span]);
            // Its unused-declaration warning (the re-compaction below gives the others again).
            let end = self.diagnostics.len();
            let finish = self
                .diagnostics
                .split_off(end.checked_sub(self.finish_diags)?);
            let (own, kept): (Vec<_>, Vec<_>) = finish.into_iter().partition(|e| {
                let at = e.primary.as_ref().map(|l| l.span);
                at.is_some_and(|s| {
                    s.file == d.span.file && (d.span.start..d.span.end).contains(&s.start)
                })
            });
            (own.len() <= 1).then_some(())?;
            self.finish_diags = kept.len();
            self.diagnostics.extend(kept);
            self.renumber(ns, at, false)?;
        }
        let records = vec![StmtRecord::default(); new.len()];
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records,
        };
        let own = added.then_some(old.start);
        if !self.splice(0..0, 0..0, old, nothing, shift) {
            return None;
        }
        let mut relowered = Relowered::default();
        if added {
            // Its place among its kind, in statement order.
            let (table, order) = (&mut self.tables[ns as usize], &self.order);
            let at = table
                .spans
                .partition_point(|s| order.before(*s, d.name.span));
            table.insert_at(at, &d.name.name, d.name.span);
            self.renumber(ns, at, true)?;
            self.lower_added(sources, ns, at, d, &mut relowered)?;
        }
        self.recompact(sources, relowered)?;
        let rechecked = self.recheck_unknown_names(sources, ns, naming, own, dependents)?;
        Some(new.len() + rechecked)
    }

    /// After a declaration of `ns` was added or removed (every span already the new text's):
    /// the statements `naming` (they name an added one) and those with an unknown-name
    /// diagnostic of `ns` (its did-you-mean lists `ns`'s names, which changed; found as a
    /// rename finds them, [`CheckMemo::rename_dependents`]), but the statement `own`, checked
    /// again in place ([`super::redo`], [`CheckMemo::splice_decls`]). How many, or `None`
    /// when one of them is a setting (an area light naming an unknown mesh) or the re-check
    /// declines.
    fn recheck_unknown_names(
        &mut self,
        sources: &SourceMap,
        ns: Namespace,
        mut naming: BTreeMap<usize, Stmt>,
        own: Option<usize>,
        dependents: &mut Dependents,
    ) -> Option<usize> {
        let unmoved = Shift {
            file: crate::source::FileId(0),
            start: u32::MAX,
            old_end: u32::MAX,
            new_end: u32::MAX,
        };
        naming.extend(self.rename_dependents(sources, ns, &[], &unmoved, dependents)?);
        if let Some(own) = own {
            naming.remove(&own);
        }
        if naming.is_empty() {
            return Some(0);
        }
        let was_used = (self.used_meshes(), self.used_materials());
        let mut cx = self.lend(sources);
        let (records, textures) = (&self.records, &self.material_textures);
        let redone = redo(&mut cx, naming, records, textures, false, dependents, None);
        self.take_back(&mut cx);
        let redone = redone?;
        if !redone.settings.is_empty() {
            return None;
        }
        self.normal_maps_unchanged(&redone.relowered.textures, dependents)?;
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        self.splice_decls(sources, redone, &unmoved, used_changed)
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

    /// Every table index of `ns` from `at` on moved up by one (a declaration `added` at `at`),
    /// or every one after `at` down by one (the one at `at` removed).
    fn renumber(&mut self, ns: Namespace, at: usize, added: bool) -> Option<()> {
        let moved = |i: u32| -> u32 {
            match (added, i as usize >= at) {
                (true, true) => i + 1,
                (false, true) => i - 1,
                _ => i,
            }
        };
        let (map, uses, used_before) = match ns {
            Namespace::Material => (
                &mut self.material_map,
                Some(&mut self.material_uses),
                Some(&mut self.used_before.used_materials),
            ),
            Namespace::Mesh => (
                &mut self.mesh_map,
                Some(&mut self.mesh_uses),
                Some(&mut self.used_before.used_meshes),
            ),
            _ => (&mut self.texture_map, None, None),
        };
        if added {
            (at <= map.len()).then_some(())?;
            map.insert(at, None);
            if let Some(uses) = uses {
                (at <= uses.len()).then(|| uses.insert(at, 0))?;
            }
            if let Some(used) = used_before.filter(|u| at <= u.len()) {
                used.insert(at, false);
            }
        } else {
            // Nothing names a removed declaration: it is neither in the IR nor used.
            map.get(at)?.is_none().then_some(())?;
            map.remove(at);
            if let Some(uses) = uses {
                (uses.get(at)? == &0).then(|| uses.remove(at))?;
            }
            if let Some(used) = used_before.filter(|u| at < u.len()) {
                used.remove(at);
            }
        }
        let dropped = &mut self.dropped;
        let key = at as u32;
        match ns {
            Namespace::Material => {
                if !added {
                    dropped.materials.retain(|(i, _)| *i != key);
                    self.material_textures.retain(|(m, _)| *m != key);
                }
                for r in &mut self.records {
                    r.material = r.material.map(moved);
                }
                for (i, _) in &mut dropped.materials {
                    *i = moved(*i);
                }
                for (_, _, m) in &mut dropped.unresolved {
                    *m = moved(*m);
                }
                for (m, _) in &mut self.material_textures {
                    *m = moved(*m);
                }
            }
            Namespace::Mesh => {
                if !added {
                    dropped.meshes.retain(|(i, _)| *i != key);
                }
                for r in &mut self.records {
                    r.mesh = r.mesh.map(moved);
                }
                for (i, _) in &mut dropped.meshes {
                    *i = moved(*i);
                }
                for (_, m, _) in &mut dropped.unresolved {
                    *m = moved(*m);
                }
            }
            _ => {
                if !added {
                    dropped.textures.retain(|(i, _)| *i != key);
                }
                for (i, _) in &mut dropped.textures {
                    *i = moved(*i);
                }
                for (_, textures) in &mut self.material_textures {
                    for t in textures {
                        *t = moved(*t as u32) as usize;
                    }
                }
            }
        }
        Some(())
    }
}
