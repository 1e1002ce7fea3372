//! Four triangles against one ray at once: the watertight test of [`super::triangle`] run on
//! four lanes (SSE, part of every x86-64 CPU), over triangles stored side by side (structure
//! of arrays), as the BVH's leaves hold them.
//!
//! Stage: geometry, below the BVH. The lanes compute exactly what the one-triangle test
//! computes, operation for operation in the same order (no fused multiply-adds), so a packet
//! gives the same hits, distances and barycentrics, bit for bit, as testing its triangles one
//! after another; `tests` checks that on random and on edge-aligned rays.

use glam::{BVec4A, Vec3A, Vec4};

use super::triangle::{gamma, TriangleHit, WatertightRay};

/// Lanes per packet.
pub const LANES: usize = 4;

/// Four triangles, vertex coordinates side by side: row `3·j + a` holds axis `a` (x, y, z) of
/// vertex `j` (0, 1, 2), one lane per triangle. An empty lane holds NaN, which no ray hits.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(16))]
pub struct Tri4 {
    /// Vertex coordinates: `rows[3·j + a][lane]`.
    pub rows: [[f32; LANES]; 9],
}

impl Tri4 {
    /// A packet with every lane empty.
    pub const EMPTY: Tri4 = Tri4 {
        rows: [[f32::NAN; LANES]; 9],
    };

    /// Puts triangle `tri` into `lane`.
    pub fn set(&mut self, lane: usize, tri: [Vec3A; 3]) {
        for (j, p) in tri.iter().enumerate() {
            for a in 0..3 {
                self.rows[3 * j + a][lane] = p[a];
            }
        }
    }

    /// The triangle in `lane`, `None` for an empty lane.
    pub fn get(&self, lane: usize) -> Option<[Vec3A; 3]> {
        let v = |j: usize| {
            Vec3A::new(
                self.rows[3 * j][lane],
                self.rows[3 * j + 1][lane],
                self.rows[3 * j + 2][lane],
            )
        };
        let tri = [v(0), v(1), v(2)];
        tri.iter().all(|p| !p.is_nan()).then_some(tri)
    }
}

/// The lanes of one packet that a ray hits within `(0, t_max)`, with what the one-triangle test
/// would have returned for each, and what it takes to re-check a lane against a smaller `t_max`.
#[derive(Debug, Clone, Copy)]
pub struct Hits4 {
    /// Bit `k` set: lane `k` is hit within the `t_max` given to [`watertight4`].
    pub mask: u32,
    t: [f32; LANES],
    u: [f32; LANES],
    v: [f32; LANES],
    /// The sheared distance with the determinant's sign taken out, and `|det|`: the test
    /// compares `ts < t_max · ad` before dividing, as the one-triangle test does.
    ts: [f32; LANES],
    ad: [f32; LANES],
}

impl Hits4 {
    /// Lane `k`'s hit if it is also within `(0, t_max)` for this (smaller or equal) `t_max`:
    /// the same comparisons as the one-triangle test with that `t_max`.
    #[inline(always)]
    pub fn within(&self, k: usize, t_max: f32) -> Option<TriangleHit> {
        (self.mask & (1 << k) != 0 && self.ts[k] < t_max * self.ad[k] && self.t[k] < t_max).then(
            || TriangleHit {
                t: self.t[k],
                u: self.u[k],
                v: self.v[k],
            },
        )
    }
}

