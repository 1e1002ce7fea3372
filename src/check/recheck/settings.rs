//! Stage 2, check, incrementally: the scene settings — every `camera`, `light` and `render`
//! block — checked again together (2026-11-28, eighth session), whenever an edit changes one
//! of them (a value, a name, one added or removed: [`CheckMemo::recheck_settings`]) or
//! something they may read: a constant one names, a mesh an `area` light names, a name an
//! unknown-name diagnostic of theirs lists, the constants an unused `--define`'s did-you-mean
//! lists. Until the seventh session each setting was checked alone, and only while the scene
//! had no error and the setting kept its diagnostics; everything else was a full compile.
//!
//! Why the result is the full check's: the check declares the cameras and lights in
//! statement order (their own tables: nothing else declares into them), lowers the lights
//! after the meshes (an area light's `mesh NAME` marks that mesh used before the placements;
//! its `quad` is a mesh of its own, past the declared ones), and the cameras, a second render
//! block's error, the unused `--define`s and the render block after the placements. What
//! they read is the constants, the `frame`, the `--define`s (and whether a `let` used each),
//! the mesh table and their own two tables; nothing else reads what they write but the
//! check's last pass (`finish`: whether there is a camera, which meshes are used, the area
//! lights' and quads' IR indices). They are few, so all of them are lowered again from their
//! statements (found by their statement records) against the memo's state once the rest of
//! the edit is in place, and their output replaces the old: the camera and light tables,
//! their diagnostics before the placements (each lies in its statement's text) and after them
//! (all the diagnostics between the placements' and `finish`'s), the IR's cameras, lights,
//! quads and render settings. When which meshes the lights use, how many quads there are, or
//! whether the scene has a camera changes, the IR is compacted again ([`super::compact`]),
//! which gives `finish`'s warnings and indices again. A render block that fails leaves the
//! IR's render settings as they were: the scene then has an error, so no one sees them.

use std::sync::Arc;

use super::super::names::{Namespace, Table};
use super::compact::Relowered;
use super::{CheckMemo, Dependents, Rechecked};
use crate::diag::{Code, Diagnostic};
use crate::ir;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{DeclKind, Stmt};

/// The settings of the new text lowered again: what replaces their old output.
pub(super) struct Settings {
    /// Every setting statement's span.
    spans: Vec<Span>,
    /// Their diagnostics before the placements (names declared twice, the lights').
    early: Vec<Diagnostic>,
    /// The cameras', a second render block's, the unused `--define`s' and the render block's.
    late: Vec<Diagnostic>,
    /// The lights, an area light's mesh by table index.
    lights: Vec<ir::Light>,
    /// The area lights' own quads, in order (table indices past the declared meshes).
    quads: Vec<ir::Mesh>,
    /// Which meshes the area lights named (used before the placements).
    marks: Vec<bool>,
    cameras: Vec<ir::Camera>,
    render: Option<ir::RenderSettings>,
    active_camera: usize,
}

impl Settings {
    /// How many statements were checked again.
    pub(super) fn checked(&self) -> usize {
        self.spans.len()
    }
}

