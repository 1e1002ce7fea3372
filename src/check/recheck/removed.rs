//! Stage 2, check, incrementally: a `material`, `mesh` or `texture` removed that something
//! names (`material m5 = …` deleted while 1,000 objects name `m5`; 2026-11-26, seventh
//! session: a full compile before), for [`CheckMemo::add_or_remove_decl`] to take out of the
//! memo before its table entry goes, so that what names it is checked again as what names a
//! renamed one is.
//!
//! Why the result is the full check's: what names the removed one (the whole-word search of
//! the new text) is checked again once it is out of the tables, with every statement that has
//! an unknown-name diagnostic of its kind (their did-you-means list the names, which changed):
//! they get an unknown name where they had the declaration. Before that, the memo must hold
//! nothing that reads the removed table index, since every index after it moves down by one:
//! - a top-level `object` naming it has that use taken out of the counts and its record's
//!   index cleared (its other use stays, for the re-check to take out as it takes an edited
//!   object's);
//! - a `group` naming it has every use its objects counted taken out, checked once more with
//!   the old tables (as an added declaration's group is), and counts anew when checked again;
//! - its IR entry leaves the IR (the later IR indices move down by one in the maps, the
//!   objects, the area lights, the material overrides and the materials' textures); the
//!   re-compaction that follows the re-check numbers everything again from the tables;
//! - a material's list of textures loses a removed texture (the material naming it is checked
//!   again and its list replaced if its new one differs).
//!
//! - a mesh an `area` light names (used before the placements) is named by that light's
//!   statement, which the search finds: the settings are lowered again (eighth session,
//!   [`super::settings`]), the light now with an unknown mesh, and their output replaced.
//!
//! Declined (a full compile): a name declared twice anywhere (which declaration is the first
//! could change), a mesh used before the placements that no light found names, a use count
//! left above zero once what names it is taken out (something the search did not find), and
//! what the re-check declines.

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::names::{texture_inputs, Namespace};
use super::CheckMemo;
use crate::diag::Code;
use crate::ir;
use crate::source::SourceMap;
use crate::syntax::{DeclKind, Stmt};

impl CheckMemo {
    /// The `object`s among the removed statements `old` (the rest declarations): their uses
    /// out of the counts (where their output is, [`CheckMemo::output_ranges`], is asked once
    /// the removed declarations' own diagnostics are out: they come before it).
    pub(super) fn forget_removed_objects(&mut self, old: &Range<usize>) -> Option<()> {
        let records = self.records.get(old.clone())?.to_vec();
        for r in records.iter().filter(|r| r.object) {
            for (uses, at) in [
                (&mut self.mesh_uses, r.mesh),
                (&mut self.material_uses, r.material),
            ] {
                if let Some(at) = at {
                    let n = uses.get_mut(at as usize)?;
                    *n = n.checked_sub(1)?;
                }
            }
        }
        Some(())
    }

    /// Whether declarations may be removed with what names them: no name declared twice.
    pub(super) fn may_remove_named(&self) -> bool {
        !(self.diagnostics.iter()).any(|d| d.code == Code::CheckDuplicateName)
    }

    /// The `group`s of `naming` (new list indices, new statements) have the uses their objects
    /// counted taken out, the tables still the old ones: their indices, for the re-check to
    /// count them anew ([`super::redo`]'s `fresh`).
    pub(super) fn forget_group_uses(
        &mut self,
        sources: &SourceMap,
        naming: &BTreeMap<usize, Stmt>,
    ) -> Option<Vec<usize>> {
        let groups: Vec<(usize, Stmt)> = (naming.iter())
            .filter(|(_, s)| matches!(s, Stmt::Group(_)))
            .map(|(i, s)| (*i, s.clone()))
            .collect();
        if !groups.is_empty() {
            let stmts: Vec<Stmt> = groups.iter().map(|(_, s)| s.clone()).collect();
            self.forget_uses(sources, &stmts)?;
        }
        Some(groups.into_iter().map(|(i, _)| i).collect())
    }

