//! Stage 2, check, incrementally: what a declaration edit checked again ([`super::redo`]'s
//! [`Redone`]) put in place of the old in the [`CheckMemo`] — the declarations' own
//! diagnostics among those before the placement phase, each re-checked object's diagnostics
//! and IR objects in its run of the placement phase's statement order ([`merge_runs`]), the
//! re-lowered declarations in the IR (or the IR compacted again, [`super::compact`]) — every
//! other span moving by the edit.

use std::sync::Arc;

use super::compact::Relowered;
use super::decls::Redone;
use super::runs::{merge_runs, merge_runs_in_place};
use super::settings::Settings;
use super::CheckMemo;
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::{FileId, Shift, SourceMap, Span};

impl CheckMemo {
    /// of `spans` (a statement's diagnostics lie in its own text).
    pub(super) fn drop_early(&mut self, spans: &[Span]) {
        let inside = |d: &Diagnostic| {
            let at = d.primary.as_ref().map(|l| l.span);
            at.is_some_and(|at| {
                (spans.iter()).any(|s| s.file == at.file && (s.start..s.end).contains(&at.start))
            })
        };
        let early = self.used_before.diags.min(self.diagnostics.len());
        let mut kept: Vec<Diagnostic> = self.diagnostics.drain(..early).collect();
        kept.retain(|d| !inside(d));
        self.used_before.diags = kept.len();
        self.diagnostics.splice(0..0, kept);
    }

    /// Moves the spans of the name tables and constants by `shift`.
    pub(super) fn shift_names(&mut self, shift: &Shift) -> bool {
        let mut ok = true;
        for span in self.lets.spans_mut() {
            ok &= shift.apply(span);
        }
        for t in &mut self.tables {
            for span in &mut t.spans {
                ok &= shift.apply(span);
            }
        }
        ok
    }

    /// Puts what was checked again in place of the old, moving every other span by `shift`.
    pub(super) fn splice_decls(
        &mut self,
        sources: &SourceMap,
        redone: Redone,
        shift: &Shift,
        used_changed: bool,
        settings: Option<Settings>,
    ) -> Option<usize> {
        let Redone {
            objects,
            mut relowered,
            material_textures,
            early,
            early_spans,
            group_spans,
            checked,
            renamed,
            settings: _,
        } = redone;
        let mut ok = true;
        // The diagnostics before the placement phase, the placement phase's, and those after.
        let before = self.used_before.diags;
        let placed: usize = self.records.iter().map(|r| r.diags as usize).sum();
        if before + placed > self.diagnostics.len() {
            return None;
        }
        let mut tail = self.diagnostics.split_off(before + placed);
        if renamed.is_some() {
            // The last pass's own (an unused warning may be the renamed one's, in the edited
            // bytes): the re-compaction gives them again.
            tail.truncate(tail.len().checked_sub(self.finish_diags)?);
            self.finish_diags = 0;
        }
        for d in &mut tail {
            ok &= d.shift_spans(shift);
        }
        let diags = self.diagnostics.split_off(before);
        for d in &mut self.diagnostics {
            ok &= d.shift_spans(shift);
        }
        // The statements checked again that depend on a changed constant: their old
        // diagnostics, now moved, give way to the new ones.
        self.drop_early(&early_spans);
        self.used_before.diags += early.len();
        let mut early_diags = std::mem::take(&mut self.diagnostics);
        early_diags.extend(early);
        let textures_changed = !material_textures.is_empty();
        let new_diags = objects.iter().map(|(&i, (_, d, _))| (i, d.clone()));
        let mut diags = merge_runs(
            diags,
            &self.records,
            |r| r.diags,
            new_diags,
            |d| d.shift_spans(shift),
        )?;
        early_diags.append(&mut diags);
        early_diags.append(&mut tail);
        self.diagnostics = early_diags;
        for (m, textures) in material_textures {
            let list = &mut self.material_textures;
            match (
                list.binary_search_by_key(&m, |(k, _)| *k),
                textures.is_empty(),
            ) {
                (Ok(at), true) => {
                    list.remove(at);
                }
                (Ok(at), false) => list[at].1 = textures,
                (Err(at), false) => list.insert(at, (m, textures)),
                (Err(_), true) => {}
            }
        }
        // The renamed declaration's entries keep their old spans (in the edited bytes): the
        // re-compaction puts the one lowered again in their place.
        // (Before it is set aside: the IR's indices are the maps' until then.)
        self.blank_replaced(&relowered, shift.file);
        let aside = renamed.and_then(|(ns, at)| self.set_aside(ns, at));
        if let Some(scene) = &mut self.scene {
            let scene = std::sync::Arc::make_mut(scene);
            let mut objects_in_ir = std::mem::take(&mut scene.objects);
            ok &= scene.shift_spans(shift);
            let (material_map, mesh_map) = (&self.material_map, &self.mesh_map);
            let new_objects = objects.iter().map(|(&i, (_, _, objects))| {
                let mut objects = objects.clone();
                for o in &mut objects {
                    o.mesh = mesh_map
                        .get(o.mesh as usize)
                        .copied()
                        .flatten()
                        .unwrap_or(0);
                    let material = material_map.get(o.material as usize).copied();
                    o.material = material.flatten().unwrap_or(0);
                }
                (i, objects)
            });
            let filler = ir::Object {
                mesh: 0,
                material: 0,
                world_from_object: glam::DMat4::IDENTITY,
                span: Span::new(shift.file, 0, 0),
            };
            merge_runs_in_place(
                &mut objects_in_ir,
                &self.records,
                |r| r.objects,
                new_objects,
                |o| shift.apply(&mut o.span),
                filler,
            )?;
            scene.objects = objects_in_ir;
        }
        ok &= self.dropped.shift_spans(shift);
        if let Some(aside) = aside {
            self.put_back(aside);
        }
        // The groups' objects that name a declaration the IR does not hold, noted again.
        let inside = |s: &Span| {
            (group_spans.iter()).any(|g| g.file == s.file && (g.start..g.end).contains(&s.start))
        };
        self.dropped.unresolved.retain(|(s, _, _)| !inside(s));
        for (record, _, objects) in objects.values() {
            let unresolved = self.unresolved_in_groups(std::slice::from_ref(record), objects);
            self.dropped.unresolved.extend(unresolved);
        }
        for (i, (record, _, _)) in objects {
            *self.records.get_mut(i)? = record;
        }
        // The settings lowered again (they named something that changed), in place of theirs.
        let settings_changed = match settings {
            Some(s) => self.put_settings(s, &mut relowered)?,
            None => false,
        };
        // Declarations now used or unused, lowered or not, textures now used or not: the IR's
        // indices change.
        if used_changed
            || textures_changed
            || settings_changed
            || renamed.is_some()
            || !self.put_in_place(&mut relowered)
        {
            self.recompact(sources, relowered)?;
        }
        ok.then_some(checked)
    }
}

