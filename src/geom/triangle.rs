//! Ray–triangle intersection.
//!
//! [`moller_trumbore`] is the reference formulation from the course material
//! (`s1 = d × e2`, `s2 = s × e1`, with `s = o − p0`). [`watertight`] is the test of Woop, Benthin
//! and Wald (2013, "Watertight Ray/Triangle Intersection"): it shears the triangle into a space
//! where the ray is the +z axis and evaluates the 2D edge functions there, so two triangles that
//! share an edge decide a ray on that edge consistently and it cannot slip between them. Tests
//! prove the two agree away from edges, and that the watertight test closes every crack.

use glam::{Mat3A, Vec3, Vec3A};

use super::Ray;

/// Where a ray meets a triangle: `p = (1 − u − v)·p0 + u·p1 + v·p2` at parameter `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter of the hit, in multiples of the ray's `dir`; `0 < t < t_max`.
    pub t: f32,
    /// Barycentric weight of `p1`.
    pub u: f32,
    /// Barycentric weight of `p2`.
    pub v: f32,
}

/// Möller–Trumbore: solves `o + t·d = p0 + u·e1 + v·e2` by Cramer's rule.
/// Returns a hit with `0 < t < ray.t_max`, `u ≥ 0`, `v ≥ 0`, `u + v ≤ 1`; both faces count.
#[inline]
pub fn moller_trumbore(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriangleHit> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let s1 = ray.dir.cross(e2);
    let det = s1.dot(e1);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - p0;
    let u = s.dot(s1) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let s2 = s.cross(e1);
    let v = ray.dir.dot(s2) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(s2) * inv_det;
    if t > 0.0 && t < ray.t_max {
        Some(TriangleHit { t, u, v })
    } else {
        None
    }
}

/// Per-ray constants of the watertight test: the axis permutation that makes `dir`'s largest
/// component the z axis, and the shear that maps `dir` onto +z, as one matrix (`kx`, `ky`, `kz`
/// as in the paper): rows `e_kx − Sx·e_kz`, `e_ky − Sy·e_kz`, `Sz·e_kz`. Each row has two zeros,
/// so `M·a` rounds exactly as the paper's `a[kx] − Sx·a[kz]` (adding a product with 0 is exact)
/// while needing no run-time indexing. Computed once per ray (or per instance, for the
/// object-space ray) and reused for every triangle.
#[derive(Debug, Clone, Copy)]
pub struct WatertightRay {
    /// The ray's origin, unsheared: vertices are made relative to it before the shear.
    pub origin: Vec3A,
    /// The ray's `t_max`, in multiples of its `dir`.
    pub t_max: f32,
    /// The origin's coordinates on the axes `kx`, `ky`, `kz` (in that order): the eight-lane
    /// test reads them at fixed places, once per ray, instead of indexing by axis at every
    /// leaf (where the AVX2 kernel broadcast and spilled them anew each time).
    pub(crate) origin_k: [f32; 3],
    /// `kx`, `ky`, `kz`: which axes become the sheared x, y and z (for the four-wide test,
    /// which permutes rows instead of multiplying by `shear`).
    pub(crate) axes: [usize; 3],
    /// `Sx`, `Sy`, `Sz` of the paper (the entries of `shear` that are not 0 or 1).
    pub(crate) shear_factors: [f32; 3],
    /// `|dir|`, exactly 1 for (nearly) unit directions: turns the sheared `z` (in units of
    /// `t`) back into a length for the error bound of the sheared `x` and `y`.
    pub(crate) dir_length: f32,
}

