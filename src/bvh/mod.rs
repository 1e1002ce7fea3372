//! Acceleration structures: given world geometry (meshes placed by instances), answer
//! closest-hit and any-hit queries for rays.
//!
//! [`Accel`] is the one entry point the renderer uses. [`AccelKind::None`] tests every triangle
//! of every instance (the brute-force oracle that accelerated results are tested against);
//! [`AccelKind::Bvh`] is the fast path: a two-level BVH (one binned-SAH BVH per mesh in object
//! space, a top-level BVH over instances), collapsed into flat 8-wide nodes, traversed nearest
//! child first with a reused stack (the caller's [`Scratch`], or a per-thread one), leaves
//! tested with the watertight ray–triangle test four or eight triangles at a time. The
//! instruction set (portable SSE or AVX2) is chosen at run time, per CPU ([`Simd`]); both give
//! the same bits. See `docs/bvh.md` for the design
//! and measured figures.

mod brute_force;
mod build;
mod check;
mod dispatch;
mod isa;
mod mesh_bvh;
mod node;
mod octant;
mod query;
mod rebuild;
mod slot_hit;
pub mod tally;
mod traverse;
mod two_level;
mod wide;

pub use brute_force::BruteForce;
pub use dispatch::Scratch;
pub use isa::Simd;
pub use node::{MAX_DEPTH, MAX_LEAF};
pub use rebuild::Trace as BuildTrace;
pub use two_level::TwoLevel;

use glam::{Affine3A, Vec3};

use crate::geom::Ray;

/// The triangles of one mesh, in its own object space.
#[derive(Debug, Clone, Copy)]
pub struct MeshRef<'a> {
    /// Vertex positions, object space.
    pub positions: &'a [Vec3],
    /// Triangles as indices into `positions`; one out of range makes its triangle unhittable.
    pub triangles: &'a [[u32; 3]],
}

/// One placement of a mesh.
#[derive(Debug, Clone, Copy)]
pub struct Instance {
    /// Index into the `meshes` given to [`Accel::build`].
    pub mesh: u32,
    /// Maps the mesh's object space to world space.
    pub world_from_object: Affine3A,
    /// The inverse of `world_from_object`, kept to bring world rays into object space.
    pub object_from_world: Affine3A,
}

impl Instance {
    /// Places mesh `mesh` by `world_from_object`, inverting the transform once, here.
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
    /// Ray parameter of the hit, in multiples of the world ray's `dir`.
    pub t: f32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
    /// Index into the `instances` given to [`Accel::build`].
    pub instance: u32,
    /// Index into the `triangles` of that instance's mesh.
    pub prim: u32,
}

/// Which acceleration structure [`Accel::build`] makes (`--accel`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccelKind {
    /// No acceleration structure: every ray tests every triangle.
    None,
    /// The two-level, 8-wide BVH: the fast path.
    Bvh,
}

/// Which ray–triangle test the BVH runs (the brute-force oracle always runs Möller–Trumbore).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TriangleTest {
    /// The reference formulation; may let a ray slip through a shared edge by rounding.
    MollerTrumbore,
    /// Woop, Benthin & Wald 2013: no ray passes between triangles that share an edge.
    #[default]
    Watertight,
}

/// Counts reported by `--stats`. For the BVH, `nodes` counts 8-wide nodes and `leaves` their
/// leaf children, `triangles` counts each mesh once (instances share it), and `bytes` is
/// everything the structure holds: nodes, leaf-ordered vertices, triangle ids and instances.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AccelStats {
    /// 8-wide nodes over both levels; 0 for brute force.
    pub nodes: usize,
    /// Non-empty leaf children of those nodes; 0 for brute force.
    pub leaves: usize,
    /// Triangles stored: the BVH counts each mesh once, brute force each placed copy.
    pub triangles: usize,
    /// Memory the structure holds, in bytes.
    pub bytes: usize,
    /// The part of `bytes` that grows with each placement: for the BVH its top level (placement
    /// records, top-level nodes and leaf order), meshes counted once however often placed; for
    /// brute force everything, as each placement is a world-space copy.
    pub instance_bytes: usize,
}

/// The acceleration structure over a whole scene.
#[derive(Debug)]
pub enum Accel {
    /// Every ray against every world-space triangle (`--accel none`): the test oracle.
    None(BruteForce),
    /// The two-level BVH.
    Bvh(TwoLevel),
}