/// The watertight test ([`super::triangle::watertight_a`]) of `ray` against the four triangles
/// of `tri`, each against `t_max`. `None` when no lane is hit (the common case, found before
/// the division and the error bound are computed).
#[inline(always)]
pub fn watertight4(r: &WatertightRay, t_max: f32, tri: &Tri4) -> Option<Hits4> {
    let [kx, ky, kz] = r.axes;
    let [sx, sy, sz] = r.shear_factors.map(Vec4::splat);
    let origin = [
        Vec4::splat(r.origin.x),
        Vec4::splat(r.origin.y),
        Vec4::splat(r.origin.z),
    ];
    // Vertex j relative to the origin, then sheared: (x, y) across the ray, z along it.
    let sheared = |j: usize| {
        let rel = |a: usize| Vec4::from_array(tri.rows[3 * j + a]) - origin[a];
        let (x, y, z) = (rel(kx), rel(ky), rel(kz));
        (x - sx * z, y - sy * z, sz * z)
    };
    let (ax, ay, az) = sheared(0);
    let (bx, by, bz) = sheared(1);
    let (cx, cy, cz) = sheared(2);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    let zero = Vec4::ZERO;
    let exact_zero = u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero);
    if exact_zero.any() {
        // As in the one-triangle test: an edge function that rounds to exactly 0 is
        // re-evaluated in double precision (exact for products of floats).
        let (mut ua, mut va, mut wa) = (u.to_array(), v.to_array(), w.to_array());
        let (ax, ay, bx, by, cx, cy) = (
            ax.to_array(),
            ay.to_array(),
            bx.to_array(),
            by.to_array(),
            cx.to_array(),
            cy.to_array(),
        );
        for k in (0..LANES).filter(|&k| exact_zero.bitmask() & (1 << k) != 0) {
            let (ax, ay, bx, by, cx, cy) = (
                f64::from(ax[k]),
                f64::from(ay[k]),
                f64::from(bx[k]),
                f64::from(by[k]),
                f64::from(cx[k]),
                f64::from(cy[k]),
            );
            ua[k] = (cx * by - cy * bx) as f32;
            va[k] = (ax * cy - ay * cx) as f32;
            wa[k] = (bx * ay - by * ax) as f32;
        }
        (u, v, w) = (
            Vec4::from_array(ua),
            Vec4::from_array(va),
            Vec4::from_array(wa),
        );
    }
    let outside = (u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero))
        & (u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero));
    let det = u + v + w;
    // `det` finite and not 0 (NaN, from an empty lane, fails the first comparison).
    let usable = det.abs().cmplt(Vec4::INFINITY) & det.cmpne(zero);
    let t_scaled = u * az + v * bz + w * cz;
    // t = t_scaled / det within (0, t_max), compared without dividing: the sign of det
    // flipped onto both sides (a multiplication by ±1, exact).
    let sign = Vec4::select(det.cmplt(zero), Vec4::NEG_ONE, Vec4::ONE);
    let ts = t_scaled * sign;
    let ad = det * sign;
    let candidate = usable & !outside & ts.cmpgt(zero) & ts.cmplt(Vec4::splat(t_max) * ad);
    if !candidate.any() {
        return None;
    }
    let inv_det = Vec4::ONE / det;
    let t = t_scaled * inv_det;
    let in_range = t.cmpgt(zero) & t.cmplt(Vec4::splat(t_max));
    // The conservative bound on the rounding error of t (see the one-triangle test).
    let max_zt = az.abs().max(bz.abs()).max(cz.abs());
    let max_xt = ax.abs().max(bx.abs()).max(cx.abs());
    let max_yt = ay.abs().max(by.abs()).max(cy.abs());
    let delta_z = Vec4::splat(gamma(3)) * max_zt;
    let max_z_length = max_zt * Vec4::splat(r.dir_length);
    let delta_x = Vec4::splat(gamma(5)) * (max_xt + max_z_length);
    let delta_y = Vec4::splat(gamma(5)) * (max_yt + max_z_length);
    let delta_e = Vec4::splat(2.0)
        * (Vec4::splat(gamma(2)) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = u.abs().max(v.abs()).max(w.abs());
    let delta_t = Vec4::splat(3.0)
        * (Vec4::splat(gamma(3)) * max_e * max_zt + delta_e * max_zt + delta_z * max_e)
        * inv_det.abs();
    let hit: BVec4A = candidate & in_range & t.cmpgt(delta_t);
    let mask = hit.bitmask();
    (mask != 0).then(|| Hits4 {
        mask,
        t: t.to_array(),
        u: (v * inv_det).to_array(),
        v: (w * inv_det).to_array(),
        ts: ts.to_array(),
        ad: ad.to_array(),
    })
}

/// The closest hit among the packets `tris` within `(0, *t_max)`, taking lanes in order and
/// keeping a later hit only if strictly nearer, exactly as testing the triangles one by one
/// does; shrinks `*t_max`. Returns the hit's slot (packet · 4 + lane) within `tris`.
#[inline(always)]
pub fn closest4(r: &WatertightRay, t_max: &mut f32, tris: &[Tri4]) -> Option<(usize, TriangleHit)> {
    let mut best = None;
    for (p, tri) in tris.iter().enumerate() {
        if let Some(hits) = watertight4(r, *t_max, tri) {
            // Only the hit lanes, in order.
            let mut lanes = hits.mask;
            while lanes != 0 {
                let k = lanes.trailing_zeros() as usize % LANES;
                lanes &= lanes - 1;
                if let Some(h) = hits.within(k, *t_max) {
                    *t_max = h.t;
                    best = Some((p * LANES + k, h));
                }
            }
        }
    }
    best
}