impl CheckMemo {
    /// Replaces the settings `old` (indices into the old list; `old_stmts`, as parsed from the
    /// old text) by `new` (any number of each, every one a `camera`, `light` or `render`),
    /// every other span moving by `shift`, and checks every setting again; `sources` holds
    /// the new text. The number of statements checked again, or `None` when the result could
    /// differ from a full check's (the memo is then spoiled).
    pub fn recheck_settings(
        &mut self,
        sources: &SourceMap,
        old: std::ops::Range<usize>,
        old_stmts: &[Stmt],
        new: &[Stmt],
        shift: &Shift,
        statements: &mut dyn Dependents,
    ) -> Option<usize> {
        let all = |s: &[Stmt]| s.iter().all(super::super::is_setting);
        if old.len() != old_stmts.len() || !all(old_stmts) || !all(new) {
            return None;
        }
        // Their output goes before the spans move (the edited ones' lie in the edited
        // bytes); all of it is made again below.
        let old_spans: Vec<Span> = old_stmts.iter().map(Stmt::span).collect();
        self.drop_early(&old_spans);
        let late = self.late_range()?;
        self.diagnostics.drain(late);
        self.tables[Namespace::Camera as usize] = Table::default();
        self.tables[Namespace::Light as usize] = Table::default();
        let declared = self.tables[Namespace::Mesh as usize].len();
        let scene = Arc::make_mut(self.scene.as_mut()?);
        scene.cameras.clear();
        scene.lights.clear();
        scene.render.outputs.clear();
        self.light_meshes.clear();
        for k in self.mesh_map.get(declared..)?.iter().flatten() {
            let quad = scene.meshes.get_mut(*k as usize)?;
            quad.span = Span::new(shift.file, 0, 0);
        }
        let records = new
            .iter()
            .map(|_| super::StmtRecord {
                setting: true,
                ..Default::default()
            })
            .collect();
        let nothing = Rechecked {
            diags: Vec::new(),
            objects: Vec::new(),
            records,
        };
        if !self.splice(0..0, 0..0, old, nothing, shift) {
            return None;
        }
        let settings = self.lower_settings(sources, statements)?;
        let checked = settings.checked();
        let mut relowered = Relowered::default();
        if self.put_settings(settings, &mut relowered)? {
            self.recompact(sources, relowered)?;
        }
        Some(checked)
    }

    /// Lowers every setting of the new text again, as the check does, against the memo's
    /// constants, `--define`s and mesh table (the rest of the edit in place); the camera and
    /// light tables are made again here. `None` when a setting cannot be parsed alone.
    pub(super) fn lower_settings(
        &mut self,
        sources: &SourceMap,
        statements: &mut dyn Dependents,
    ) -> Option<Settings> {
        let stmts: Vec<Stmt> = (self.settings.iter())
            .map(|&i| statements.statement(i))
            .collect::<Option<_>>()?;
        let mut cx = self.lend(sources);
        cx.tables[Namespace::Camera as usize] = Table::default();
        cx.tables[Namespace::Light as usize] = Table::default();
        // The quads take the table places after the declared meshes.
        let declared = cx.tables[Namespace::Mesh as usize].len();
        cx.meshes = std::iter::repeat_with(|| None).take(declared).collect();
        let (mut cameras, mut lights, mut renders) = (Vec::new(), Vec::new(), Vec::new());
        let mut known = true;
        for s in &stmts {
            match s {
                Stmt::Camera { name, body, span } => {
                    if cx.declare(Namespace::Camera, &name.name, name.span) {
                        cameras.push((name, body, *span));
                    }
                }
                Stmt::Decl(d) if d.kind == DeclKind::Light => {
                    if cx.declare(Namespace::Light, &d.name.name, d.name.span) {
                        lights.push(&**d);
                    }
                }
                Stmt::Render { body, span } => renders.push((body, *span)),
                _ => known = false,
            }
        }
        for d in lights {
            cx.light(d);
        }
        let early = std::mem::take(&mut cx.diags);
        cx.lower_cameras(cameras);
        let render = cx.render_blocks(&renders);
        self.take_back(&mut cx);
        let quads = cx.meshes.split_off(declared);
        Some(Settings {
            spans: stmts.iter().map(Stmt::span).collect(),
            early,
            late: std::mem::take(&mut cx.diags),
            lights: std::mem::take(&mut cx.lights),
            quads: quads.into_iter().collect::<Option<_>>()?,
            marks: std::mem::take(&mut cx.used_meshes),
            cameras: std::mem::take(&mut cx.cameras),
            render,
            active_camera: cx.active_camera,
        })
        .filter(|_| known)
    }

