//! Stage 2, check, incrementally: keeps what a full check of a file's statements learnt (the
//! constants, the declaration tables, the IR, every diagnostic in the order it was found, and
//! one [`StmtRecord`] per statement) so that after an edit that changed only top-level `object`
//! statements, those alone are checked again and spliced in (`compile::incremental` decides
//! when an edit is such an edit). An edit of `let`, `material` and `mesh` declarations that
//! keeps their names is re-checked in place with what names a changed constant
//! ([`decls`]); `let`s added or removed that nothing names are checked alone ([`lets`]); a
//! value edit of a camera, a light or the render block is checked alone ([`settings`]); an
//! edit of `group`s that keeps their names is checked as one of `object`s ([`groups`]); a
//! renamed declaration is checked with what reads either name ([`renamed`]), and so is a
//! renamed `let` ([`let_renamed`]); declarations added or removed, with `object`s beside them,
//! are checked with what names them ([`added`], [`removed`]); a second declaration of a name
//! edited, added or removed alone only moves spans and gives or takes its error
//! ([`redeclared`]); everything else is a full check.
//!
//! Why the result is the full check's: an `object` is checked in the placement phase, after
//! every constant and declaration, reading only constants, the `frame`, the name tables and the
//! source text, and writing only its diagnostics, its IR object and the use of one mesh and one
//! material. Its diagnostics and objects sit in one run of the check's order (placements in
//! statement order), so they are cut out and the new ones put in their place. The IR's indices
//! of meshes and materials depend only on which are used: when an edit makes one used or
//! unused (a use count reaches or leaves zero) the IR is compacted again ([`compact`]). All
//! other spans move by the edit's [`Shift`]; one that reaches into the edited bytes makes the
//! re-check decline.

use std::ops::Range;
use std::sync::Arc;

mod added;
mod compact;
mod decls;
mod groups;
mod let_removed;
mod let_renamed;
mod lets;
mod redeclared;
mod redo;
mod reevaluate;
mod removed;
mod renamed;
mod renumber;
mod runs;
mod settings;
mod splice_decls;

pub use compact::Dropped;
pub use decls::Dependents;

use super::names::{Namespace, Table};
use super::{Checker, PlacementStart, StmtRecord};
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::{MoveSpans, Renumber, Shift, SourceMap};
use crate::syntax::Stmt;
use compact::Relowered;

/// What a full check of one statement list leaves for re-checking its `object`s and
/// declarations.
pub struct CheckMemo {
    frame: f64,
    lets: super::Constants,
    poisoned: std::collections::HashSet<String>,
    defines: std::collections::HashMap<String, (crate::syntax::Expr, bool)>,
    tables: [Table; 6],
    material_map: Vec<Option<u32>>,
    mesh_map: Vec<Option<u32>>,
    /// Declarations something other than an object had used before the placements.
    used_before: PlacementStart,
    material_uses: Vec<u32>,
    mesh_uses: Vec<u32>,
    /// The materials that refer to textures: (material, texture table indices), ascending.
    material_textures: Vec<(u32, Vec<usize>)>,
    /// The material overrides of the `obj` meshes the IR holds: (mesh, materials), table
    /// indices, ascending (what `finish` remapped, for the re-compaction to map back).
    mesh_overrides: Vec<(u32, Vec<u32>)>,
    texture_map: Vec<Option<u32>>,
    /// The lowered declarations the IR leaves out, for an edit that makes one used.
    dropped: Dropped,
    /// How many of the last diagnostics the check's last pass gave (unused declarations, no
    /// camera), which a re-compaction gives again.
    finish_diags: usize,
    /// One per statement, in statement order.
    pub records: Vec<StmtRecord>,
    /// The indices of the scene settings (cameras, lights, render blocks) among the
    /// statements, ascending: those whose records say so ([`settings`] lowers them again).
    settings: Vec<usize>,
    /// Per light of the IR, the mesh table index of an area light (the IR holds IR indices),
    /// for the re-compaction.
    light_meshes: Vec<Option<u32>>,
    /// Every diagnostic of the check, in the order it was found.
    pub diagnostics: Vec<Diagnostic>,
    /// The scene, also when there were errors (with the default render settings when the
    /// render block failed: an error stands then, and the result shows no scene).
    /// Shared with the compile's result, so that the memo and the scene a caller holds are
    /// one copy; an edit clones it only while a caller still holds the previous one.
    pub scene: Option<Arc<ir::SceneDesc>>,
    /// Which of two spans the check reads first: the compile's include structure, kept by
    /// `compile::Incremental` (empty, byte order, for a scene without includes).
    pub order: crate::source::ReadingOrder,
}

