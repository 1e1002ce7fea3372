//! Stage 2, check, incrementally: a value edit (or a rename) of one scene setting — a
//! `camera`, a `point` or `environment` `light`, or the `render` block (`fov 40deg` → `fov
//! 45deg`) — checked again alone, its IR entry replaced in place in the [`CheckMemo`].
//!
//! Why the result is the full check's: these statements are checked after every constant and
//! declaration, reading constants, the `frame` and (the render block's `camera NAME`) the
//! camera table and the cameras lowered, and writing only their own IR entry and diagnostics.
//! It declines unless the scene has no error (so every camera and light lowered, and no
//! duplicate `render`), the old statement had no diagnostic in its text, and the new one
//! gives none: then no diagnostic is added or removed, and every other one only moves by the
//! edit. The statement keeps its kind and its table place (the first of its name). An
//! `area` light is declined (it names a mesh, or lowers its `quad` to one: the meshes' use and
//! the IR's indices could change), and so is any `--define` (its unused warning depends on
//! what names it). A camera or light renamed (`light sun` → `light key`) keeps its table place
//! under the new name (declined when the name is taken, any name is declared twice, or, for a
//! camera, the render block names either name: nothing else names a camera or a light). A
//! `let` a setting names, edited ([`super::decls`]), checks the setting again
//! here once the rest of the edit is in place ([`CheckMemo::recheck_named_settings`]), under
//! the same conditions: the statement is unchanged but its value is not.

use std::sync::Arc;

use super::super::names::Namespace;
use super::super::vocabulary::{LightKind, Word};
use super::area_light::lower_area;
use super::{CheckMemo, Dependents};
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{Decl, DeclKind, Ident, Stmt};

/// A scene setting checked again: its new IR entry.
enum Setting {
    Camera(ir::Camera),
    /// A light, and an area light's own quad (its IR index and mesh).
    Light(ir::Light, Option<(u32, ir::Mesh)>),
    Render(ir::RenderSettings, usize),
}

impl CheckMemo {
    /// Whether `old` → `new` is the edit [`CheckMemo::recheck_setting`] takes: a camera, a
    /// (not `area`) light (renamed or not) or the render block.
    pub fn same_setting(old: &Stmt, new: &Stmt) -> bool {
        match (old, new) {
            (Stmt::Camera { .. }, Stmt::Camera { .. }) => true,
            (Stmt::Decl(a), Stmt::Decl(b)) => {
                let (x, y) = (light_kind(a), light_kind(b));
                x.is_some() && x == y
            }
            (Stmt::Render { .. }, Stmt::Render { .. }) => true,
            _ => false,
        }
    }

    /// A camera or light renamed from `old` to `new` (their idents): its table entry takes the
    /// new name at its place (as a renamed declaration's does: [`CheckMemo::rename_entry`];
    /// declined when the new name is taken or any name is declared twice), with the new span
    /// once every other span has moved. Only the render block names a camera (`camera NAME`;
    /// nothing names a light): declined when one names either name (the whole-word search of
    /// the new text). No diagnostic lists camera or light names but an unknown camera's, an
    /// error, which the caller declines.
    fn rename_setting(
        &mut self,
        ns: Namespace,
        (old, new): (&Ident, &Ident),
        dependents: &mut Dependents,
    ) -> Option<usize> {
        if ns == Namespace::Camera {
            let render = |found: Vec<(usize, Stmt)>| {
                (found.iter()).any(|(_, s)| matches!(s, Stmt::Render { .. }))
            };
            if render(dependents(&old.name)?) || render(dependents(&new.name)?) {
                return None;
            }
        }
        self.rename_entry(ns, old, new)
    }