/// Whether any triangle of the packets `tris` is hit within `(0, t_max)`.
#[inline(always)]
pub fn any4(r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
    // A loop, not `iter().any(..)`: the closure was left as a call inside the traversal.
    for tri in tris {
        if watertight4(r, t_max, tri).is_some() {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::triangle::watertight_a;
    use crate::geom::Ray;
    use glam::Vec3;

    use crate::testing::SplitMix64 as Rng;

    /// A point in the cube of side `scale` around the origin.
    fn point(rng: &mut Rng, scale: f32) -> Vec3A {
        let (x, y, z) = (rng.unit_f32(), rng.unit_f32(), rng.unit_f32());
        Vec3A::new(x, y, z) * scale - Vec3A::splat(scale / 2.0)
    }

    /// The one-triangle test run lane by lane, with the t_max shrinking after each hit.
    fn one_by_one(
        r: &WatertightRay,
        mut t_max: f32,
        tris: &[[Vec3A; 3]],
    ) -> Option<(usize, TriangleHit)> {
        let mut best = None;
        for (k, t) in tris.iter().enumerate() {
            let mut rr = *r;
            rr.t_max = t_max;
            if let Some(h) = watertight_a(&rr, t[0], t[1], t[2]) {
                t_max = h.t;
                best = Some((k, h));
            }
        }
        best
    }

    fn same(a: Option<(usize, TriangleHit)>, b: Option<(usize, TriangleHit)>) -> bool {
        match (a, b) {
            (None, None) => true,
            (Some((ka, ha)), Some((kb, hb))) => {
                ka == kb
                    && ha.t.to_bits() == hb.t.to_bits()
                    && ha.u.to_bits() == hb.u.to_bits()
                    && ha.v.to_bits() == hb.v.to_bits()
            }
            _ => false,
        }
    }

    #[test]
    fn packets_give_the_one_triangle_answers_bit_for_bit() {
        let mut rng = Rng(7);
        let mut hits = 0;
        for case in 0..20_000 {
            // Triangles near the origin, some sharing an edge (lanes 0 and 1), some padded.
            let n: usize = 1 + case % 7;
            let mut tris: Vec<[Vec3A; 3]> = (0..n)
                .map(|_| {
                    [
                        point(&mut rng, 2.0),
                        point(&mut rng, 2.0),
                        point(&mut rng, 2.0),
                    ]
                })
                .collect();
            if n >= 2 {
                tris[1] = [tris[0][1], tris[0][0], point(&mut rng, 2.0)];
            }
            let origin = point(&mut rng, 8.0);
            // Aim at a vertex, an edge midpoint or a random point, so edge cases are common.
            let aim = match case % 3 {
                0 => tris[0][0],
                1 => (tris[0][0] + tris[0][1]) * 0.5,
                _ => point(&mut rng, 1.0),
            };
            let dir = Vec3::from(aim - origin);
            let ray = Ray::new(origin.into(), dir.normalize_or_zero());
            let r = WatertightRay::new(&ray);
            let t_max = if case % 5 == 0 { 3.0 } else { f32::INFINITY };
            let mut packets = vec![Tri4::EMPTY; n.div_ceil(LANES)];
            for (k, t) in tris.iter().enumerate() {
                packets[k / LANES].set(k % LANES, *t);
            }
            let mut t4 = t_max;
            let four = closest4(&r, &mut t4, &packets);
            let one = one_by_one(&r, t_max, &tris);
            assert!(same(four, one), "case {case}: {four:?} vs {one:?}");
            assert_eq!(any4(&r, t_max, &packets), one.is_some(), "case {case}");
            hits += usize::from(one.is_some());
        }
        assert!(
            hits > 5_000,
            "the cases must hit often enough to test something: {hits}"
        );
    }

    #[test]
    fn empty_lanes_are_never_hit_and_read_back_as_none() {
        let mut p = Tri4::EMPTY;
        let t = [Vec3A::ZERO, Vec3A::X, Vec3A::Y];
        p.set(2, t);
        assert_eq!(p.get(2), Some(t));
        assert_eq!(p.get(0), None);
        let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z);
        let r = WatertightRay::new(&ray);
        let hits = watertight4(&r, f32::INFINITY, &p).expect("lane 2 is hit");
        assert_eq!(hits.mask, 0b100);
        // A ray through where lanes 0, 1, 3 would be if they were not NaN hits nothing else.
        let far = Ray::new(Vec3::new(5.0, 5.0, 1.0), -Vec3::Z);
        assert!(watertight4(&WatertightRay::new(&far), f32::INFINITY, &p).is_none());
    }
}
