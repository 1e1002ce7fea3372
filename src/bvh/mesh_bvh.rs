//! The bottom level: one BVH per mesh, in the mesh's object space, with the triangles' vertices
//! copied in leaf order (48 bytes each, aligned, read sequentially by a leaf) beside their
//! original indices. Triangles with a non-finite vertex or an out-of-range index are left out at build.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::build::{build, Built, PrimBox, PrimRef};
use super::wide::{collapse, traverse4, Wide, WideNode, WideRay};
use super::MeshRef;
use crate::geom::triangle::{moller_trumbore, watertight_a, TriangleHit, WatertightRay};
use crate::geom::{Aabb, Ray};

/// The two ray–triangle tests, chosen once per query so each traversal loop is monomorphic
/// (a private trait for static dispatch; the public choice is the `TriangleTest` enum).
pub trait TriTest {
    /// Per-ray constants, computed once per query.
    type Prepared: Copy;
    /// Computes the per-ray constants of `ray`.
    fn prepare(ray: &Ray) -> Self::Prepared;
    /// The hit on `tri` with `0 < t < t_max`, if any.
    fn test(pre: &Self::Prepared, t_max: f32, tri: &Tri) -> Option<TriangleHit>;
}

/// [`TriTest`] running [`moller_trumbore`].
pub struct MollerTrumbore;
/// [`TriTest`] running the watertight test ([`watertight_a`]).
pub struct Watertight;

impl TriTest for MollerTrumbore {
    type Prepared = Ray;
    #[inline(always)]
    fn prepare(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn test(ray: &Ray, t_max: f32, [p0, p1, p2]: &Tri) -> Option<TriangleHit> {
        moller_trumbore(
            &Ray { t_max, ..*ray },
            (*p0).into(),
            (*p1).into(),
            (*p2).into(),
        )
    }
}

impl TriTest for Watertight {
    type Prepared = WatertightRay;
    #[inline(always)]
    fn prepare(ray: &Ray) -> WatertightRay {
        WatertightRay::new(ray)
    }
    #[inline(always)]
    fn test(ray: &WatertightRay, t_max: f32, [p0, p1, p2]: &Tri) -> Option<TriangleHit> {
        let mut r = *ray;
        r.t_max = t_max;
        watertight_a(&r, *p0, *p1, *p2)
    }
}

/// A triangle's vertices as stored in leaf order: 16-byte aligned for single-load SIMD use.
pub type Tri = [Vec3A; 3];

/// A closest hit inside one bottom-level BVH: triangle `prim` of its mesh number `part`.
#[derive(Debug, Clone, Copy)]
pub struct MeshHit {
    /// Which of the parts given to [`MeshBvh::build`] the triangle belongs to.
    pub part: u32,
    /// Index into that part's `triangles`.
    pub prim: u32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
}

/// A bottom-level BVH over the triangles of one or more meshes, in their object space.
#[derive(Debug, Default)]
pub struct MeshBvh {
    pub(super) tree: Wide,
    /// Vertices of the leaf-ordered triangles.
    pub(super) tris: Vec<Tri>,
    /// `ids[k]`: which triangle `tris[k]` is, numbered across the parts in order.
    pub(super) ids: Vec<u32>,
    /// Where each part's numbering starts (one entry per part, ascending).
    pub(super) part_starts: Vec<u32>,
}

/// The vertices of triangle `t`, or `None` if an index is out of range or a vertex not finite.
pub fn triangle_vertices(mesh: &MeshRef<'_>, t: &[u32; 3]) -> Option<[Vec3; 3]> {
    let v = |k: usize| {
        mesh.positions
            .get(t[k] as usize)
            .copied()
            .filter(|p| p.is_finite())
    };
    Some([v(0)?, v(1)?, v(2)?])
}

/// The vertices of a triangle the builder ordered: [`MeshBvh::build`] gave the builder only
/// triangles whose [`triangle_vertices`] is `Some`, and the mesh has not changed since.
#[allow(
    clippy::expect_used,
    reason = "build() hands the builder only triangles whose triangle_vertices is Some, and \
              the builder's order holds only those ids"
)]
fn builder_vertices(mesh: &MeshRef<'_>, t: &[u32; 3]) -> [Vec3; 3] {
    triangle_vertices(mesh, t)
        .expect("only triangles with valid vertices were given to the builder")
}

