//! Stage 2, check, incrementally: the IR's declarations compacted again after an edit that
//! changes which materials, meshes and textures the IR holds — one that makes a declaration
//! used or unused, adds or removes one, or makes its lowering fail or succeed (an error in a
//! material) — without checking any statement again.
//!
//! The check's last pass (`finish`, in `names.rs`) drops what nothing uses, with a warning
//! each, and numbers what is left: the IR's indices are table indices compacted. The memo
//! keeps what that pass dropped ([`Dropped`], by table index) and the spans of its warnings
//! (the last diagnostics). To compact again, the IR is first laid out by table index once more
//! ("unfinished"): its declarations go back to their table places, their references (a
//! material's textures, an object's mesh and material, an area light's mesh) back to table
//! indices, through the inverse of the maps that compacted them; a top-level `object`'s mesh
//! and material come from its statement record (exact even where the IR's index was a
//! placeholder, for a declaration that failed to lower; an object in a `group` that names one
//! is found in [`Dropped::unresolved`]). Then the same `finish` runs again on
//! that, with the memo's use counts: the same warnings, in the same order, and the same
//! compaction as a full check. It costs one pass over the objects (two index look-ups each:
//! about a millisecond for 100,000) and over the declarations, and clones nothing but the
//! render settings.
//!
//! A material's textures come back from its list of textures (table indices, in the order of
//! its inputs), exact also where one failed to lower; an `obj` mesh's material overrides from
//! the list `finish` keeps of them (2026-11-26, sixth session: they declined before, since a
//! failed material is remapped to a placeholder 0). `finish` marks the materials a used
//! mesh's overrides name as used, so a re-compaction gives their used-ness too; the memo's
//! own used-ness does not count them, which only sends more edits to a re-compaction.

use std::sync::Arc;

use super::super::names::{remap_textures, texture_inputs, Namespace};
use super::CheckMemo;
use crate::ir;
use crate::source::{MoveSpans, SourceMap, Span};

/// The lowered declarations the IR leaves out (nothing uses them), by table index, ascending.
#[derive(Debug, Default)]
pub struct Dropped {
    pub(in crate::check) textures: Vec<(u32, ir::Texture)>,
    pub(in crate::check) materials: Vec<(u32, ir::Material)>,
    pub(in crate::check) meshes: Vec<(u32, ir::Mesh)>,
    /// The objects whose mesh or material failed to lower (the IR has 0 in its place): each
    /// one's span and the mesh and material it names (table indices).
    pub(in crate::check) unresolved: Vec<(Span, u32, u32)>,
}

impl Dropped {
    /// Moves every span by `shift`; `false` when one reaches into the edited bytes.
    pub(super) fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        let mut ok = true;
        for (_, t) in &mut self.textures {
            ok &= t.shift_spans(shift);
        }
        for (_, m) in &mut self.materials {
            ok &= m.shift_spans(shift);
        }
        for (_, m) in &mut self.meshes {
            ok &= m.shift_spans(shift);
        }
        // One in the edited bytes is a top-level object's, checked again (its record tells
        // its names); a group is never checked again alone.
        self.unresolved.retain_mut(|(span, _, _)| shift.apply(span));
        ok
    }
}

/// Declarations lowered again by a re-check: table index and IR (`None`: it failed to lower).
#[derive(Default)]
pub(super) struct Relowered {
    pub textures: Vec<(usize, Option<ir::Texture>)>,
    pub materials: Vec<(usize, Option<ir::Material>)>,
    pub meshes: Vec<(usize, Option<ir::Mesh>)>,
    /// The area lights' own quads, all of them, when the settings lowered again have another
    /// number of them than the IR holds ([`super::settings`]).
    pub quads: Option<Vec<ir::Mesh>>,
}

/// Puts `item` at table index `i` of the sparse, ascending list `list` (`None`: takes it out).
fn put<T>(list: &mut Vec<(u32, T)>, i: usize, item: Option<T>) {
    let i = i as u32;
    match (list.binary_search_by_key(&i, |(k, _)| *k), item) {
        (Ok(at), Some(item)) => list[at].1 = item,
        (Ok(at), None) => {
            list.remove(at);
        }
        (Err(at), Some(item)) => list.insert(at, (i, item)),
        (Err(_), None) => {}
    }
}