impl CheckMemo {
    /// The old IR entries (in the IR or among the dropped ones) of the declarations
    /// `relowered` replaces, their spans set to the file's start (`file`): an `obj` mesh's or
    /// an `image` texture's file name lies in the edited bytes, which no shift can move, and
    /// every one of them is replaced once the others have moved (`put_in_place`, or the
    /// re-compaction from `relowered`).
    fn blank_replaced(&mut self, r: &Relowered, file: FileId) {
        let blank = Span::new(file, 0, 0);
        let Some(scene) = self.scene.as_mut().map(Arc::make_mut) else {
            return;
        };
        let dropped = &mut self.dropped;
        for (i, _) in &r.textures {
            if let Some(t) = entry(
                &mut scene.textures,
                &self.texture_map,
                &mut dropped.textures,
                *i,
            ) {
                t.span = blank;
                if let ir::TextureSource::Image { file, .. } = &mut t.source {
                    file.span = blank;
                }
            }
        }
        for (i, _) in &r.meshes {
            if let Some(m) = entry(&mut scene.meshes, &self.mesh_map, &mut dropped.meshes, *i) {
                m.span = blank;
                if let ir::MeshSource::Obj(path) = &mut m.source {
                    path.span = blank;
                }
                for o in m.obj.iter_mut().flat_map(|o| &mut o.materials) {
                    o.span = blank;
                }
            }
        }
        for (i, _) in &r.materials {
            let list = &mut scene.materials;
            if let Some(m) = entry(list, &self.material_map, &mut dropped.materials, *i) {
                m.span = blank;
            }
        }
    }
}

/// Table entry `i`: in the IR's `list` (through `map`) or among the `dropped` ones.
fn entry<'a, T>(
    list: &'a mut [T],
    map: &[Option<u32>],
    dropped: &'a mut [(u32, T)],
    i: usize,
) -> Option<&'a mut T> {
    match map.get(i).copied().flatten() {
        Some(k) => list.get_mut(k as usize),
        None => dropped
            .iter_mut()
            .find(|(k, _)| *k as usize == i)
            .map(|(_, t)| t),
    }
}
