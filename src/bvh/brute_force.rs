//! The brute-force oracle: every ray against every triangle of every instance, in world space.
//! Slow by design and simple enough to trust; `--accel none` renders with it.

use glam::Vec3;

use super::{AccelStats, Hit, Instance, MeshRef};
use crate::geom::triangle::moller_trumbore;
use crate::geom::Ray;

/// World-space triangles, with the instance and primitive index each came from.
#[derive(Debug, Default)]
pub struct BruteForce {
    triangles: Vec<[Vec3; 3]>,
    origin: Vec<(u32, u32)>,
}

impl BruteForce {
    /// Every placed triangle, transformed to world space. An instance naming a missing mesh
    /// is skipped; an out-of-range vertex index becomes a NaN corner, which no ray hits.
    pub fn build(meshes: &[MeshRef<'_>], instances: &[Instance]) -> BruteForce {
        let mut out = BruteForce::default();
        for (i, inst) in instances.iter().enumerate() {
            let Some(mesh) = meshes.get(inst.mesh as usize) else {
                debug_assert!(false, "instance {i} names a missing mesh");
                continue;
            };
            for (p, tri) in mesh.triangles.iter().enumerate() {
                let corner = |k: usize| {
                    let v = mesh
                        .positions
                        .get(tri[k] as usize)
                        .copied()
                        .unwrap_or(Vec3::NAN);
                    inst.world_from_object.transform_point3(v)
                };
                out.triangles.push([corner(0), corner(1), corner(2)]);
                out.origin.push((i as u32, p as u32));
            }
        }
        out
    }

    /// The nearest hit with `0 < t < ray.t_max`, testing every triangle.
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut ray = *ray;
        let mut best = None;
        for (k, [p0, p1, p2]) in self.triangles.iter().enumerate() {
            if let Some(h) = moller_trumbore(&ray, *p0, *p1, *p2) {
                ray.t_max = h.t;
                let (instance, prim) = self.origin[k];
                best = Some(Hit {
                    t: h.t,
                    u: h.u,
                    v: h.v,
                    instance,
                    prim,
                });
            }
        }
        best
    }

    /// Whether any triangle is hit with `0 < t < ray.t_max`.
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.triangles
            .iter()
            .any(|[p0, p1, p2]| moller_trumbore(ray, *p0, *p1, *p2).is_some())
    }

    /// Counts for `--stats`: no nodes, one entry per placed triangle.
    pub fn stats(&self) -> AccelStats {
        let bytes = self.triangles.len() * (std::mem::size_of::<[Vec3; 3]>() + 8);
        AccelStats {
            nodes: 0,
            leaves: 0,
            triangles: self.triangles.len(),
            bytes,
            instance_bytes: bytes,
        }
    }
}
