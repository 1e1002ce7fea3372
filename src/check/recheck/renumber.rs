//! Stage 2, check, incrementally: a declaration's table index is its place among those of its
//! kind in statement order, so when one is added or removed ([`super::added`]) every table
//! index after it, wherever the [`CheckMemo`] keeps one (statement records, use counts, index
//! maps, texture lists, material overrides, dropped declarations), moves up or down by one.

use super::super::names::Namespace;
use super::CheckMemo;

impl CheckMemo {
    /// Every table index of `ns` from `at` on moved up by one (a declaration `added` at `at`),
    /// or every one after `at` down by one (the one at `at` removed).
    pub(super) fn renumber(&mut self, ns: Namespace, at: usize, added: bool) -> Option<()> {
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
            // A removed declaration is out of the IR and unused by now: what named it had its
            // uses taken out first (`super::removed`).
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
                // Material overrides: the kept meshes' list, the dropped meshes' own (table
                // indices; nothing names a removed one).
                for m in (self.mesh_overrides.iter_mut()).flat_map(|(_, l)| l) {
                    *m = moved(*m);
                }
                let dropped_overrides = (dropped.meshes.iter_mut())
                    .flat_map(|(_, m)| m.obj.iter_mut().flat_map(|o| &mut o.materials));
                for o in dropped_overrides {
                    o.material = moved(o.material);
                }
            }
            Namespace::Mesh => {
                if !added {
                    dropped.meshes.retain(|(i, _)| *i != key);
                }
                for r in &mut self.records {
                    r.mesh = r.mesh.map(moved);
                }
                // An area light naming a removed mesh is lowered again (`super::settings`).
                for m in &mut self.light_meshes {
                    *m = m.filter(|&i| added || i as usize != at).map(moved);
                }
                for (i, _) in &mut dropped.meshes {
                    *i = moved(*i);
                }
                for (i, _) in &mut self.mesh_overrides {
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