impl WatertightRay {
    /// Precomputes the axis permutation and shear for `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> WatertightRay {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let dz = [d.x, d.y, d.z][kz];
        // Keep the winding of the permuted space the same as the original one.
        let (kx, ky) = if dz < 0.0 {
            ((kz + 2) % 3, (kz + 1) % 3)
        } else {
            ((kz + 1) % 3, (kz + 2) % 3)
        };
        let dv = [d.x, d.y, d.z];
        // One division for the three factors (the same bits as three `divss`).
        let [sx, sy, sz] = (Vec3A::new(dv[kx], dv[ky], 1.0) / dz).to_array();
        // Camera, shadow and BRDF rays are unit length up to rounding; keeping exactly 1 for
        // them keeps pbrt's bound (and every image) bit for bit. Object-space rays of scaled
        // instances are not: their `t` is in units of a `dir` that may be 1e-6 or 1e6 long.
        let length = d.length();
        let dir_length = if (length - 1.0).abs() < 1e-5 {
            1.0
        } else {
            length
        };
        WatertightRay {
            origin: ray.origin.into(),
            t_max: ray.t_max,
            origin_k: {
                let o = ray.origin.to_array();
                [o[kx], o[ky], o[kz]]
            },
            axes: [kx, ky, kz],
            shear_factors: [sx, sy, sz],
            dir_length,
        }
    }

    /// The shear as one matrix, for the one-triangle test: rows `e_kx − Sx·e_kz`,
    /// `e_ky − Sy·e_kz`, `Sz·e_kz` (their zero entries stay exact zeros). Built on demand: the
    /// BVH's packet tests permute rows instead, and building it for every ray was about 5% of
    /// a primary ray's instructions.
    fn shear(&self) -> Mat3A {
        const AXES: [Vec3A; 3] = [Vec3A::X, Vec3A::Y, Vec3A::Z];
        let [kx, ky, kz] = self.axes;
        let [sx, sy, sz] = self.shear_factors;
        let rows = [
            AXES[kx] - sx * AXES[kz],
            AXES[ky] - sy * AXES[kz],
            sz * AXES[kz],
        ];
        Mat3A::from_cols(rows[0], rows[1], rows[2]).transpose()
    }
}