/// Table → IR index map inverted: IR index → table index.
fn inverse(map: &[Option<u32>], len: usize) -> Vec<Option<u32>> {
    let mut inv = vec![None; len];
    for (i, k) in map.iter().enumerate() {
        if let Some(slot) = k.and_then(|k| inv.get_mut(k as usize)) {
            *slot = Some(i as u32);
        }
    }
    inv
}

/// The list `ir` (IR order) and the dropped `dropped` laid out by table index (`len` places),
/// each IR entry passed through `untie` (its references back to table indices).
fn by_table<T>(
    ir: Vec<T>,
    inv: &[Option<u32>],
    dropped: Vec<(u32, T)>,
    len: usize,
    mut untie: impl FnMut(u32, &mut T) -> Option<()>,
) -> Option<Vec<Option<T>>> {
    let mut all: Vec<Option<T>> = std::iter::repeat_with(|| None).take(len).collect();
    for (k, mut item) in ir.into_iter().enumerate() {
        let i = inv.get(k).copied().flatten()?;
        untie(i, &mut item)?;
        *all.get_mut(i as usize)? = Some(item);
    }
    for (i, item) in dropped {
        *all.get_mut(i as usize)? = Some(item);
    }
    Some(all)
}

impl CheckMemo {
    /// Puts declarations lowered again where they belong when that changes no IR index: in the
    /// IR (remapped) when it holds them and still should, among the dropped ones when it does
    /// not and still should not. `false` (nothing put) when one of them must come into or go out
    /// of the IR: [`CheckMemo::recompact`] then.
    pub(super) fn put_in_place(&mut self, r: &mut Relowered) -> bool {
        let (used_materials, used_meshes) = (self.used_materials(), self.used_meshes());
        let used_textures = self.used_textures(&used_materials);
        let stays = |map: &[Option<u32>], used: &[bool], i: usize, lowered: bool| {
            let in_ir = map.get(i).copied().flatten().is_some();
            // Meshes past the table (an area light's) are always kept.
            let used = used.get(i).copied().unwrap_or(true);
            in_ir == (lowered && used)
        };
        // A mesh the IR holds with material overrides (before or after): they are IR indices
        // there, and may make materials used or unused.
        let plain_meshes = r.meshes.iter().all(|(i, m)| {
            let in_ir = self.mesh_map.get(*i).copied().flatten().is_some();
            let key = *i as u32;
            let had = (self.mesh_overrides.binary_search_by_key(&key, |(k, _)| *k)).is_ok();
            let has = m
                .as_ref()
                .is_some_and(|m| !m.obj_options().materials.is_empty());
            !in_ir || (!had && !has)
        });
        let fits = plain_meshes
            && r.textures
                .iter()
                .all(|(i, t)| stays(&self.texture_map, &used_textures, *i, t.is_some()))
            && r.materials
                .iter()
                .all(|(i, m)| stays(&self.material_map, &used_materials, *i, m.is_some()))
            && r.meshes
                .iter()
                .all(|(i, m)| stays(&self.mesh_map, &used_meshes, *i, m.is_some()));
        let Some(scene) = self.scene.as_mut().filter(|_| fits) else {
            return false;
        };
        let scene = Arc::make_mut(scene);
        let at = |map: &[Option<u32>], i: usize| map.get(i).copied().flatten();
        for (i, t) in std::mem::take(&mut r.textures) {
            match (at(&self.texture_map, i), t) {
                (Some(k), Some(t)) => scene.textures[k as usize] = t,
                (_, t) => put(&mut self.dropped.textures, i, t),
            }
        }
        for (i, m) in std::mem::take(&mut r.materials) {
            match (at(&self.material_map, i), m) {
                (Some(k), Some(mut m)) => {
                    remap_textures(&mut m, &self.texture_map);
                    scene.materials[k as usize] = m;
                }
                (_, m) => put(&mut self.dropped.materials, i, m),
            }
        }
        for (i, m) in std::mem::take(&mut r.meshes) {
            match (at(&self.mesh_map, i), m) {
                (Some(k), Some(m)) => scene.meshes[k as usize] = m,
                (_, m) => put(&mut self.dropped.meshes, i, m),
            }
        }
        true
    }