    /// The settings lowered again ([`CheckMemo::lower_settings`]) when a re-check found some
    /// among what names a changed name (`redone`'s, counted among its statements checked
    /// again: the others are added), or `always`; `None` inside when none need to be, `None`
    /// when the re-check must decline.
    pub(super) fn settings_named(
        &mut self,
        sources: &SourceMap,
        redone: &mut super::decls::Redone,
        always: bool,
        statements: &mut dyn Dependents,
    ) -> Option<Option<Settings>> {
        let found = std::mem::take(&mut redone.settings).len();
        if found == 0 && !always {
            return Some(None);
        }
        let settings = self.lower_settings(sources, statements)?;
        redone.checked += settings.checked().checked_sub(found)?;
        Some(Some(settings))
    }

    /// Puts the settings lowered again in place of the old ones' output (every span already
    /// the new text's). `true` when the IR must be compacted again (which meshes the lights
    /// use, how many quads there are or whether the scene has a camera changed), with the
    /// quads put in `relowered`; else the lights and quads are in the IR already.
    pub(super) fn put_settings(&mut self, s: Settings, relowered: &mut Relowered) -> Option<bool> {
        let inside = |d: &Diagnostic| {
            let at = d.primary.as_ref().map(|l| l.span);
            at.is_some_and(|at| {
                (s.spans.iter()).any(|s| s.file == at.file && (s.start..s.end).contains(&at.start))
            })
        };
        // The next edit finds them by their statements' spans.
        if !s.early.iter().all(inside) {
            return None;
        }
        self.drop_early(&s.spans);
        let at = self.used_before.diags;
        self.used_before.diags += s.early.len();
        self.diagnostics.splice(at..at, s.early);
        let late = self.late_range()?;
        self.diagnostics.splice(late, s.late);
        let finish = self.diagnostics.len() - self.finish_diags;
        let had_no_camera =
            (self.diagnostics[finish..].iter()).any(|d| d.code == Code::CheckNoCamera);
        let no_camera = s.cameras.is_empty() && self.tables[Namespace::Camera as usize].is_empty();
        if s.marks.len() != self.used_before.used_meshes.len() {
            return None;
        }
        let marks_changed = s.marks != self.used_before.used_meshes;
        self.used_before.used_meshes = s.marks;
        self.light_meshes = (s.lights.iter())
            .map(|l| match l {
                ir::Light::Area(a) => Some(a.mesh),
                _ => None,
            })
            .collect();
        let declared = self.tables[Namespace::Mesh as usize].len();
        let quads_kept = self.mesh_map.len().checked_sub(declared)? == s.quads.len();
        let scene = Arc::make_mut(self.scene.as_mut()?);
        scene.cameras = s.cameras;
        scene.active_camera = s.active_camera;
        match s.render {
            Some(render) => scene.render = render,
            // Unseen: an error stands (a failing value is reported, or names a constant
            // that failed, which was).
            None if self.diagnostics.iter().any(Diagnostic::is_error) => {}
            None => return None,
        }
        scene.lights = s.lights;
        if marks_changed || !quads_kept || had_no_camera != no_camera {
            relowered.quads = Some(s.quads);
            return Some(true);
        }
        for (l, &mesh) in scene.lights.iter_mut().zip(&self.light_meshes) {
            if let (ir::Light::Area(a), Some(mesh)) = (l, mesh) {
                // As `finish` maps it (0 for a mesh that failed to lower).
                a.mesh = self.mesh_map.get(mesh as usize)?.unwrap_or(0);
            }
        }
        let quad_places = self.mesh_map.get(declared..)?;
        for (k, quad) in quad_places.iter().zip(s.quads) {
            *scene.meshes.get_mut((*k)? as usize)? = quad;
        }
        Some(false)
    }

    /// Where the diagnostics after the placements and before `finish`'s lie: the cameras', a
    /// second render block's, the unused `--define`s' and the render block's.
    fn late_range(&self) -> Option<std::ops::Range<usize>> {
        let placed: usize = self.records.iter().map(|r| r.diags as usize).sum();
        let start = self.used_before.diags + placed;
        let end = self.diagnostics.len().checked_sub(self.finish_diags)?;
        (start <= end).then_some(start..end)
    }
}
