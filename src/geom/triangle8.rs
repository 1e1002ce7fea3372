//! Eight triangles (two packets of four) against one ray at once, on AVX2: the watertight test
//! of [`super::triangle4`], operation for operation, on eight lanes.
//!
//! Stage: geometry, below the BVH; used by its AVX2 path (`bvh::isa`). Lanes 0–3 hold the first
//! packet and lanes 4–7 the second (or the first again when a leaf has an odd number of
//! packets: a lane repeated later is never strictly nearer, so it never wins). The arithmetic
//! is the four-lane test's (no fused multiply-adds, the same operand order and predicates),
//! except two steps written for fewer instructions that give the same values in every lane
//! that can hit (the determinant's sign as a sign-bit flip, "outside" as `min < 0 < max`; see
//! `watertight8`), so hits, distances and barycentrics are the same bits; `tests` checks that,
//! degenerate and overflowing triangles included.

use super::avx2::{Avx2, F8};
use super::triangle::{gamma, TriangleHit, WatertightRay};
use super::triangle4::{Tri4, LANES};

/// Lanes per test.
const LANES8: usize = 2 * LANES;

/// The lanes of two packets that a ray hits within `(0, t_max)`; as `triangle4::Hits4`.
#[derive(Debug, Clone, Copy)]
struct Hits8 {
    mask: u32,
    t: [f32; LANES8],
    u: [f32; LANES8],
    v: [f32; LANES8],
    ts: [f32; LANES8],
    ad: [f32; LANES8],
}

impl Hits8 {
    /// Lane `k`'s hit if it is also within `(0, t_max)` for this (smaller or equal) `t_max`.
    #[inline(always)]
    fn within(&self, k: usize, t_max: f32) -> Option<TriangleHit> {
        (self.mask & (1 << k) != 0 && self.ts[k] < t_max * self.ad[k] && self.t[k] < t_max).then(
            || TriangleHit {
                t: self.t[k],
                u: self.u[k],
                v: self.v[k],
            },
        )
    }
}

/// Vertex `j` of the two packets relative to the ray's origin, sheared: (x, y) across the
/// ray, z along it. (Helpers are functions, not closures: a closure's body might not be
/// inlined into the AVX2 kernel, and outside it every intrinsic becomes a call.)
#[inline(always)]
fn sheared(avx: Avx2, r: &WatertightRay, lo: &Tri4, hi: &Tri4, j: usize) -> [F8; 3] {
    let [kx, ky, kz] = r.axes;
    let (x, y, z) = (
        relative(avx, r, lo, hi, 3 * j + kx, 0),
        relative(avx, r, lo, hi, 3 * j + ky, 1),
        relative(avx, r, lo, hi, 3 * j + kz, 2),
    );
    let [sx, sy, sz] = r.shear_factors;
    [
        avx.sub(x, avx.mul(avx.splat(sx), z)),
        avx.sub(y, avx.mul(avx.splat(sy), z)),
        avx.mul(avx.splat(sz), z),
    ]
}

/// Row `row` of the two packets (a vertex's coordinate on axis `r.axes[k]`), minus the
/// origin's coordinate on that axis.
#[inline(always)]
fn relative(avx: Avx2, r: &WatertightRay, lo: &Tri4, hi: &Tri4, row: usize, k: usize) -> F8 {
    let p = avx.load2(&lo.rows[row], &hi.rows[row]);
    avx.sub(p, avx.splat(r.origin_k[k]))
}

/// `p·q − s·t`.
#[inline(always)]
fn cross(avx: Avx2, p: F8, q: F8, s: F8, t: F8) -> F8 {
    avx.sub(avx.mul(p, q), avx.mul(s, t))
}

/// `max(max(|p|, |q|), |s|)`.
#[inline(always)]
fn max_abs(avx: Avx2, p: F8, q: F8, s: F8) -> F8 {
    avx.max(avx.max(avx.abs(p), avx.abs(q)), avx.abs(s))
}

/// `(a·b + c·d) + e·f`, rounded after each operation.
#[inline(always)]
fn dot3(avx: Avx2, [a, b, c, d, e, f]: [F8; 6]) -> F8 {
    avx.add(avx.add(avx.mul(a, b), avx.mul(c, d)), avx.mul(e, f))
}