    /// Which textures are used: those a used material refers to.
    fn used_textures(&self, used_materials: &[bool]) -> Vec<bool> {
        let mut used = vec![false; self.texture_map.len()];
        for (m, textures) in &self.material_textures {
            if used_materials.get(*m as usize).copied().unwrap_or(false) {
                for &t in textures {
                    if let Some(u) = used.get_mut(t) {
                        *u = true;
                    }
                }
            }
        }
        used
    }

    /// Compacts the IR's declarations again, as the check's last pass would after the memo's
    /// statements were checked in full, with `relowered` put in their table places first: the
    /// IR, the index maps, the dropped declarations and the unused-declaration warnings. `None`
    /// when its indices cannot be inverted exactly (the memo is then spoiled).
    pub(super) fn recompact(&mut self, sources: &SourceMap, relowered: Relowered) -> Option<()> {
        let used_materials = self.used_materials();
        let used_meshes = self.used_meshes();
        let mut shared = self.scene.take()?;
        let scene = Arc::make_mut(&mut shared);
        let inv_texture = inverse(&self.texture_map, scene.textures.len());
        let inv_material = inverse(&self.material_map, scene.materials.len());
        let inv_mesh = inverse(&self.mesh_map, scene.meshes.len());
        let mut unresolved = std::mem::take(&mut self.dropped.unresolved);
        unresolved.sort_unstable_by_key(|(span, _, _)| (span.file, span.start, span.end));
        // The objects are remapped after `finish` (which is given none), in one pass: table
        // indices through the new maps (two passes over the 100,000 objects before, back to
        // table indices and then `finish`'s remap: 2026-11-26, seventh session).
        let mut objects = std::mem::take(&mut scene.objects);
        let back = |inv: &[Option<u32>], k: u32| inv.get(k as usize).copied().flatten();
        // An area light's mesh by table index, as the memo keeps it (exact where the IR's
        // was a placeholder for a mesh that failed to lower).
        let mut lights = std::mem::take(&mut scene.lights);
        if lights.len() != self.light_meshes.len() {
            return None;
        }
        for (l, &mesh) in lights.iter_mut().zip(&self.light_meshes) {
            if let ir::Light::Area(a) = l {
                a.mesh = mesh?;
            }
        }
        let dropped = std::mem::take(&mut self.dropped);
        let textures = std::mem::take(&mut scene.textures);
        let len = self.texture_map.len();
        let mut textures = by_table(textures, &inv_texture, dropped.textures, len, |_, _| {
            Some(())
        })?;
        let materials = std::mem::take(&mut scene.materials);
        let len = self.material_map.len();
        // A material's textures by table index, from its list (the IR has 0 in place of one
        // that failed to lower).
        // (One lowered again is replaced below: its list may be its new one already.)
        let listed = &self.material_textures;
        let redone = &relowered.materials;
        let untie = |i: u32, m: &mut ir::Material| {
            if redone.iter().any(|(k, _)| *k == i as usize) {
                return Some(());
            }
            let list = match listed.binary_search_by_key(&i, |(m, _)| *m) {
                Ok(at) => &listed[at].1[..],
                Err(_) => &[],
            };
            let mut each = list.iter();
            let mut exact = true;
            texture_inputs(m, |t| match each.next() {
                Some(&table) => *t = table as u32,
                None => exact = false,
            });
            (exact && each.next().is_none()).then_some(())
        };
        let mut materials = by_table(materials, &inv_material, dropped.materials, len, untie)?;
        let meshes = std::mem::take(&mut scene.meshes);
        let len = self.mesh_map.len();
        // An `obj` mesh's material overrides by table index, from the list `finish` kept (the
        // IR has 0 in place of one that failed to lower).
        let overrides = &self.mesh_overrides;
        let untie_mesh = |i: u32, m: &mut ir::Mesh| {
            let list = match overrides.binary_search_by_key(&i, |(k, _)| *k) {
                Ok(at) => &overrides[at].1[..],
                Err(_) => &[],
            };
            let mut each = list.iter();
            for o in m.obj.iter_mut().flat_map(|o| &mut o.materials) {
                o.material = *each.next()?;
            }
            each.next().is_none().then_some(())
        };
        let mut meshes = by_table(meshes, &inv_mesh, dropped.meshes, len, untie_mesh)?;
        for (i, t) in relowered.textures {
            *textures.get_mut(i)? = t;
        }
        for (i, m) in relowered.materials {
            *materials.get_mut(i)? = m;
        }
        for (i, m) in relowered.meshes {
            *meshes.get_mut(i)? = m;
        }
        // The area lights' own quads, when the settings were lowered again with another
        // number of them: past the declared meshes.
        if let Some(quads) = relowered.quads {
            meshes.truncate(self.tables[Namespace::Mesh as usize].len());
            meshes.extend(quads.into_iter().map(Some));
        }
        let render = scene.render.clone();
        let mut cx = self.lend(sources);
        cx.textures = textures;
        cx.materials = materials;
        cx.meshes = meshes;
        cx.lights = lights;
        cx.cameras = std::mem::take(&mut scene.cameras);
        cx.active_camera = scene.active_camera;
        cx.material_textures = std::mem::take(&mut self.material_textures);
        cx.used_materials = used_materials;
        cx.used_meshes = used_meshes;
        let finished = cx.finish(Some(render));
        self.take_back(&mut cx);
        self.material_textures = std::mem::take(&mut cx.material_textures);
        self.texture_map = std::mem::take(&mut cx.texture_map);
        self.material_map = std::mem::take(&mut cx.material_map);
        self.mesh_map = std::mem::take(&mut cx.mesh_map);
        self.mesh_overrides = std::mem::take(&mut cx.mesh_overrides);
        self.light_meshes = std::mem::take(&mut cx.light_meshes);
        self.dropped = std::mem::take(&mut cx.dropped);
        // `finish`'s remap of the objects, from their table indices: a top-level object's from
        // its statement record (exact where the IR's was a placeholder), one in a group's
        // from the objects `finish` noted or through the inverse maps.
        let (mesh_map, material_map) = (&self.mesh_map, &self.material_map);
        let mut placed = objects.iter_mut();
        for r in &self.records {
            for o in placed.by_ref().take(r.objects as usize) {
                let key = (o.span.file, o.span.start, o.span.end);
                let (mesh, material) = if r.object {
                    (r.mesh?, r.material?)
                } else if let Ok(at) =
                    unresolved.binary_search_by_key(&key, |(s, _, _)| (s.file, s.start, s.end))
                {
                    (unresolved[at].1, unresolved[at].2)
                } else {
                    (back(&inv_mesh, o.mesh)?, back(&inv_material, o.material)?)
                };
                let in_ir = mesh_map.get(mesh as usize).copied()?;
                let material_in_ir = material_map.get(material as usize).copied()?;
                if in_ir.is_none() || material_in_ir.is_none() {
                    // A declaration that failed to lower (an error): 0 stands in for it.
                    self.dropped.unresolved.push((o.span, mesh, material));
                }
                o.mesh = in_ir.unwrap_or(0);
                o.material = material_in_ir.unwrap_or(0);
            }
        }
        if placed.next().is_some() {
            return None;
        }
        let kept = self.diagnostics.len().checked_sub(self.finish_diags)?;
        self.diagnostics.truncate(kept);
        self.finish_diags = cx.diags.len();
        self.diagnostics.append(&mut cx.diags);
        *scene = finished?;
        scene.objects = objects;
        self.scene = Some(shared);
        Some(())
    }
}
