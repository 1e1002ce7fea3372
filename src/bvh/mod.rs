//! Acceleration structures: given world geometry (meshes placed by instances), answer
//! closest-hit and any-hit queries for rays.
//!
//! [`Accel`] is the one entry point the renderer uses. [`AccelKind::None`] tests every triangle
//! of every instance (the brute-force oracle that accelerated results are tested against);
//! [`AccelKind::Bvh`] is the fast path.

mod brute_force;

pub use brute_force::BruteForce;

use glam::{Affine3A, Vec3};

use crate::geom::Ray;

/// The triangles of one mesh, in its own object space.
#[derive(Debug, Clone, Copy)]
pub struct MeshRef<'a> {
    pub positions: &'a [Vec3],
    pub triangles: &'a [[u32; 3]],
}

/// One placement of a mesh.
#[derive(Debug, Clone, Copy)]
pub struct Instance {
    pub mesh: u32,
    pub world_from_object: Affine3A,
    pub object_from_world: Affine3A,
}

impl Instance {
    pub fn new(mesh: u32, world_from_object: Affine3A) -> Instance {
        Instance {
            mesh,
            world_from_object,
            object_from_world: world_from_object.inverse(),
        }
    }
}

/// The closest intersection along a ray. `t` is in units of the world ray's `dir`;
/// `(u, v)` are the barycentrics of `triangles[prim]` of the instance's mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
    pub instance: u32,
    pub prim: u32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelKind {
    /// No acceleration structure: every ray tests every triangle.
    None,
    Bvh,
}

/// Counts reported by `--stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AccelStats {
    pub nodes: usize,
    pub leaves: usize,
    pub triangles: usize,
    pub bytes: usize,
}

/// The acceleration structure over a whole scene.
#[derive(Debug)]
pub enum Accel {
    None(BruteForce),
}

impl Accel {
    pub fn build(meshes: &[MeshRef<'_>], instances: &[Instance], kind: AccelKind) -> Accel {
        match kind {
            // The BVH lands separately; until then both kinds trace by brute force.
            AccelKind::None | AccelKind::Bvh => Accel::None(BruteForce::build(meshes, instances)),
        }
    }

    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::None(b) => b.closest_hit(ray),
        }
    }

    pub fn any_hit(&self, ray: &Ray) -> bool {
        match self {
            Accel::None(b) => b.any_hit(ray),
        }
    }

    pub fn stats(&self) -> AccelStats {
        match self {
            Accel::None(b) => b.stats(),
        }
    }
}