impl Accel {
    /// Builds the structure of `kind` with the default (watertight) triangle test. Meshes no
    /// instance places cost nothing; triangles with non-finite vertices or out-of-range indices
    /// and instances naming a missing mesh are skipped, never a panic.
    pub fn build(meshes: &[MeshRef<'_>], instances: &[Instance], kind: AccelKind) -> Accel {
        Accel::build_with(meshes, instances, kind, TriangleTest::default())
    }

    /// [`Accel::build`] with a chosen triangle test for the BVH (benchmarks compare both).
    pub fn build_with(
        meshes: &[MeshRef<'_>],
        instances: &[Instance],
        kind: AccelKind,
        test: TriangleTest,
    ) -> Accel {
        match kind {
            AccelKind::None => Accel::None(BruteForce::build(meshes, instances)),
            AccelKind::Bvh => {
                let bvh = TwoLevel::build(meshes, instances, test);
                debug_assert_eq!(check::check_two_level(&bvh, meshes), Ok(()));
                Accel::Bvh(bvh)
            }
        }
    }

    /// [`Accel::build`] for a scene rebuilt after an edit: the BVH's top level reuses the
    /// subtrees of the `earlier` build (its trace) over unchanged instances, the structure
    /// being the same as [`Accel::build`]'s bit for bit; also the trace of this build (`None`
    /// for brute force).
    pub fn build_reusing(
        meshes: &[MeshRef<'_>],
        instances: &[Instance],
        kind: AccelKind,
        earlier: Option<&BuildTrace>,
    ) -> (Accel, Option<BuildTrace>) {
        match kind {
            AccelKind::None => (Accel::None(BruteForce::build(meshes, instances)), None),
            AccelKind::Bvh => {
                let test = TriangleTest::default();
                let (bvh, trace) = TwoLevel::build_traced(meshes, instances, test, earlier);
                debug_assert_eq!(check::check_two_level(&bvh, meshes), Ok(()));
                (Accel::Bvh(bvh), Some(trace))
            }
        }
    }

    /// The nearest hit with `0 < t < ray.t_max` (`ray` in world space), if any.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Accel::None(b) => b.closest_hit(ray),
            Accel::Bvh(b) => b.closest_hit(ray),
        }
    }

    /// [`Accel::closest_hit`] on the caller's traversal stacks (the same hit; no thread-local
    /// lookup per query): for callers that make many queries on one thread.
    #[inline]
    pub fn closest_hit_with(&self, ray: &Ray, scratch: &mut Scratch) -> Option<Hit> {
        match self {
            Accel::None(b) => b.closest_hit(ray),
            Accel::Bvh(b) => b.closest_hit_with(ray, scratch),
        }
    }

    /// Whether anything is hit with `0 < t < ray.t_max`; stops at the first hit found.
    #[inline]
    pub fn any_hit(&self, ray: &Ray) -> bool {
        match self {
            Accel::None(b) => b.any_hit(ray),
            Accel::Bvh(b) => b.any_hit(ray),
        }
    }

    /// [`Accel::any_hit`] on the caller's traversal stacks.
    #[inline]
    pub fn any_hit_with(&self, ray: &Ray, scratch: &mut Scratch) -> bool {
        match self {
            Accel::None(b) => b.any_hit(ray),
            Accel::Bvh(b) => b.any_hit_with(ray, scratch),
        }
    }

    /// Sizes for `--stats`.
    pub fn stats(&self) -> AccelStats {
        match self {
            Accel::None(b) => b.stats(),
            Accel::Bvh(b) => b.stats(),
        }
    }

    /// The instruction set the queries run on (brute force: always the portable one).
    pub fn simd(&self) -> Simd {
        match self {
            Accel::None(_) => Simd::Portable,
            Accel::Bvh(b) => b.simd(),
        }
    }

    /// Makes the queries run on `simd` (tests and benchmarks compare the paths); `false`, and
    /// nothing changed, if this CPU cannot run it or the structure has no such path.
    pub fn force_simd(&mut self, simd: Simd) -> bool {
        match self {
            Accel::None(_) => simd == Simd::Portable,
            Accel::Bvh(b) => b.force_simd(simd),
        }
    }

    /// Checks the structure's invariants against the input it was built from (the meshes must
    /// be the ones given to `build`). The brute-force structure has none to check.
    pub fn check_invariants(&self, meshes: &[MeshRef<'_>]) -> Result<(), String> {
        match self {
            Accel::None(_) => Ok(()),
            Accel::Bvh(b) => check::check_two_level(b, meshes),
        }
    }
}

#[cfg(test)]
mod tests;