impl MeshBvh {
    /// One BVH over the triangles of `parts` (usually one mesh; several meshes when identity
    /// instances are merged, each placed once, so nothing is duplicated).
    ///
    /// Temporaries are dropped as soon as the next step no longer needs them, so that the peak
    /// during the build (32-byte primitive references and 32-byte binary nodes, about 60 bytes per triangle)
    /// stays below the size of the result (about 90).
    pub fn build(parts: &[MeshRef<'_>]) -> MeshBvh {
        let total: usize = parts.iter().map(|m| m.triangles.len()).sum();
        let mut refs = Vec::with_capacity(total);
        let mut part_starts = Vec::with_capacity(parts.len());
        let mut id = 0u32;
        for mesh in parts {
            part_starts.push(id);
            for t in mesh.triangles {
                if let Some(tri) = triangle_vertices(mesh, t) {
                    let [a, b, c] = tri.map(Vec3A::from);
                    let bounds = PrimBox {
                        min: a.min(b).min(c),
                        max: a.max(b).max(c),
                    };
                    refs.push(PrimRef::new(bounds, id));
                }
                id += 1;
            }
        }
        let Built { nodes, order } = build(refs);
        let tree = collapse(&nodes);
        drop(nodes);
        let mut bvh = MeshBvh {
            tree,
            tris: Vec::new(),
            ids: order,
            part_starts,
        };
        bvh.tris = bvh
            .ids
            .par_iter()
            .map(|&id| {
                let (part, prim) = bvh.locate(id);
                let mesh = &parts[part as usize];
                builder_vertices(mesh, &mesh.triangles[prim as usize]).map(Vec3A::from)
            })
            .collect();
        bvh
    }

    /// The part and the triangle within it of global id `id`.
    pub(super) fn locate(&self, id: u32) -> (u32, u32) {
        let part = self
            .part_starts
            .partition_point(|&s| s <= id)
            .saturating_sub(1);
        (part as u32, id - self.part_starts[part])
    }

    /// Whether it holds no triangle (there were none, or none was valid).
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// Bounds of its triangles, object space; empty when it holds none.
    pub fn bounds(&self) -> Aabb {
        self.tree.root_bounds.unwrap_or(Aabb::EMPTY)
    }

    /// Memory it holds, in bytes, for `--stats`.
    pub fn bytes(&self) -> usize {
        self.tree.nodes.len() * std::mem::size_of::<WideNode>()
            + self.tris.len() * std::mem::size_of::<Tri>()
            + self.ids.len() * 4
            + self.part_starts.len() * 4
    }

    /// Closest hit with `t < *t_max` (in units of `ray.dir`); shrinks `*t_max` when found.
    #[inline]
    pub fn closest<T: TriTest>(&self, ray: &Ray, t_max: &mut f32) -> Option<MeshHit> {
        let wr = WideRay::new(ray);
        let pre = T::prepare(ray);
        let mut best = None;
        traverse4(&self.tree, &wr, t_max, |first, count, t_max| {
            let range = first as usize..(first + count) as usize;
            for (k, tri) in self.tris[range.clone()].iter().enumerate() {
                if let Some(h) = T::test(&pre, *t_max, tri) {
                    *t_max = h.t;
                    // The slot, not the id: `ids` is read once, for the final hit only.
                    best = Some((range.start + k, h.u, h.v));
                }
            }
            false
        });
        best.map(|(slot, u, v)| {
            let (part, prim) = self.locate(self.ids[slot]);
            MeshHit { part, prim, u, v }
        })
    }

    /// Whether anything is hit with `t < t_max`; stops at the first hit found.
    #[inline]
    pub fn any<T: TriTest>(&self, ray: &Ray, t_max: f32) -> bool {
        let wr = WideRay::new(ray);
        let pre = T::prepare(ray);
        let mut t = t_max;
        traverse4(&self.tree, &wr, &mut t, |first, count, t_max| {
            let range = first as usize..(first + count) as usize;
            self.tris[range]
                .iter()
                .any(|tri| T::test(&pre, *t_max, tri).is_some())
        })
    }
}