/// The watertight test of Woop, Benthin and Wald (2013). Same contract as [`moller_trumbore`]:
/// `0 < t < t_max`, both faces, `(u, v)` the weights of `p1` and `p2`.
#[inline]
pub fn watertight(r: &WatertightRay, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriangleHit> {
    watertight_a(r, p0.into(), p1.into(), p2.into())
}

/// [`watertight`] on 16-byte-aligned vertices (as the BVH stores them).
#[inline]
pub fn watertight_a(r: &WatertightRay, p0: Vec3A, p1: Vec3A, p2: Vec3A) -> Option<TriangleHit> {
    // Vertices relative to the origin, in the sheared space: (x, y) in the plane across the
    // ray, z scaled so that the ray runs from z = 0 to z = t.
    let shear = r.shear();
    let a = shear * (p0 - r.origin);
    let b = shear * (p1 - r.origin);
    let c = shear * (p2 - r.origin);
    let mut u = c.x * b.y - c.y * b.x;
    let mut v = a.x * c.y - a.y * c.x;
    let mut w = b.x * a.y - b.y * a.x;
    // An edge function that rounds to exactly zero is re-evaluated in double precision, which
    // is exact for products of floats: the ray is then decided by the exact sign.
    if u == 0.0 || v == 0.0 || w == 0.0 {
        let (ax, ay, bx, by, cx, cy) = (
            f64::from(a.x),
            f64::from(a.y),
            f64::from(b.x),
            f64::from(b.y),
            f64::from(c.x),
            f64::from(c.y),
        );
        u = (cx * by - cy * bx) as f32;
        v = (ax * cy - ay * cx) as f32;
        w = (bx * ay - by * ax) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let t_scaled = u * a.z + v * b.z + w * c.z;
    // Compare t = t_scaled / det with (0, t_max) without dividing: flip by the sign of det.
    let sign = det.signum();
    let ts = t_scaled * sign;
    let ad = det * sign;
    if ts <= 0.0 || ts >= r.t_max * ad {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t > 0.0 && t < r.t_max) {
        return None;
    }
    // A conservative bound on the rounding error of `t` (pbrt-v4, "Conservative Ray–Bounds
    // Intersections" and §6.8.6): a hit closer than it may be the surface the ray starts on,
    // seen through rounding. Without it, a ray leaving a large triangle near its plane (a shadow
    // ray from a floor) can hit that triangle again, as its edge functions round with the
    // triangle's extent, not with the tiny distance. Only hits that passed every other test
    // pay for it.
    // pbrt adds the sheared z to the error of the sheared x and y, which presumes a unit
    // direction (z is in units of t); scaled by |dir| it is a length again, so the bound holds
    // for the object-space rays of scaled instances too (it rejected every hit of a scene
    // placed with scale 1e6, whose object-space rays are 1e-6 long).
    let max_zt = a.z.abs().max(b.z.abs()).max(c.z.abs());
    let max_xt = a.x.abs().max(b.x.abs()).max(c.x.abs());
    let max_yt = a.y.abs().max(b.y.abs()).max(c.y.abs());
    let delta_z = gamma(3) * max_zt;
    let max_z_length = max_zt * r.dir_length;
    let delta_x = gamma(5) * (max_xt + max_z_length);
    let delta_y = gamma(5) * (max_yt + max_z_length);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = u.abs().max(v.abs()).max(w.abs());
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit {
        t,
        u: v * inv_det,
        v: w * inv_det,
    })
}

/// The bound `n·ε / (1 − n·ε)` on the relative error of `n` rounded float operations.
#[inline(always)]
pub(crate) fn gamma(n: u32) -> f32 {
    let e = n as f32 * (f32::EPSILON * 0.5);
    e / (1.0 - e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_the_centroid_with_barycentrics_one_third() {
        let (p0, p1, p2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let c = (p0 + p1 + p2) / 3.0;
        let ray = Ray::new(c + Vec3::Z * 2.0, -Vec3::Z);
        let hit = moller_trumbore(&ray, p0, p1, p2).expect("ray through the centroid hits");
        assert!((hit.t - 2.0).abs() < 1e-6);
        assert!((hit.u - 1.0 / 3.0).abs() < 1e-6 && (hit.v - 1.0 / 3.0).abs() < 1e-6);
    }

    #[test]
    fn misses_outside_and_respects_t_max() {
        let ray = Ray::new(Vec3::new(2.0, 2.0, 1.0), -Vec3::Z);
        assert!(moller_trumbore(&ray, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
        let short = Ray::segment(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.5);
        assert!(moller_trumbore(&short, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
    }

    #[test]
    fn parallel_ray_misses() {
        let ray = Ray::new(Vec3::new(0.2, 0.2, 0.0), Vec3::X);
        assert!(moller_trumbore(&ray, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
    }
}

#[cfg(test)]
mod agreement_tests {
    //! The watertight test against Möller–Trumbore: the same answer away from edges, and no
    //! cracks on shared edges and vertices.
    use super::*;

    use crate::testing::SplitMix64 as Rng;

    #[test]
    fn agrees_with_moller_trumbore_away_from_edges() {
        let mut rng = Rng(7);
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..20_000 {
            let (p0, p1, p2) = (
                rng.vec3(-1.0, 1.0),
                rng.vec3(-1.0, 1.0),
                rng.vec3(-1.0, 1.0),
            );
            let origin = rng.vec3(-4.0, 4.0);
            // Aim at a point with known barycentrics (inside or outside the triangle).
            let (u, v) = (rng.unit_f32() * 1.6 - 0.3, rng.unit_f32() * 1.6 - 0.3);
            let w = 1.0 - u - v;
            if u.abs().min(v.abs()).min(w.abs()) < 1e-3 {
                continue;
            }
            let target = p0 + u * (p1 - p0) + v * (p2 - p0);
            let dir = (target - origin) * (0.5 + rng.unit_f32());
            let normal = (p1 - p0).cross(p2 - p0).normalize();
            // Grazing rays make t ill-conditioned for any method; keep |cos| ≥ 0.05.
            if normal.dot(dir.normalize()).abs() < 0.05 {
                continue;
            }
            let ray = Ray::new(origin, dir);
            let mt = moller_trumbore(&ray, p0, p1, p2);
            let wt = watertight(&WatertightRay::new(&ray), p0, p1, p2);
            match (mt, wt) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!((a.t - b.t).abs() <= 2e-5 * a.t, "t {} vs {}", a.t, b.t);
                    assert!((a.u - b.u).abs() < 1e-4 && (a.v - b.v).abs() < 1e-4);
                    assert!((a.u - u).abs() < 1e-3 && (a.v - v).abs() < 1e-3);
                }
                (None, None) => misses += 1,
                _ => panic!("disagree on {ray:?} {p0} {p1} {p2}: {mt:?} vs {wt:?}"),
            }
        }
        assert!(hits > 2000 && misses > 2000, "{hits} hits, {misses} misses");
    }

    /// Triangles of a gently bumpy `n × n` grid and of a 16-triangle fan around its centre, all
    /// sharing edges and vertices.
    fn shared_edge_meshes(rng: &mut Rng) -> Vec<Vec<[Vec3; 3]>> {
        let n = 12;
        let mut pts = vec![Vec3::ZERO; (n + 1) * (n + 1)];
        for j in 0..=n {
            for i in 0..=n {
                let h = 0.03 * rng.unit_f32();
                pts[j * (n + 1) + i] = Vec3::new(i as f32 / 3.0 - 2.0, h, j as f32 / 7.0 - 0.9);
            }
        }
        let at = |i: usize, j: usize| pts[j * (n + 1) + i];
        let mut grid = Vec::new();
        for j in 0..n {
            for i in 0..n {
                grid.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                grid.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let centre = Vec3::new(0.1, 0.2, 0.3);
        let rim: Vec<Vec3> = (0..16)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 16.0;
                Vec3::new(a.cos() * 1.7, 0.1 * rng.unit_f32(), a.sin() * 0.9)
            })
            .collect();
        let fan = (0..16)
            .map(|k| [centre, rim[k], rim[(k + 1) % 16]])
            .collect();
        vec![grid, fan]
    }

    #[test]
    fn watertight_never_lets_a_ray_through_a_shared_edge_or_vertex() {
        let mut rng = Rng(11);
        let mut mt_cracks = 0;
        let mut rays = 0;
        for mesh in shared_edge_meshes(&mut rng) {
            // Interior edges: each one shared by two triangles (counted over both windings).
            let mut targets = Vec::new();
            let mut boundary = Vec::new();
            for (a, tri) in mesh.iter().enumerate() {
                for e in 0..3 {
                    let (p, q) = (tri[e], tri[(e + 1) % 3]);
                    let shared = mesh
                        .iter()
                        .enumerate()
                        .any(|(b, o)| b != a && (0..3).any(|f| o[f] == q && o[(f + 1) % 3] == p));
                    if shared {
                        targets.push(p);
                        for k in 1..8 {
                            targets.push(p + (q - p) * (k as f32 / 8.0));
                        }
                    } else {
                        boundary.extend([p, q]);
                    }
                }
            }
            // Vertices on the rim may be missed legitimately; every other one is inside.
            targets.retain(|t| !boundary.contains(t));
            for target in targets {
                for _ in 0..6 {
                    // Steeper than any face, so no shared edge is a silhouette (where a ray may
                    // rightly pass beside both triangles).
                    let o = rng.vec3(-1.0, 1.0);
                    let origin = Vec3::new(3.0 * o.x, 6.0 + o.y, 3.0 * o.z);
                    let ray = Ray::new(origin, target - origin);
                    let pre = WatertightRay::new(&ray);
                    let wt = mesh
                        .iter()
                        .any(|t| watertight(&pre, t[0], t[1], t[2]).is_some());
                    let mt = mesh
                        .iter()
                        .any(|t| moller_trumbore(&ray, t[0], t[1], t[2]).is_some());
                    assert!(wt, "watertight crack: {ray:?} target {target}");
                    mt_cracks += usize::from(!mt);
                    rays += 1;
                }
            }
        }
        assert!(rays > 5000, "{rays} rays");
        // The reason for the watertight test: on these exact rays the reference one leaks.
        assert!(mt_cracks > 0);
        eprintln!(
            "{rays} rays at shared edges: Möller–Trumbore missed {mt_cracks}, watertight none"
        );
    }
}