    /// Takes declaration `at` of `ns` (about to be removed: the statements `old` of the old
    /// list) out of what reads its table index: the top-level objects of `naming` (new list
    /// indices) lose their use of it, and its IR entry leaves the IR. `None` when something
    /// still uses it.
    pub(super) fn release_removed(
        &mut self,
        ns: Namespace,
        at: usize,
        old: &Range<usize>,
        naming: &BTreeMap<usize, Stmt>,
    ) -> Option<()> {
        let uses = match ns {
            Namespace::Material => {
                Some((&mut self.material_uses, &self.used_before.used_materials))
            }
            Namespace::Mesh => Some((&mut self.mesh_uses, &self.used_before.used_meshes)),
            _ => None,
        };
        if let Some((uses, before)) = uses {
            // Used before the placements: an area light names it, found among what names it
            // and lowered again with the other settings (`super::settings`).
            let light = |s: &Stmt| matches!(s, Stmt::Decl(d) if d.kind == DeclKind::Light);
            if before.get(at).copied().unwrap_or(false) && !naming.values().any(light) {
                return None;
            }
            for (&j, s) in naming {
                if !matches!(s, Stmt::Object(_)) {
                    continue;
                }
                // The old list's index: the removed statements stood at `old`.
                let i = if j < old.start { j } else { j + old.len() };
                let record = self.records.get_mut(i)?;
                let field = match ns {
                    Namespace::Material => &mut record.material,
                    _ => &mut record.mesh,
                };
                if *field == Some(at as u32) {
                    let n = uses.get_mut(at)?;
                    *n = n.checked_sub(1)?;
                    *field = None;
                }
            }
            (uses.get(at) == Some(&0)).then_some(())?;
        } else {
            // Its materials are checked again: their lists without it, the rest renumbered.
            for (_, textures) in &mut self.material_textures {
                textures.retain(|&t| t != at);
            }
        }
        self.out_of_ir(ns, at)
    }

    /// Declaration `at` of `ns` out of the IR, if the IR holds it (a dropped one is left to
    /// the removal), every later IR index of its kind moved down by one.
    fn out_of_ir(&mut self, ns: Namespace, at: usize) -> Option<()> {
        let map = match ns {
            Namespace::Material => &mut self.material_map,
            Namespace::Mesh => &mut self.mesh_map,
            _ => &mut self.texture_map,
        };
        let Some(k) = map.get(at).copied()? else {
            return Some(());
        };
        map[at] = None;
        for i in map.iter_mut().flatten() {
            if *i > k {
                *i -= 1;
            }
        }
        let down = |i: &mut u32| {
            if *i > k {
                *i -= 1;
            }
        };
        if ns == Namespace::Mesh {
            self.mesh_overrides.retain(|(m, _)| *m as usize != at);
        }
        let scene = std::sync::Arc::make_mut(self.scene.as_mut()?);
        match ns {
            Namespace::Material => {
                ((k as usize) < scene.materials.len())
                    .then(|| scene.materials.remove(k as usize))?;
                for o in &mut scene.objects {
                    down(&mut o.material);
                }
                let overrides = scene.meshes.iter_mut().flat_map(|m| m.obj.iter_mut());
                for o in overrides.flat_map(|o| &mut o.materials) {
                    down(&mut o.material);
                }
            }
            Namespace::Mesh => {
                ((k as usize) < scene.meshes.len()).then(|| scene.meshes.remove(k as usize))?;
                for o in &mut scene.objects {
                    down(&mut o.mesh);
                }
                for l in &mut scene.lights {
                    if let ir::Light::Area(a) = l {
                        down(&mut a.mesh);
                    }
                }
            }
            _ => {
                ((k as usize) < scene.textures.len()).then(|| scene.textures.remove(k as usize))?;
                for m in &mut scene.materials {
                    texture_inputs(m, down);
                }
            }
        }
        Some(())
    }
}
