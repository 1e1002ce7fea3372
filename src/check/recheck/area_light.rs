//! Stage 2, check, incrementally: an `area` light edited in place (`light panel = area { quad
//! … radiance 5 }` → `… radiance 6 }`, its corners, its transform), for
//! [`CheckMemo::recheck_setting`].
//!
//! Why the result is the full check's: an area light is checked after every declaration, as
//! the other lights are, but it also emits from a mesh. With `mesh NAME` it names a declared
//! mesh (marking it used before the placements); with `quad P0 P1 P2 P3` it lowers a mesh of its
//! own, placed past the declared ones (table index: the declared meshes and the quads of the
//! area lights before it), which the IR always keeps. The edit is taken when the new light
//! emits from the same mesh table index as the old one, in the same way (`mesh NAME` of the
//! same mesh, or its own quad): then which meshes are used and every IR index stay, the light's
//! IR entry takes the old one's mesh index, and a quad's IR mesh is replaced where it was.
//! Anything else (a quad given a mesh name, another mesh named) declines: the meshes' use and
//! the IR's indices could change.

use super::super::names::Namespace;
use super::super::Checker;
use super::CheckMemo;
use crate::ir;
use crate::source::Span;
use crate::syntax::Decl;

/// The mesh an area light emits from, as the memo holds it.
pub(super) struct AreaMesh {
    /// Its table index (past the declared meshes for a quad of the light's own).
    table: usize,
    /// Its IR index.
    pub(super) ir: u32,
    /// Whether it is the light's own quad.
    quad: bool,
}

impl CheckMemo {
    /// The mesh of the area light whose IR entry's span lies in `old` (the statement's span,
    /// in the text the IR's spans are in), or `None` when there is none.
    pub(super) fn area_mesh(&self, old: Span) -> Option<AreaMesh> {
        let inside = |s: Span| s.file == old.file && (old.start..old.end).contains(&s.start);
        let scene = self.scene.as_ref()?;
        let ir = scene.lights.iter().find_map(|l| match l {
            ir::Light::Area(a) if inside(a.span) => Some(a.mesh),
            _ => None,
        })?;
        let table = self.mesh_map.iter().position(|m| *m == Some(ir))?;
        let quad = table >= self.tables[Namespace::Mesh as usize].len();
        Some(AreaMesh { table, ir, quad })
    }
}

/// Lowers the area light `d` against the lent checker `cx`: its IR (the mesh index the IR's,
/// `old`'s) and, for a quad, its mesh; `None` when it does not emit from `old`'s mesh in the
/// same way (or fails to lower: the caller declines on its diagnostics).
pub(super) fn lower_area(
    cx: &mut Checker,
    d: &Decl,
    old: &AreaMesh,
) -> Option<(ir::Light, Option<ir::Mesh>)> {
    // A quad takes the next table index: the one the full check gave it.
    cx.meshes = std::iter::repeat_with(|| None)
        .take(if old.quad { old.table } else { 0 })
        .collect();
    let before = cx.meshes.len();
    cx.light(d);
    let light = cx.lights.pop();
    let mut own = cx.meshes.split_off(before);
    cx.meshes.clear();
    let Some(ir::Light::Area(mut a)) = light else {
        return None;
    };
    if a.mesh as usize != old.table || own.len() != usize::from(old.quad) {
        return None;
    }
    let mesh = match own.pop() {
        Some(mesh) => Some(mesh?),
        None => None,
    };
    a.mesh = old.ir;
    Some((ir::Light::Area(a), mesh))
}