/// The watertight test of `r` against `lo`'s triangles (lanes 0–3) and `hi`'s (lanes 4–7),
/// each against `t_max`; `None` when no lane is hit. With `FULL == false` only the mask is
/// kept (the any-hit query needs nothing else).
#[inline(always)]
fn watertight8<const FULL: bool>(
    avx: Avx2,
    r: &WatertightRay,
    t_max: f32,
    lo: &Tri4,
    hi: &Tri4,
) -> Option<Hits8> {
    let [ax, ay, az] = sheared(avx, r, lo, hi, 0);
    let [bx, by, bz] = sheared(avx, r, lo, hi, 1);
    let [cx, cy, cz] = sheared(avx, r, lo, hi, 2);
    let mut u = cross(avx, cx, by, cy, bx);
    let mut v = cross(avx, ax, cy, ay, cx);
    let mut w = cross(avx, bx, ay, by, ax);
    let zero = avx.splat(0.0);
    let exact_zero = avx.bitmask(avx.or(avx.or(avx.eq(u, zero), avx.eq(v, zero)), avx.eq(w, zero)));
    if exact_zero != 0 {
        let xy = [ax, ay, bx, by, cx, cy];
        // Plain arrays in and out: the cold path is a call, not compiled for AVX2.
        let [u2, v2, w2] = reevaluate_in_f64(
            exact_zero,
            [avx.store(u), avx.store(v), avx.store(w)],
            [
                avx.store(xy[0]),
                avx.store(xy[1]),
                avx.store(xy[2]),
                avx.store(xy[3]),
                avx.store(xy[4]),
                avx.store(xy[5]),
            ],
        );
        (u, v, w) = (avx.load(&u2), avx.load(&v2), avx.load(&w2));
    }
    let det = avx.add(avx.add(u, v), w);
    // The four-lane test's `sign = det < 0 ? −1 : 1`, `ts = t_scaled · sign`, `ad = det · sign`,
    // as a flip of the sign bit (multiplying by ±1 is exact, so the bits are the same), in one
    // operation of latency 1 instead of a compare, a blend and two multiplications. The lanes
    // where the two differ are `det = −0` (here `ad = +0`, `ts` flipped), never usable, and NaN
    // (any sign), never usable either.
    let sign_bit = avx.and(det, avx.splat(-0.0));
    let t_scaled = dot3(avx, [u, az, v, bz, w, cz]);
    let (ts, ad) = (avx.xor(t_scaled, sign_bit), avx.xor(det, sign_bit));
    // `ad` is `|det|`: usable where `0 < |det| < ∞` (the four-lane `det ≠ 0 && |det| < ∞`; a
    // NaN fails both forms).
    let usable = avx.and(avx.gt(ad, zero), avx.lt(ad, avx.splat(f32::INFINITY)));
    // Some edge function below 0 and some above: in a usable lane u, v and w are finite
    // (`det` would be NaN or infinite otherwise), so that is `min < 0 && max > 0` (the
    // four-lane form compares each: six compares and four ors here become four min/max and
    // two compares).
    let lowest = avx.min(avx.min(u, v), w);
    let highest = avx.max(avx.max(u, v), w);
    let outside = avx.and(avx.lt(lowest, zero), avx.gt(highest, zero));
    let t_max8 = avx.splat(t_max);
    let in_front = avx.and(avx.gt(ts, zero), avx.lt(ts, avx.mul(t_max8, ad)));
    let candidate = avx.bitmask(avx.and_not(outside, avx.and(usable, in_front)));
    if candidate == 0 {
        return None;
    }
    let inv_det = avx.div(avx.splat(1.0), det);
    let t = avx.mul(t_scaled, inv_det);
    let in_range = avx.and(avx.gt(t, zero), avx.lt(t, t_max8));
    // The conservative bound on the rounding error of t (see the one-triangle test).
    let max_zt = max_abs(avx, az, bz, cz);
    let max_xt = max_abs(avx, ax, bx, cx);
    let max_yt = max_abs(avx, ay, by, cy);
    let delta_z = avx.mul(avx.splat(gamma(3)), max_zt);
    let max_z_length = avx.mul(max_zt, avx.splat(r.dir_length));
    let delta_x = avx.mul(avx.splat(gamma(5)), avx.add(max_xt, max_z_length));
    let delta_y = avx.mul(avx.splat(gamma(5)), avx.add(max_yt, max_z_length));
    let g2_xt = avx.mul(avx.splat(gamma(2)), max_xt);
    let delta_e = avx.mul(
        avx.splat(2.0),
        dot3(avx, [g2_xt, max_yt, delta_y, max_xt, delta_x, max_yt]),
    );
    let max_e = max_abs(avx, u, v, w);
    let g3_e = avx.mul(avx.splat(gamma(3)), max_e);
    let delta_t = avx.mul(
        avx.mul(
            avx.splat(3.0),
            dot3(avx, [g3_e, max_zt, delta_e, max_zt, delta_z, max_e]),
        ),
        avx.abs(inv_det),
    );
    let mask = candidate & avx.bitmask(avx.and(in_range, avx.gt(t, delta_t)));
    if mask == 0 {
        return None;
    }
    let nothing = [0.0; LANES8];
    Some(if FULL {
        Hits8 {
            mask,
            t: avx.store(t),
            u: avx.store(avx.mul(v, inv_det)),
            v: avx.store(avx.mul(w, inv_det)),
            ts: avx.store(ts),
            ad: avx.store(ad),
        }
    } else {
        Hits8 {
            mask,
            t: nothing,
            u: nothing,
            v: nothing,
            ts: nothing,
            ad: nothing,
        }
    })
}