    /// Replaces the check of the setting `old` (as parsed from the old text) by that of `new`
    /// ([`CheckMemo::same_setting`]), every other span moving by `shift`; `sources` holds the
    /// new text. The number of statements checked again (1), or `None` when the result could
    /// differ from a full check's: the memo is then spoiled, and the caller checks in full.
    pub fn recheck_setting(
        &mut self,
        sources: &SourceMap,
        old: &Stmt,
        new: &Stmt,
        shift: &Shift,
        dependents: &mut Dependents,
    ) -> Option<usize> {
        let old_span = old.span();
        let in_old = |d: &Diagnostic| {
            d.primary.as_ref().is_some_and(|l| {
                l.span.file == old_span.file
                    && (old_span.start..old_span.end).contains(&l.span.start)
            })
        };
        let clean = !self.diagnostics.iter().any(|d| d.is_error() || in_old(d));
        if !Self::same_setting(old, new) || !clean || !self.defines.is_empty() {
            return None;
        }
        let renamed = match (old, new) {
            (Stmt::Camera { name: a, .. }, Stmt::Camera { name: b, .. }) => {
                Some((Namespace::Camera, a, b))
            }
            (Stmt::Decl(a), Stmt::Decl(b)) => Some((Namespace::Light, &a.name, &b.name)),
            _ => None,
        }
        .filter(|(_, a, b)| a.name != b.name);
        let at = match renamed {
            Some((ns, a, b)) => Some((ns, self.rename_setting(ns, (a, b), dependents)?, b.span)),
            None => None,
        };
        let area = match old {
            Stmt::Decl(d) if light_kind(d) == Some(LightKind::Area) => {
                Some(self.area_mesh(old_span)?)
            }
            _ => None,
        };
        let cameras = self.scene.as_ref()?.cameras.clone();
        if !self.shift_names(shift) {
            return None;
        }
        if let Some((ns, at, span)) = at {
            *self.tables[ns as usize].spans.get_mut(at)? = span;
        }
        let mut cx = self.lend(sources);
        let setting = match new {
            Stmt::Camera { name, body, span } => {
                let first = cx.tables[Namespace::Camera as usize].get(&name.name);
                let spans = &cx.tables[Namespace::Camera as usize].spans;
                let first = first.is_some_and(|at| spans.get(at) == Some(&name.span));
                first.then(|| cx.camera(name, body, *span).map(Setting::Camera))
            }
            Stmt::Decl(d) if d.kind == DeclKind::Light => {
                let first = cx.tables[Namespace::Light as usize].get(&d.name.name);
                let spans = &cx.tables[Namespace::Light as usize].spans;
                let first = first.is_some_and(|at| spans.get(at) == Some(&d.name.span));
                first.then(|| match &area {
                    Some(area) => {
                        let (light, mesh) = lower_area(&mut cx, d, area)?;
                        Some(Setting::Light(light, mesh.map(|m| (area.ir, m))))
                    }
                    None => {
                        cx.light(d);
                        cx.lights.pop().map(|l| Setting::Light(l, None))
                    }
                })
            }
            Stmt::Render { body, span } => {
                cx.cameras = cameras;
                let settings = cx.render(Some((body, *span)));
                Some(settings.map(|s| Setting::Render(s, cx.active_camera)))
            }
            _ => None,
        };
        self.take_back(&mut cx);
        let setting = setting.flatten().filter(|_| cx.diags.is_empty())?;
        self.put_setting(old_span, setting, shift).then_some(1)
    }

    /// Checks again the settings `settings` (statements of the new text, whose spans the memo
    /// already holds) that name a constant whose value a declaration edit changed: each as
    /// [`CheckMemo::recheck_setting`] checks an edited one (its spans unmoved), cameras and
    /// lights before the render block (it reads the cameras lowered). `None`: decline.
    pub(super) fn recheck_named_settings(
        &mut self,
        sources: &SourceMap,
        settings: &[Stmt],
    ) -> Option<()> {
        let (render, others): (Vec<&Stmt>, Vec<&Stmt>) = settings
            .iter()
            .partition(|s| matches!(s, Stmt::Render { .. }));
        for s in others.into_iter().chain(render) {
            let unmoved = Shift {
                file: s.span().file,
                start: u32::MAX,
                old_end: u32::MAX,
                new_end: u32::MAX,
            };
            self.recheck_setting(sources, s, s, &unmoved, &mut |_| Some(Vec::new()))?;
        }
        Some(())
    }

    /// Moves every span by `shift` but those of the setting whose old statement is `old`,
    /// whose IR entry `setting` replaces.
    fn put_setting(&mut self, old: Span, setting: Setting, shift: &Shift) -> bool {
        let Some(scene) = &mut self.scene else {
            return false;
        };
        let scene = Arc::make_mut(scene);
        let inside = |s: Span| s.file == old.file && (old.start..old.end).contains(&s.start);
        // The old entry is taken out before the spans move (its own lie in the edited text).
        let place = match &setting {
            Setting::Camera(_) => {
                let at = scene.cameras.iter().position(|c| inside(c.span));
                at.inspect(|&at| drop(scene.cameras.remove(at)))
            }
            Setting::Light(..) => {
                let at = scene.lights.iter().position(|l| inside(light_span(l)));
                at.inspect(|&at| drop(scene.lights.remove(at)))
            }
            Setting::Render(..) => {
                scene.render.outputs.clear();
                Some(0)
            }
        };
        let Some(at) = place else {
            return false;
        };
        // An area light's own quad: its old mesh (a span in the edited text) replaced before
        // the spans move, the new one's span (the new text's) set after.
        let quad = match &setting {
            Setting::Light(_, Some((k, mesh))) => {
                let Some(slot) = scene.meshes.get_mut(*k as usize) else {
                    return false;
                };
                *slot = ir::Mesh {
                    span: Span::new(old.file, 0, 0),
                    ..mesh.clone()
                };
                Some((*k as usize, mesh.span))
            }
            _ => None,
        };
        let mut ok = scene.shift_spans(shift);
        if let Some((k, span)) = quad {
            scene.meshes[k].span = span;
        }
        match setting {
            Setting::Camera(c) => scene.cameras.insert(at, c),
            Setting::Light(l, _) => scene.lights.insert(at, l),
            Setting::Render(r, active_camera) => {
                scene.render = r;
                scene.active_camera = active_camera;
            }
        }
        for d in &mut self.diagnostics {
            ok &= d.shift_spans(shift);
        }
        ok & self.dropped.shift_spans(shift)
    }
}

/// The span a light's IR entry keeps (its name's).
fn light_span(l: &ir::Light) -> Span {
    match l {
        ir::Light::Point(p) => p.span,
        ir::Light::Area(a) => a.span,
        ir::Light::Environment(e) => e.span,
    }
}

/// The kind of the light declaration `d` (`None`: not a light, or an unknown kind).
fn light_kind(d: &Decl) -> Option<LightKind> {
    (d.kind == DeclKind::Light)
        .then(|| LightKind::from_word(&d.ctor.name.name))
        .flatten()
}
