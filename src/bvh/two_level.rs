//! The two-level BVH: a top-level BVH over instances (world bounds = the transformed bounds of
//! their mesh's BVH) whose leaves send the ray, mapped into object space, into the one shared
//! bottom-level BVH of the instance's mesh. Meshes are never copied per instance. The object
//! ray's direction is transformed without renormalising, so `t` means the same point in both
//! spaces and one `t_max` serves the whole query.

use glam::{Affine3A, Vec3A};
use rayon::prelude::*;

use super::build::{build, PrimBox};
use super::mesh_bvh::{MeshBvh, MollerTrumbore, TriTest, Watertight};
use super::wide::{collapse, traverse4, Wide, WideNode, WideRay};
use super::{AccelStats, Hit, Instance, MeshRef, TriangleTest};
use crate::geom::{Aabb, Ray};

/// An instance that survived validation (its mesh exists and has triangles, its transform is
/// finite and invertible).
#[derive(Debug, Clone, Copy)]
pub(super) struct Placed {
    pub mesh: u32,
    /// Index in the caller's instance list, reported in hits.
    pub index: u32,
    pub object_from_world: Affine3A,
    /// Skip the ray transform (the common single-instance case).
    pub identity: bool,
    pub world_bounds: Aabb,
}

#[derive(Debug)]
pub struct TwoLevel {
    pub(super) meshes: Vec<MeshBvh>,
    pub(super) placed: Vec<Placed>,
    pub(super) top: Wide,
    /// Leaf order of the top level: indices into `placed`.
    pub(super) top_order: Vec<u32>,
    test: TriangleTest,
}

fn finite_affine(m: &Affine3A) -> bool {
    m.matrix3.is_finite() && m.translation.is_finite()
}

impl TwoLevel {
    pub fn build(meshes: &[MeshRef<'_>], instances: &[Instance], test: TriangleTest) -> TwoLevel {
        let mut used = vec![false; meshes.len()];
        for inst in instances {
            if let Some(u) = used.get_mut(inst.mesh as usize) {
                *u = true;
            }
        }
        // Only meshes some instance places are built; each one once, however often placed.
        let bvhs: Vec<MeshBvh> = meshes
            .par_iter()
            .zip(used.par_iter())
            .map(|(m, &u)| {
                if u {
                    MeshBvh::build(m)
                } else {
                    MeshBvh::default()
                }
            })
            .collect();
        let placed: Vec<Placed> = instances
            .iter()
            .enumerate()
            .filter_map(|(i, inst)| {
                let bvh = bvhs.get(inst.mesh as usize)?;
                let ok = !bvh.is_empty()
                    && finite_affine(&inst.world_from_object)
                    && finite_affine(&inst.object_from_world);
                let world_bounds = bvh.bounds().transformed(&inst.world_from_object);
                (ok && world_bounds.min.is_finite() && world_bounds.max.is_finite()).then(|| {
                    Placed {
                        mesh: inst.mesh,
                        index: i as u32,
                        object_from_world: inst.object_from_world,
                        identity: inst.world_from_object == Affine3A::IDENTITY
                            && inst.object_from_world == Affine3A::IDENTITY,
                        world_bounds,
                    }
                })
            })
            .collect();
        let boxes: Vec<PrimBox> = placed
            .iter()
            .map(|p| PrimBox {
                min: Vec3A::from(p.world_bounds.min),
                max: Vec3A::from(p.world_bounds.max),
            })
            .collect();
        let top = build(&boxes, (0..placed.len() as u32).collect());
        TwoLevel {
            meshes: bvhs,
            placed,
            top: collapse(&top.nodes),
            top_order: top.order,
            test,
        }
    }

    #[inline(always)]
    fn object_ray(p: &Placed, ray: &Ray) -> Ray {
        if p.identity {
            *ray
        } else {
            Ray {
                origin: p.object_from_world.transform_point3(ray.origin),
                dir: p.object_from_world.transform_vector3(ray.dir),
                t_max: ray.t_max,
            }
        }
    }

    fn closest_with<T: TriTest>(&self, ray: &Ray) -> Option<Hit> {
        let wr = WideRay::new(ray);
        let mut t_max = ray.t_max;
        let mut best = None;
        traverse4(&self.top, &wr, &mut t_max, |first, count, t_max| {
            for &k in &self.top_order[first as usize..(first + count) as usize] {
                let p = &self.placed[k as usize];
                let obj = Self::object_ray(p, ray);
                if let Some(h) = self.meshes[p.mesh as usize].closest::<T>(&obj, t_max) {
                    best = Some(Hit {
                        t: *t_max,
                        u: h.u,
                        v: h.v,
                        instance: p.index,
                        prim: h.prim,
                    });
                }
            }
            false
        });
        best
    }

    fn any_with<T: TriTest>(&self, ray: &Ray) -> bool {
        let wr = WideRay::new(ray);
        let mut t_max = ray.t_max;
        traverse4(&self.top, &wr, &mut t_max, |first, count, t_max| {
            self.top_order[first as usize..(first + count) as usize]
                .iter()
                .any(|&k| {
                    let p = &self.placed[k as usize];
                    let obj = Self::object_ray(p, ray);
                    self.meshes[p.mesh as usize].any::<T>(&obj, *t_max)
                })
        })
    }

    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        if !(ray.origin.is_finite() && ray.dir.is_finite()) || ray.t_max.is_nan() {
            return None;
        }
        match self.test {
            TriangleTest::MollerTrumbore => self.closest_with::<MollerTrumbore>(ray),
            TriangleTest::Watertight => self.closest_with::<Watertight>(ray),
        }
    }

    pub fn any_hit(&self, ray: &Ray) -> bool {
        if !(ray.origin.is_finite() && ray.dir.is_finite()) || ray.t_max.is_nan() {
            return false;
        }
        match self.test {
            TriangleTest::MollerTrumbore => self.any_with::<MollerTrumbore>(ray),
            TriangleTest::Watertight => self.any_with::<Watertight>(ray),
        }
    }

    pub fn stats(&self) -> AccelStats {
        let leaves = |w: &Wide| {
            let inner: usize = w
                .nodes
                .iter()
                .map(|n| n.count.iter().filter(|&&c| c > 0).count())
                .sum();
            inner + usize::from(w.root_count > 0)
        };
        let mut s = AccelStats {
            nodes: self.top.nodes.len(),
            leaves: leaves(&self.top),
            triangles: 0,
            bytes: self.top.nodes.len() * std::mem::size_of::<WideNode>()
                + self.top_order.len() * 4
                + self.placed.len() * std::mem::size_of::<Placed>(),
        };
        for m in &self.meshes {
            s.nodes += m.tree.nodes.len();
            s.leaves += leaves(&m.tree);
            s.triangles += m.tris.len();
            s.bytes += m.bytes();
        }
        s
    }
}