/// The edge functions `uvw` of the lanes in `lanes` recomputed in double precision (exact for
/// products of floats) from the sheared `[ax, ay, bx, by, cx, cy]`, as the one-triangle test
/// does when one rounds to exactly 0. Plain arrays: this cold path is not compiled for AVX2.
#[inline(never)]
#[cold]
fn reevaluate_in_f64(
    lanes: u32,
    uvw: [[f32; LANES8]; 3],
    xy: [[f32; LANES8]; 6],
) -> [[f32; LANES8]; 3] {
    let [mut u, mut v, mut w] = uvw;
    let [ax, ay, bx, by, cx, cy] = xy;
    for k in (0..LANES8).filter(|&k| lanes & (1 << k) != 0) {
        let f = |a: [f32; LANES8]| f64::from(a[k]);
        let (ax, ay, bx, by, cx, cy) = (f(ax), f(ay), f(bx), f(by), f(cx), f(cy));
        u[k] = (cx * by - cy * bx) as f32;
        v[k] = (ax * cy - ay * cx) as f32;
        w[k] = (bx * ay - by * ax) as f32;
    }
    [u, v, w]
}

/// [`super::triangle4::closest4`] on AVX2: the closest hit among the packets `tris` within
/// `(0, *t_max)`, lanes taken in order, a later hit kept only if strictly nearer; shrinks
/// `*t_max`. Returns the hit's slot (packet · 4 + lane) within `tris`.
#[inline(always)]
pub fn closest8(
    avx: Avx2,
    r: &WatertightRay,
    t_max: &mut f32,
    tris: &[Tri4],
) -> Option<(usize, TriangleHit)> {
    let mut best = None;
    for (p, pair) in tris.chunks(2).enumerate() {
        let (lo, hi) = (&pair[0], pair.get(1).unwrap_or(&pair[0]));
        if let Some(hits) = watertight8::<true>(avx, r, *t_max, lo, hi) {
            // Only the hit lanes, in order (a repeated odd packet's upper lanes left out).
            let mut lanes = hits.mask & ((1 << (LANES * pair.len())) - 1);
            while lanes != 0 {
                let k = lanes.trailing_zeros() as usize % LANES8;
                lanes &= lanes - 1;
                if let Some(h) = hits.within(k, *t_max) {
                    *t_max = h.t;
                    best = Some((2 * LANES * p + k, h));
                }
            }
        }
    }
    best
}