/// [`super::check_placed`], keeping a [`CheckMemo`]: its `scene` (filtered by errors) and its
/// `diagnostics` are that check's result.
pub fn check_tracked(
    statements: &[Stmt],
    placed: super::Placed,
    sources: &SourceMap,
    frame: f64,
    defines: Vec<(String, crate::syntax::Expr)>,
) -> CheckMemo {
    let mut cx = Checker::new(sources);
    cx.frame = frame;
    cx.defines = defines.into_iter().map(|(n, e)| (n, (e, false))).collect();
    let mut records = Vec::new();
    let mut start = None;
    let scene = cx.run(statements, placed, Some((&mut records, &mut start)));
    let used_before = start.unwrap_or(PlacementStart {
        diags: cx.diags.len(),
        used_meshes: Vec::new(),
        used_materials: Vec::new(),
    });
    CheckMemo {
        frame: cx.frame,
        lets: std::mem::take(&mut cx.lets),
        poisoned: std::mem::take(&mut cx.poisoned),
        defines: std::mem::take(&mut cx.defines),
        tables: std::mem::take(&mut cx.tables),
        material_map: std::mem::take(&mut cx.material_map),
        mesh_map: std::mem::take(&mut cx.mesh_map),
        used_before,
        material_uses: std::mem::take(&mut cx.material_uses),
        mesh_uses: std::mem::take(&mut cx.mesh_uses),
        material_textures: std::mem::take(&mut cx.material_textures),
        mesh_overrides: std::mem::take(&mut cx.mesh_overrides),
        texture_map: std::mem::take(&mut cx.texture_map),
        dropped: std::mem::take(&mut cx.dropped),
        finish_diags: cx.diags.len() - cx.finish_from,
        settings: (records.iter().enumerate())
            .filter(|(_, r)| r.setting)
            .map(|(i, _)| i)
            .collect(),
        light_meshes: std::mem::take(&mut cx.light_meshes),
        records,
        diagnostics: std::mem::take(&mut cx.diags),
        scene: scene.map(Arc::new),
        order: Default::default(),
    }
}

/// The re-check of some `object`s: their diagnostics, IR objects (table indices) and records.
struct Rechecked {
    diags: Vec<Diagnostic>,
    objects: Vec<ir::Object>,
    records: Vec<StmtRecord>,
}

impl CheckMemo {
    /// Whether the statements `old` (indices into the old list) and `new` are all top-level
    /// `object`s: the edit [`CheckMemo::recheck`] takes.
    pub fn only_objects(&self, old: Range<usize>, new: &[Stmt]) -> bool {
        self.records
            .get(old)
            .is_some_and(|rs| rs.iter().all(|r| r.object))
            && new.iter().all(|s| matches!(s, Stmt::Object(_)))
    }

    /// Replaces the check of the statements `old` (indices into the old list, every one a
    /// top-level `object`) by that of `new` (every one a top-level `object`), all other spans
    /// moving by `shift`; `sources` holds the new text. `false` when the result could differ
    /// from a full check's: the memo is then spoiled, and the caller checks in full.
    pub fn recheck(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        new: &[Stmt],
        shift: &Shift,
    ) -> bool {
        self.only_objects(old.clone(), new) && self.replace_objects(sources, old, new, shift)
    }

    /// [`CheckMemo::recheck`] of an included file's statements added or removed with the
    /// include that reads it (`compile::Incremental`'s include edits): the old statements `old`
    /// are `object`s but at the list indices `old_inert` (the caller found a version header or
    /// an include there: their records must say nothing), and `new` are `object`s, version
    /// headers and includes (checked in no phase: the driver reads them).
    pub fn recheck_block(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_inert: &[usize],
        new: &[Stmt],
        shift: &Shift,
    ) -> bool {
        let Some(old_records) = self.records.get(old.clone()) else {
            return false;
        };
        let kept = (old.clone())
            .zip(old_records)
            .all(|(i, r)| match old_inert.contains(&i) {
                true => *r == StmtRecord::default(),
                false => r.object,
            });
        let placed = |s: &Stmt| matches!(s, Stmt::Object(_)) || inert(s);
        kept && new.iter().all(placed) && self.replace_objects(sources, old, new, shift)
    }

