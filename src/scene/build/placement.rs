//! Stage 3, build: where the placed geometry is, for the world origin (`origin.rs`), and the
//! warning for an object f32 cannot place precisely even relative to that origin.
//!
//! Syntax: any `object` or area `light` placing a mesh (`object ball { transform { … } }`).

use glam::{DVec3, Vec3};

use super::origin::{placed_bounds, resolution, world_origin};
use super::Builder;
use crate::ir;
use crate::scene::BuildError;

/// An object whose smallest f32 step is above this fraction of its size is reported (about a
/// thousand steps across it, where the renderer's own tolerances start to show).
const WARN_FRACTION: f64 = 1.0 / 1024.0;

impl Builder<'_> {
    /// Loads the meshes of every object and area light and picks the world origin from where
    /// they are placed (the transforms in f64).
    pub(super) fn world_origin(&mut self) -> DVec3 {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let placements: Vec<(ir::MeshId, glam::DMat4)> = (self.desc.objects.iter())
            .map(|o| (o.mesh, o.world_from_object))
            .chain(self.desc.lights.iter().filter_map(|l| match l {
                ir::Light::Area(a) => Some((a.mesh, a.world_from_object)),
                _ => None,
            }))
            .collect();
        for (id, m) in placements {
            let Some(mesh) = self.mesh(id) else { continue };
            let Some((b_lo, b_hi)) = self
                .mesh_bounds(mesh)
                .and_then(|(l, h)| placed_bounds(l, h, m))
            else {
                continue;
            };
            lo = lo.min(b_lo);
            hi = hi.max(b_hi);
        }
        world_origin(lo, hi)
    }

    /// Object-space bounds of loaded mesh `mesh` (`None` if it has no positions), computed
    /// once per mesh.
    fn mesh_bounds(&mut self, mesh: u32) -> Option<(Vec3, Vec3)> {
        let i = mesh as usize;
        if let Some(Some(known)) = self.mesh_bounds.get(i) {
            return *known;
        }
        let positions = &self.meshes.get(i)?.positions;
        let lo = positions.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
        let hi = positions.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
        let bounds = lo.cmple(hi).all().then_some((lo, hi));
        if self.mesh_bounds.len() <= i {
            self.mesh_bounds.resize(i + 1, None);
        }
        self.mesh_bounds[i] = Some(bounds);
        bounds
    }

    /// Warns when a placement of loaded mesh `mesh` (IR mesh `id`, by `world_from_object`, at
    /// `span`: an object or an area light) cannot be resolved to a thousandth of its size in
    /// f32, relative to the world origin.
    pub(super) fn check_resolution(
        &mut self,
        id: ir::MeshId,
        world_from_object: glam::DMat4,
        span: crate::source::Span,
        mesh: u32,
    ) {
        let Some((lo, hi)) = self.mesh_bounds(mesh) else {
            return;
        };
        let Some((step, size)) = resolution(lo, hi, world_from_object, self.origin) else {
            return;
        };
        if size > 0.0 && step > WARN_FRACTION * size {
            let name = self.desc.meshes.get(id as usize);
            self.problems.push(BuildError::PrecisionLost {
                mesh: name.map(|m| m.name.clone()).unwrap_or_default(),
                step,
                size,
                span,
            });
        }
    }
}