/// [`super::triangle4::any4`] on AVX2: whether any triangle of `tris` is hit within
/// `(0, t_max)`.
#[inline(always)]
pub fn any8(avx: Avx2, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
    for pair in tris.chunks(2) {
        let (lo, hi) = (&pair[0], pair.get(1).unwrap_or(&pair[0]));
        if watertight8::<false>(avx, r, t_max, lo, hi).is_some() {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::triangle4::{any4, closest4};
    use crate::geom::Ray;
    use glam::{Vec3, Vec3A};

    use crate::testing::SplitMix64 as Rng;

    /// A point in the cube of side `scale` around the origin.
    fn point(rng: &mut Rng, scale: f32) -> Vec3A {
        let (x, y, z) = (rng.unit_f32(), rng.unit_f32(), rng.unit_f32());
        Vec3A::new(x, y, z) * scale - Vec3A::splat(scale / 2.0)
    }

    fn key(h: Option<(usize, TriangleHit)>) -> Option<(usize, u32, u32, u32)> {
        h.map(|(k, h)| (k, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()))
    }

    #[test]
    fn eight_lanes_give_the_four_lane_answers_bit_for_bit() {
        let Some(avx) = Avx2::detect_cpu() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let mut rng = Rng(11);
        let mut hits = 0;
        for case in 0..20_000 {
            // Up to three packets (an odd count repeats the last one in the upper lanes),
            // neighbours sharing edges and vertices, rays aimed at vertices and edges.
            let n: usize = 1 + case % 11;
            let mut tris: Vec<[Vec3A; 3]> = (0..n)
                .map(|_| {
                    [
                        point(&mut rng, 2.0),
                        point(&mut rng, 2.0),
                        point(&mut rng, 2.0),
                    ]
                })
                .collect();
            for k in 1..n {
                if k % 2 == 1 {
                    tris[k] = [tris[k - 1][1], tris[k - 1][0], point(&mut rng, 2.0)];
                }
            }
            let origin = point(&mut rng, 8.0);
            let pick = case % n;
            let aim = match case % 3 {
                0 => tris[pick][0],
                1 => (tris[pick][0] + tris[pick][1]) * 0.5,
                _ => point(&mut rng, 1.0),
            };
            let dir = Vec3::from(aim - origin).normalize_or_zero();
            let r = WatertightRay::new(&Ray::new(origin.into(), dir));
            let t_max = if case % 5 == 0 { 3.0 } else { f32::INFINITY };
            let mut packets = vec![Tri4::EMPTY; n.div_ceil(LANES)];
            for (k, t) in tris.iter().enumerate() {
                packets[k / LANES].set(k % LANES, *t);
            }
            let (mut t4, mut t8) = (t_max, t_max);
            let four = closest4(&r, &mut t4, &packets);
            let eight = closest8(avx, &r, &mut t8, &packets);
            assert_eq!(key(eight), key(four), "case {case}");
            assert_eq!(t8.to_bits(), t4.to_bits(), "case {case}");
            assert_eq!(
                any8(avx, &r, t_max, &packets),
                any4(&r, t_max, &packets),
                "case {case}"
            );
            hits += usize::from(four.is_some());
        }
        assert!(hits > 5_000, "too few hits to test anything: {hits}");
    }

    /// The lanes where the eight-lane test's sign flip and min/max form differ from the
    /// four-lane test's multiplications and compares are those with `det` = ±0, infinite or
    /// NaN: degenerate triangles (repeated or collinear vertices, where `det` rounds to a
    /// signed zero) and coordinates near `f32::MAX` (edge functions that overflow to ±∞, and
    /// `∞ − ∞` = NaN). Both tests must still give the same answers there.
    #[test]
    fn eight_lanes_agree_with_four_on_degenerate_and_overflowing_triangles() {
        let Some(avx) = Avx2::detect_cpu() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let mut rng = Rng(16);
        let (mut hits, mut non_finite) = (0, 0);
        for case in 0..20_000 {
            let scale = [1.0, 1.0e19, 3.0e38][case % 3];
            let n: usize = 1 + case % 8;
            let tris: Vec<[Vec3A; 3]> = (0..n)
                .map(|k| {
                    let a = point(&mut rng, 2.0) * scale;
                    let b = point(&mut rng, 2.0) * scale;
                    match (case + k) % 4 {
                        // Repeated vertex, collinear, and a thin sliver.
                        0 => [a, a, b],
                        1 => [a, b, (a + b) * 0.5],
                        2 => [a, b, b + Vec3A::splat(f32::EPSILON) * scale],
                        _ => [a, b, point(&mut rng, 2.0) * scale],
                    }
                })
                .collect();
            non_finite += tris
                .iter()
                .filter(|t| !(t[1] - t[0]).cross(t[2] - t[0]).is_finite())
                .count();
            let origin = point(&mut rng, 8.0) * scale.min(1.0e19);
            let aim = tris[case % n][case % 3];
            let dir = Vec3::from(aim - origin).normalize_or_zero();
            let r = WatertightRay::new(&Ray::new(origin.into(), dir));
            let mut packets = vec![Tri4::EMPTY; n.div_ceil(LANES)];
            for (k, t) in tris.iter().enumerate() {
                packets[k / LANES].set(k % LANES, *t);
            }
            let (mut t4, mut t8) = (f32::INFINITY, f32::INFINITY);
            let four = closest4(&r, &mut t4, &packets);
            let eight = closest8(avx, &r, &mut t8, &packets);
            assert_eq!(key(eight), key(four), "case {case}");
            assert_eq!(t8.to_bits(), t4.to_bits(), "case {case}");
            assert_eq!(
                any8(avx, &r, f32::INFINITY, &packets),
                any4(&r, f32::INFINITY, &packets),
                "case {case}"
            );
            hits += usize::from(four.is_some());
        }
        assert!(hits > 400, "too few hits to test anything: {hits}");
        assert!(
            non_finite > 1_000,
            "too few overflowing triangles: {non_finite}"
        );
    }
}
