//! The bottom level: one BVH per mesh, in the mesh's object space, with the triangles' vertices
//! copied in leaf order (36 bytes each, read sequentially by a leaf) beside their original
//! indices. Triangles with a non-finite vertex or an out-of-range index are left out at build.

use glam::{Vec3, Vec3A};

use super::build::{build, Built, PrimBox};
use super::wide::{collapse, traverse4, Wide, WideNode, WideRay};
use super::MeshRef;
use crate::geom::triangle::{moller_trumbore, watertight, TriangleHit, WatertightRay};
use crate::geom::{Aabb, Ray};

/// The two ray–triangle tests, chosen once per query so each traversal loop is monomorphic
/// (a private trait for static dispatch; the public choice is the `TriangleTest` enum).
pub trait TriTest {
    type Prepared: Copy;
    fn prepare(ray: &Ray) -> Self::Prepared;
    fn test(pre: &Self::Prepared, t_max: f32, tri: &[Vec3; 3]) -> Option<TriangleHit>;
}

pub struct MollerTrumbore;
pub struct Watertight;

impl TriTest for MollerTrumbore {
    type Prepared = Ray;
    #[inline(always)]
    fn prepare(ray: &Ray) -> Ray {
        *ray
    }
    #[inline(always)]
    fn test(ray: &Ray, t_max: f32, [p0, p1, p2]: &[Vec3; 3]) -> Option<TriangleHit> {
        moller_trumbore(&Ray { t_max, ..*ray }, *p0, *p1, *p2)
    }
}

impl TriTest for Watertight {
    type Prepared = WatertightRay;
    #[inline(always)]
    fn prepare(ray: &Ray) -> WatertightRay {
        WatertightRay::new(ray)
    }
    #[inline(always)]
    fn test(ray: &WatertightRay, t_max: f32, [p0, p1, p2]: &[Vec3; 3]) -> Option<TriangleHit> {
        let mut r = *ray;
        r.t_max = t_max;
        watertight(&r, *p0, *p1, *p2)
    }
}

/// A closest hit inside one mesh.
#[derive(Debug, Clone, Copy)]
pub struct MeshHit {
    pub prim: u32,
    pub u: f32,
    pub v: f32,
}

#[derive(Debug, Default)]
pub struct MeshBvh {
    pub(super) tree: Wide,
    /// Vertices of the leaf-ordered triangles.
    pub(super) tris: Vec<[Vec3; 3]>,
    /// `prims[k]`: index in the mesh of `tris[k]`.
    pub(super) prims: Vec<u32>,
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

impl MeshBvh {
    pub fn build(mesh: &MeshRef<'_>) -> MeshBvh {
        let mut boxes = Vec::with_capacity(mesh.triangles.len());
        let mut refs = Vec::with_capacity(mesh.triangles.len());
        for (i, t) in mesh.triangles.iter().enumerate() {
            let Some([a, b, c]) = triangle_vertices(mesh, t) else {
                boxes.push(PrimBox {
                    min: Vec3A::ZERO,
                    max: Vec3A::ZERO,
                });
                continue;
            };
            let (a, b, c) = (Vec3A::from(a), Vec3A::from(b), Vec3A::from(c));
            boxes.push(PrimBox {
                min: a.min(b).min(c),
                max: a.max(b).max(c),
            });
            refs.push(i as u32);
        }
        let Built { nodes, order } = build(&boxes, refs);
        let tris = order
            .iter()
            .map(|&p| {
                triangle_vertices(mesh, &mesh.triangles[p as usize])
                    .expect("only triangles with valid vertices were given to the builder")
            })
            .collect();
        MeshBvh {
            tree: collapse(&nodes),
            tris,
            prims: order,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    pub fn bounds(&self) -> Aabb {
        self.tree.root_bounds.unwrap_or(Aabb::EMPTY)
    }

    pub fn bytes(&self) -> usize {
        self.tree.nodes.len() * std::mem::size_of::<WideNode>()
            + self.tris.len() * std::mem::size_of::<[Vec3; 3]>()
            + self.prims.len() * 4
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
                    best = Some(MeshHit {
                        prim: self.prims[range.start + k],
                        u: h.u,
                        v: h.v,
                    });
                }
            }
            false
        });
        best
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