    /// The re-check of [`CheckMemo::recheck`], its statements' kinds found right.
    fn replace_objects(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        new: &[Stmt],
        shift: &Shift,
    ) -> bool {
        let Some(old_records) = self.records.get(old.clone()) else {
            return false;
        };
        let (diag_range, object_range) = self.output_ranges(&old);
        let removed: Vec<StmtRecord> = old_records.to_vec();
        let was_used = (self.used_meshes(), self.used_materials());
        let rechecked = self.check_objects(sources, new);
        for r in &removed {
            if let Some(m) = r.mesh {
                self.mesh_uses[m as usize] -= 1;
            }
            if let Some(m) = r.material {
                self.material_uses[m as usize] -= 1;
            }
        }
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        if !self.splice(diag_range, object_range, old, rechecked, shift) {
            return false;
        }
        // A mesh or material now used or unused: the IR's indices change.
        !used_changed || self.recompact(sources, Relowered::default()).is_some()
    }

    /// Moves every span by `shift`, for an edit whose statements nothing checks (the version
    /// header); `false` when one reaches into the edited bytes.
    pub fn shift_spans(&mut self, shift: &impl MoveSpans) -> bool {
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records: Vec::new(),
        };
        self.splice(0..0, 0..0, 0..0, nothing, shift)
    }

    /// Every span's file named by its new id after `renumber` (an include added before other
    /// files are read, or removed while others are read after it), the reading order's
    /// included too; `false` when one names a file removed, or a `--define`'s value (whose
    /// file is read after the scene's) is kept: the memo is then spoiled.
    pub fn renumber_files(&mut self, renumber: &Renumber) -> bool {
        self.defines.is_empty() && self.order.renumber(renumber) && self.shift_spans(renumber)
    }

    /// Cuts the old statements' results out, moves every other span, puts the new ones in.
    fn splice(
        &mut self,
        diag_range: Range<usize>,
        object_range: Range<usize>,
        old: Range<usize>,
        rechecked: Rechecked,
        shift: &impl MoveSpans,
    ) -> bool {
        let Rechecked {
            diags,
            mut objects,
            records,
        } = rechecked;
        let mut ok = true;
        if diag_range.end > self.diagnostics.len() {
            return false;
        }
        self.diagnostics.splice(diag_range.clone(), []);
        for d in &mut self.diagnostics {
            ok &= d.shift_spans(shift);
        }
        self.diagnostics
            .splice(diag_range.start..diag_range.start, diags);
        if let Some(scene) = &mut self.scene {
            if object_range.end > scene.objects.len() {
                return false;
            }
            let scene = Arc::make_mut(scene);
            scene.objects.splice(object_range.clone(), []);
            ok &= scene.shift_spans(shift);
            for o in &mut objects {
                let mesh = self.mesh_map.get(o.mesh as usize).copied().flatten();
                let material = self
                    .material_map
                    .get(o.material as usize)
                    .copied()
                    .flatten();
                o.mesh = mesh.unwrap_or(0);
                o.material = material.unwrap_or(0);
            }
            scene
                .objects
                .splice(object_range.start..object_range.start, objects);
        }
        ok &= self.dropped.shift_spans(shift);
        for span in self.lets.spans_mut() {
            ok &= shift.apply(span);
        }
        for t in &mut self.tables {
            for span in &mut t.spans {
                ok &= shift.apply(span);
            }
        }
        let added = records.len();
        let settings: Vec<usize> = (records.iter().enumerate())
            .filter(|(_, r)| r.setting)
            .map(|(i, _)| old.start + i)
            .collect();
        self.records.splice(old.clone(), records);
        // The settings' indices: those of the old statements out, the later ones moved, the
        // new ones in.
        self.settings.retain(|i| !old.contains(i));
        for i in &mut self.settings {
            if *i >= old.end {
                *i = *i + added - old.len();
            }
        }
        let at = self.settings.partition_point(|&i| i < old.start);
        self.settings.splice(at..at, settings);
        ok
    }

    /// Checks `new` (top-level `object`s and `group`s) as the placement phase would, against
    /// the memo's constants and tables, counting their uses. The groups are checked against an
    /// empty group table (the caller answers for their names: [`groups`]).
    fn check_objects(&mut self, sources: &SourceMap, new: &[Stmt]) -> Rechecked {
        self.check_placements(sources, new, false)
    }

    /// [`CheckMemo::check_objects`], the groups checked against the memo's group table when
    /// `with_groups` (later declarations of names it holds: [`groups`]).
    fn check_placements(
        &mut self,
        sources: &SourceMap,
        new: &[Stmt],
        with_groups: bool,
    ) -> Rechecked {
        let mut cx = self.lend(sources);
        let groups = match with_groups {
            true => Default::default(),
            false => std::mem::take(&mut cx.tables[Namespace::Group as usize]),
        };
        let mut records = Vec::with_capacity(new.len());
        for stmt in new {
            if inert(stmt) {
                records.push(StmtRecord::default());
                continue;
            }
            let (diags, objects) = (cx.diags.len(), cx.objects.len());
            let (mesh, material) = cx.placement(stmt);
            records.push(StmtRecord {
                object: matches!(stmt, Stmt::Object(_)),
                setting: false,
                diags: (cx.diags.len() - diags) as u32,
                objects: (cx.objects.len() - objects) as u32,
                mesh: mesh.map(|m| m as u32),
                material: material.map(|m| m as u32),
            });
        }
        if !with_groups {
            cx.tables[Namespace::Group as usize] = groups;
        }
        self.take_back(&mut cx);
        Rechecked {
            diags: std::mem::take(&mut cx.diags),
            objects: std::mem::take(&mut cx.objects),
            records,
        }
    }

    /// A checker in the state the full check left (constants, names, use counts), to check
    /// statements again; [`CheckMemo::take_back`] returns that state.
    fn lend<'s>(&mut self, sources: &'s SourceMap) -> Checker<'s> {
        let mut cx = Checker::new(sources);
        cx.frame = self.frame;
        cx.order = self.order.clone();
        cx.lets = std::mem::take(&mut self.lets);
        cx.poisoned = std::mem::take(&mut self.poisoned);
        cx.defines = std::mem::take(&mut self.defines);
        cx.tables = std::mem::take(&mut self.tables);
        cx.used_meshes = vec![false; self.mesh_uses.len()];
        cx.used_materials = vec![false; self.material_uses.len()];
        cx.mesh_uses = std::mem::take(&mut self.mesh_uses);
        cx.material_uses = std::mem::take(&mut self.material_uses);
        cx
    }

    /// Takes back what [`CheckMemo::lend`] lent (`cx` keeps its diagnostics and objects).
    fn take_back(&mut self, cx: &mut Checker) {
        self.lets = std::mem::take(&mut cx.lets);
        self.poisoned = std::mem::take(&mut cx.poisoned);
        self.defines = std::mem::take(&mut cx.defines);
        self.tables = std::mem::take(&mut cx.tables);
        self.mesh_uses = std::mem::take(&mut cx.mesh_uses);
        self.material_uses = std::mem::take(&mut cx.material_uses);
    }

    /// Where the statements `old` (indices into the memo's records) put their output: the range
    /// of their diagnostics among the check's and of their objects among the IR's.
    fn output_ranges(&self, old: &Range<usize>) -> (Range<usize>, Range<usize>) {
        let sum = |rs: &[StmtRecord], f: fn(&StmtRecord) -> u32| -> usize {
            rs.iter().map(|r| f(r) as usize).sum()
        };
        let (before, records) = (&self.records[..old.start], &self.records[old.clone()]);
        let diag_at = self.used_before.diags + sum(before, |r| r.diags);
        let object_at = sum(before, |r| r.objects);
        (
            diag_at..diag_at + sum(records, |r| r.diags),
            object_at..object_at + sum(records, |r| r.objects),
        )
    }

    /// Which meshes are used (by an object, or by something checked before the objects).
    fn used_meshes(&self) -> Vec<bool> {
        used(&self.used_before.used_meshes, &self.mesh_uses)
    }

    /// Which materials are used (as [`CheckMemo::used_meshes`]).
    fn used_materials(&self) -> Vec<bool> {
        used(&self.used_before.used_materials, &self.material_uses)
    }
}

/// Whether `s` is checked in no phase: a version header or an `include` (the driver reads
/// them; their statement records say nothing).
pub fn inert(s: &Stmt) -> bool {
    matches!(s, Stmt::Version { .. } | Stmt::Include { .. })
}

fn used(before: &[bool], uses: &[u32]) -> Vec<bool> {
    uses.iter()
        .enumerate()
        .map(|(i, &n)| n > 0 || before.get(i).copied().unwrap_or(false))
        .collect()
}
