//! Shading layer: sampling a rectangular light uniformly by solid angle (Ureña, Fajardo, King
//! 2013, "An Area-Preserving Parametrization for Spherical Rectangles").
//!
//! A quad light (`light panel = area { mesh panel … }` with `panel = quad { … }`, as cornell's)
//! is sampled as a whole (`area::AreaLight` recognises a two-triangle rectangle): exactly
//! uniform in solid angle (`pdf = 1 / Ω`). In the rectangle's own frame (x, y along its edges,
//! z across) the four great-circle normals of the spherical rectangle have closed forms
//! (`n₀ ∝ (0, z₀, −y₀)` and so on, the paper's eq. 5), so each corner angle's cosine and
//! sine are ratios of square roots. Ω, the corner angles' sum less 2π, is a small difference
//! of angles near 2π: rather than four `acos` and a subtraction that loses it (in f32 it would
//! be off by ~1e-4 relative for a light of a few millisteradians, a bias
//! `tests/render_light_sampling.rs` sees), the set-up multiplies the corners' complex numbers
//! `cos gᵢ + i·sin gᵢ` in f64 (each scaled by a positive length, which changes no argument:
//! one normalisation instead of four) and takes one argument of the product
//! (`complex_arg::arg`, a short f64 polynomial in place of libm's `atan2f`), which *is* Ω; the per-sample mapping's offset angle `k = 2π − g₂ − g₃` is kept the same way, as
//! its cosine and sine, so a sample needs one f32 `sincos` of `u·Ω` (small, so exact to f32's
//! relative precision) and square roots. Below
//! [`spherical::MIN_SOLID_ANGLE`](super::spherical::MIN_SOLID_ANGLE) a caller samples by area
//! (as `area` does for triangles).

use glam::{DVec2, Vec2, Vec3};

use super::complex_arg::arg;

/// A rectangle as seen from a shading point, ready to be sampled: the local frame (x, y along
/// the edges, z towards the point's side flipped away) and the spherical rectangle's angles.
#[derive(Debug, Clone, Copy)]
pub struct SphericalRect {
    pub(super) x: Vec3,
    pub(super) y: Vec3,
    pub(super) z: Vec3,
    pub(super) z0: f32,
    pub(super) x0: f32,
    pub(super) x1: f32,
    pub(super) y0: f32,
    pub(super) y1: f32,
    pub(super) inv_width: f32,
    pub(super) inv_height: f32,
    pub(super) b0: f32,
    pub(super) b1: f32,
    /// 1 − b0² = z0² / (z0² + y0²), from f64 (no cancellation).
    pub(super) one_minus_b0_sq: f32,
    pub(super) cos_k: f32,
    pub(super) sin_k: f32,
    pub(super) solid_angle: f32,
}

/// A point of the rectangle drawn by [`SphericalRect::sample`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectSample {
    /// From the shading point to the sampled point (world space, not normalised): computed in
    /// the rectangle's frame relative to the shading point, so no large coordinates cancel.
    pub offset: Vec3,
    /// The point's parameter along `ex`, in [0, 1]: the point is `corner + s·ex + t·ey`.
    pub s: f32,
    /// The point's parameter along `ey`, in [0, 1].
    pub t: f32,
}

/// `(cos g + i·sin g)·|nₐ|·|n_b|`, the angle at a corner of the spherical rectangle between
/// the great circles through the corner's two edges, scaled by the lengths of the
/// (unnormalised) closed-form normals `nₐ`, `n_b`: the numerator of the cosine, and the sine's
/// `|nₐ × n_b| = |z₀|·(the corner's distance)`. A positive factor changes no argument, so the
/// corners are multiplied without the four normalisations.
#[inline]
pub(super) fn corner_turn(cos_numerator: f64, z0: f64, corner_length: f64) -> DVec2 {
    DVec2::new(cos_numerator, z0.abs() * corner_length)
}

/// The largest light-frame coordinate the set-up takes unscaled: its product then stays under
/// `(2⁶¹)⁸·2¹¹ = 2⁴⁹⁹`, far inside f64's range.
const MAX_UNSCALED: f32 = (1u64 << 60) as f32;
/// The smallest: the product stays over `2⁻⁴⁸⁰`, far from f64's subnormals (smaller coordinates
/// of the same configuration lose their digits in f32 already).
const MIN_UNSCALED: f32 = 1.0 / MAX_UNSCALED;

/// The power of two that brings `largest` (a positive f32) into [1, 2): exact to multiply by.
/// `None` for an infinite or NaN figure (the set-up has no finite angles then).
fn power_of_two_scale(largest: f32) -> Option<f64> {
    if !largest.is_finite() || largest <= 0.0 {
        return None;
    }
    // An f32 is a normal f64 (subnormals included): its exponent is in [−149, 127], so 2^−e is
    // a normal f64 too.
    let exponent = ((f64::from(largest).to_bits() >> 52) & 0x7ff) as i64 - 1023;
    Some(f64::from_bits(((1023 - exponent) as u64) << 52))
}

/// The complex product `a · b`.
#[inline]
pub(super) fn turn(a: DVec2, b: DVec2) -> DVec2 {
    DVec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x)
}

/// What a rectangle's set-up needs that does not depend on the shading point (its edges'
/// lengths and unit directions), computed once per light instead of once per sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectFrame {
    pub(super) corner: Vec3,
    pub(super) x: Vec3,
    pub(super) y: Vec3,
    pub(super) z: Vec3,
    pub(super) exl: f32,
    pub(super) eyl: f32,
    pub(super) inv_width: f32,
    pub(super) inv_height: f32,
}

impl RectFrame {
    /// The rectangle `corner + s·ex + t·ey` (s, t ∈ [0, 1], `ex ⊥ ey`). `None` when an edge is
    /// degenerate.
    pub fn new(corner: Vec3, ex: Vec3, ey: Vec3) -> Option<RectFrame> {
        let (exl, eyl) = (ex.length(), ey.length());
        if !(exl > 0.0 && eyl > 0.0) {
            return None;
        }
        let (x, y) = (ex / exl, ey / eyl);
        Some(RectFrame {
            corner,
            x,
            y,
            z: x.cross(y),
            exl,
            eyl,
            inv_width: 1.0 / exl,
            inv_height: 1.0 / eyl,
        })
    }
}

impl SphericalRect {
    /// The rectangle `corner + s·ex + t·ey` (s, t ∈ [0, 1], `ex ⊥ ey`) seen from `p`. `None`
    /// when an edge is degenerate, `p` lies in its plane, or the solid angle is not positive.
    pub fn new(p: Vec3, corner: Vec3, ex: Vec3, ey: Vec3) -> Option<SphericalRect> {
        SphericalRect::seen_from(p, &RectFrame::new(corner, ex, ey)?)
    }

    /// [`SphericalRect::new`] of a rectangle whose frame is already known.
    #[inline]
    pub fn seen_from(p: Vec3, frame: &RectFrame) -> Option<SphericalRect> {
        let c = FrameCoordinates::of(p, frame);
        if !c.in_front() {
            return None;
        }
        // The product below is of eighth powers of these coordinates: near f32's largest
        // (≈ 3e38) it overflows f64 (its argument would be NaN), among f32's subnormals it
        // underflows. Every figure taken from the set-up is homogeneous of degree 0 in them, so
        // an exact power-of-two scale changes no bit; only such coordinates pay for it.
        let coords = c.as_f64();
        let coords = match c.unscaled() {
            true => coords,
            false => {
                let s = power_of_two_scale(c.largest())?;
                coords.map(|v| v * s)
            }
        };
        let a = Angles::of(coords);
        // arg(e^{i(2π + Ω)}) = Ω, in (−π, π]; a light filling more than half the hemisphere
        // (Ω > π) comes out negative. A negative figure is told apart from a rounding of a
        // vanishing Ω by the plain angle sum, which only this rare case pays for.
        let mut omega = a.omega;
        if omega <= 0.0 {
            let angle = |g: DVec2| g.y.atan2(g.x);
            let [g0, g1, g2, g3] = a.turns;
            let sum = angle(g0) + angle(g1) + angle(g2) + angle(g3) - 2.0 * std::f64::consts::PI;
            if sum <= std::f64::consts::PI {
                return None;
            }
            omega += 2.0 * std::f64::consts::PI;
        }
        let solid_angle = omega as f32;
        if solid_angle <= 0.0 || solid_angle.is_nan() {
            return None;
        }
        Some(a.rect(&c, frame, solid_angle))
    }

    /// The component across the rectangle's plane of every offset [`SphericalRect::sample`]
    /// returns (negative: the frame's z points away from the rectangle).
    pub fn plane_offset(&self) -> f32 {
        self.z0
    }

    /// The solid angle Ω (sr) the rectangle subtends: the sampling density is `1 / Ω`.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// The point of the rectangle for `u` ∈ [0, 1)²; its direction from the shading point is
    /// uniform over the spherical rectangle.
    #[inline]
    pub fn sample(&self, u: Vec2) -> RectSample {
        let (sin_u, cos_u) = self.column_angle(u.x).sin_cos();
        self.sample_at(u.y, sin_u, cos_u)
    }

    /// The angle whose sine and cosine [`SphericalRect::sample_at`] takes for `u.x`: the
    /// sub-rectangle left of the sample's column subtends `u.x · Ω`.
    #[inline(always)]
    pub(super) fn column_angle(&self, ux: f32) -> f32 {
        ux * self.solid_angle
    }

    /// [`SphericalRect::sample`] from the sine and cosine of its column angle (libm's, taken
    /// apart so that several samples' remaining arithmetic can run side by side:
    /// `rect_lanes`).
    #[inline(always)]
    pub(super) fn sample_at(&self, uy: f32, sin_u: f32, cos_u: f32) -> RectSample {
        // The column: the sub-rectangle [x0, xu] subtends u.x · Ω; au = u.x · Ω + k.
        let sin_au = sin_u * self.cos_k + cos_u * self.sin_k;
        let cos_au = cos_u * self.cos_k - sin_u * self.sin_k;
        // The paper's fu = (cos_au·b0 − b1) / sin_au, cu = sign(fu) / √(fu² + b0²) and
        // xu = −cu·z0 / √(1 − cu²), folded into one square root and one division (a short
        // chain: each sample waits on it):
        // xu = −z0 · sign(num) · sin_au / √(num² − (1 − b0²)·sin_au²), num = cos_au·b0 − b1.
        let num = cos_au * self.b0 - self.b1;
        let den2 = num * num - self.one_minus_b0_sq * sin_au * sin_au;
        let xu = -self.z0 * 1f32.copysign(num) * sin_au / den2.max(0.0).sqrt();
        let xu = clamp(if xu.is_nan() { self.x0 } else { xu }, self.x0, self.x1);
        // The row: uniform in the sine of the elevation along that column; d² = xu² + z0² and
        // yv = hv·d / √(1 − hv²) = hv·√(d² / (1 − hv²)).
        let d2 = xu * xu + self.z0 * self.z0;
        let h0 = self.y0 / (d2 + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d2 + self.y1 * self.y1).sqrt();
        let hv = h0 + uy * (h1 - h0);
        let hv2 = hv * hv;
        let yv = if hv2 < 1.0 - 1e-6 {
            clamp(hv * (d2 / (1.0 - hv2)).sqrt(), self.y0, self.y1)
        } else {
            self.y1
        };
        RectSample {
            offset: xu * self.x + yv * self.y + self.z0 * self.z,
            s: clamp((xu - self.x0) * self.inv_width, 0.0, 1.0),
            t: clamp((yv - self.y0) * self.inv_height, 0.0, 1.0),
        }
    }
}

/// `f32::clamp` without its panic for `lo > hi` (never the case here: each caller's `lo` is
/// below its `hi`), which would keep a loop over several samples from running them side by
/// side; the same value otherwise.
#[inline(always)]
fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x < lo { lo } else { x };
    if x > hi {
        hi
    } else {
        x
    }
}

/// A shading point's coordinates in a rectangle's frame: `z` the frame's normal flipped away
/// from the point's side, `z0` the plane's offset along it (negative in front), `x0 … x1` and
/// `y0 … y1` the rectangle's extent.
#[derive(Debug, Clone, Copy)]
pub(super) struct FrameCoordinates {
    pub(super) z: Vec3,
    pub(super) z0: f32,
    pub(super) x0: f32,
    pub(super) x1: f32,
    pub(super) y0: f32,
    pub(super) y1: f32,
}

impl FrameCoordinates {
    #[inline(always)]
    pub(super) fn of(p: Vec3, frame: &RectFrame) -> FrameCoordinates {
        let d = frame.corner - p;
        let z0 = d.dot(frame.z);
        let flip = z0 > 0.0;
        let (x0, y0) = (d.dot(frame.x), d.dot(frame.y));
        FrameCoordinates {
            z: if flip { -frame.z } else { frame.z },
            z0: if flip { -z0 } else { z0 },
            x0,
            x1: x0 + frame.exl,
            y0,
            y1: y0 + frame.eyl,
        }
    }

    /// Whether the point is off the plane (a finite `z0`, now negative).
    #[inline(always)]
    pub(super) fn in_front(&self) -> bool {
        self.z0 < 0.0
    }

    /// Whether the set-up takes the coordinates unscaled: the largest in [`MIN_UNSCALED`,
    /// `MAX_UNSCALED`] (in-plane) and `−z0` in it too. (Two range tests on the in-plane four's
    /// largest: `f32::max`'s NaN rules on all five cost 30 instructions a call.)
    #[inline(always)]
    pub(super) fn unscaled(&self) -> bool {
        let unscaled = MIN_UNSCALED..=MAX_UNSCALED;
        unscaled.contains(&self.in_plane()) && unscaled.contains(&-self.z0)
    }

    /// The largest in-plane coordinate's magnitude (NaN if any of them is).
    #[inline(always)]
    fn in_plane(&self) -> f32 {
        let m = |a: f32, b: f32| {
            if a.is_nan() || b.is_nan() {
                f32::NAN
            } else {
                a.max(b)
            }
        };
        m(
            m(self.x0.abs(), self.x1.abs()),
            m(self.y0.abs(), self.y1.abs()),
        )
    }

    /// The largest coordinate's magnitude.
    fn largest(&self) -> f32 {
        self.in_plane().max(-self.z0)
    }

    /// `(x0, x1, y0, y1, z0)` in f64.
    #[inline(always)]
    pub(super) fn as_f64(&self) -> [f64; 5] {
        [self.x0, self.x1, self.y0, self.y1, self.z0].map(f64::from)
    }
}

/// The spherical rectangle's angles from the light-frame coordinates `(x0, x1, y0, y1, z0)`
/// (f64, possibly scaled by a power of two), the set-up's common branch.
#[derive(Debug, Clone, Copy)]
pub(super) struct Angles {
    /// The product's argument: Ω, or Ω − 2π for Ω > π.
    pub(super) omega: f64,
    /// The four corners' unnormalised turns (for the rare Ω > π case).
    turns: [DVec2; 4],
    b0: f32,
    b1: f32,
    one_minus_b0_sq: f32,
    cos_k: f32,
    sin_k: f32,
}

impl Angles {
    #[inline(always)]
    pub(super) fn of([dx0, dx1, dy0, dy1, dz0]: [f64; 5]) -> Angles {
        // The closed-form normals n₀ ∝ (0, z₀, −y₀), n₁ ∝ (−z₀, 0, x₁), n₂ ∝ (0, −z₀, y₁),
        // n₃ ∝ (z₀, 0, −x₀); n₀ and n₂ have lengths…
        let zz = dz0 * dz0;
        let (l0, l2) = ((zz + dy0 * dy0).sqrt(), (zz + dy1 * dy1).sqrt());
        let corner_len = |a: f64, b: f64| (a * a + b * b + zz).sqrt();
        // …and the angle gᵢ = acos(−nᵢ·nᵢ₊₁) at each corner is the argument of
        // (−nᵢ·nᵢ₊₁, |nᵢ × nᵢ₊₁|) with the normals unnormalised (`corner_turn`).
        let g0 = corner_turn(dy0 * dx1, dz0, corner_len(dx1, dy0));
        let g1 = corner_turn(-dx1 * dy1, dz0, corner_len(dx1, dy1));
        let g2 = corner_turn(dx0 * dy1, dz0, corner_len(dx0, dy1));
        let g3 = corner_turn(-dx0 * dy0, dz0, corner_len(dx0, dy0));
        // The product's argument is Ω; its length (the normals' lengths squared, eight powers
        // of the distances: within f64's range for any f32 coordinates) does not matter, so
        // Ω does not wait for a normalisation.
        let g23 = turn(g2, g3);
        let all = turn(turn(g0, g1), g23);
        // e^{i(g₂ + g₃)}, normalised: the sample's offset angle k needs its cosine and sine.
        let g23 = g23 * (1.0 / g23.length());
        // The product is exact to f64 and its argument to `complex_arg::ARG_RELATIVE_ERROR`
        // (5e-11), far under the f32 Ω is kept in.
        Angles {
            omega: arg(all),
            turns: [g0, g1, g2, g3],
            b0: (-dy0 / l0) as f32,
            b1: (dy1 / l2) as f32,
            one_minus_b0_sq: (zz / (l0 * l0)) as f32,
            // k = 2π − g₂ − g₃: e^{ik} is the conjugate of e^{i(g₂ + g₃)}.
            cos_k: g23.x as f32,
            sin_k: -g23.y as f32,
        }
    }

    /// The spherical rectangle of solid angle `solid_angle` these angles describe.
    #[inline(always)]
    pub(super) fn rect(
        &self,
        c: &FrameCoordinates,
        frame: &RectFrame,
        solid_angle: f32,
    ) -> SphericalRect {
        SphericalRect {
            x: frame.x,
            y: frame.y,
            z: c.z,
            z0: c.z0,
            x0: c.x0,
            x1: c.x1,
            y0: c.y0,
            y1: c.y1,
            inv_width: frame.inv_width,
            inv_height: frame.inv_height,
            b0: self.b0,
            b1: self.b1,
            one_minus_b0_sq: self.one_minus_b0_sq,
            cos_k: self.cos_k,
            sin_k: self.sin_k,
            solid_angle,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::spherical;
    use super::*;

    /// Solid angle of the sub-rectangle `[s0, s1] × [t0, t1]` from `p`, as two triangles.
    fn rect_omega(p: Vec3, c: Vec3, ex: Vec3, ey: Vec3, s: (f32, f32), t: (f32, f32)) -> f32 {
        let q = |a: f32, b: f32| c + a * ex + b * ey;
        let (a, b, cc, d) = (q(s.0, t.0), q(s.1, t.0), q(s.1, t.1), q(s.0, t.1));
        spherical::solid_angle(p, &[a, b, cc]) + spherical::solid_angle(p, &[a, cc, d])
    }

    fn cases() -> Vec<(Vec3, Vec3, Vec3, Vec3)> {
        let (c, ex, ey) = (
            Vec3::new(-0.3, 1.0, -0.15),
            Vec3::new(0.6, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.3),
        );
        vec![
            (Vec3::ZERO, c, ex, ey),
            (Vec3::new(0.7, 0.2, -0.4), c, ex, ey),
            // Close: the light fills most of the hemisphere.
            (Vec3::new(0.05, 0.99, 0.02), c, ex, ey),
            // Grazing: 2 away, 0.05 below the light's plane.
            (Vec3::new(2.0, 0.95, 0.0), c, ex, ey),
            // Tilted, seen from above (z flips).
            (
                Vec3::new(0.2, 3.0, 0.1),
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(0.5, 0.2, 0.0),
                Vec3::new(-0.08, 0.2, 0.4),
            ),
        ]
    }

    #[test]
    fn solid_angle_is_that_of_its_two_triangles() {
        for (p, c, ex, ey) in cases() {
            let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
            let expected = rect_omega(p, c, ex, ey, (0.0, 1.0), (0.0, 1.0));
            let rel = (r.solid_angle() / expected - 1.0).abs();
            assert!(rel < 1e-3, "from {p}: {} vs {expected}", r.solid_angle());
        }
        // Far and grazing (Ω ≈ 3e-5 sr, under `spherical::MIN_SOLID_ANGLE`, where a caller
        // samples by area as `area` does for triangles): still close.
        let (p, c, ex, ey) = (
            Vec3::new(5.0, 0.98, 0.0),
            cases()[0].1,
            cases()[0].2,
            cases()[0].3,
        );
        let tiny = rect_omega(p, c, ex, ey, (0.0, 1.0), (0.0, 1.0));
        assert!(tiny < spherical::MIN_SOLID_ANGLE);
        let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
        assert!((r.solid_angle() / tiny - 1.0).abs() < 0.02);
        let flat = SphericalRect::new(
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-0.3, 1.0, -0.15),
            Vec3::X,
            Vec3::Z,
        );
        assert!(flat.is_none());
    }

    /// Light-frame coordinates near f32's largest (where the corners' product overflowed f64
    /// and its argument was NaN) and among its subnormals (where it underflowed): the same
    /// configuration scaled by a power of two, every coordinate exact, gives the same angles to
    /// the bit as at scale 1 (the set-up is homogeneous of degree 0).
    #[test]
    fn extreme_coordinates_give_the_angles_of_scale_one() {
        // Few mantissa bits, so every coordinate is exact as a subnormal too; p at the origin
        // and axis-aligned edges, so the frame's dot products are exact. At 2¹²⁷ the
        // coordinates are 3.2e38 and the unscaled product 2¹⁰²⁵.
        let frame = RectFrame::new(
            Vec3::new(-1.875, 1.875, -1.875),
            Vec3::new(1.875, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.875),
        )
        .expect("not degenerate");
        let base = SphericalRect::seen_from(Vec3::ZERO, &frame).expect("seen");
        let angles = |r: &SphericalRect| {
            [
                r.solid_angle,
                r.b0,
                r.b1,
                r.one_minus_b0_sq,
                r.cos_k,
                r.sin_k,
            ]
            .map(f32::to_bits)
        };
        // A square whose corner is straight above p, as high as it is wide: Ω = π/6.
        assert!((base.solid_angle - std::f32::consts::FRAC_PI_6).abs() < 1e-6);
        for k in [127, 100, 61, 60, -60, -61, -100, -126, -133] {
            let s = 2f64.powi(k) as f32;
            let scaled = RectFrame {
                corner: frame.corner * s,
                exl: frame.exl * s,
                eyl: frame.eyl * s,
                ..frame
            };
            let r = SphericalRect::seen_from(Vec3::ZERO, &scaled)
                .unwrap_or_else(|| panic!("at scale 2^{k}: not seen"));
            assert_eq!(angles(&r), angles(&base), "at scale 2^{k}");
            assert_eq!(
                [r.x0, r.x1, r.y0, r.y1, r.z0],
                [base.x0, base.x1, base.y0, base.y1, base.z0].map(|c| c * s)
            );
        }
        // A coordinate beyond f32's range (a point at infinity) has no angles.
        let far = Vec3::new(f32::MAX, 0.0, 0.0);
        assert!(SphericalRect::seen_from(
            -far,
            &RectFrame {
                corner: far,
                ..frame
            }
        )
        .is_none());
    }

    /// Samples on a 64×64 grid of `u` land on the rectangle, and the share falling in each of
    /// 4×4 sub-rectangles is that sub-rectangle's share of the solid angle (uniform density
    /// `1 / Ω`, so it integrates to 1): a quadrature of 4096 points per case, each cell's
    /// share within 0.004 (about a quarter of a row of the grid, 64/4096).
    #[test]
    fn samples_are_uniform_in_solid_angle() {
        let n = 64;
        for (p, c, ex, ey) in cases() {
            let r = SphericalRect::new(p, c, ex, ey).expect("not degenerate");
            let mut cells = [0u32; 16];
            for i in 0..n {
                for j in 0..n {
                    let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let q = p + r.sample(u).offset - c;
                    let (s, t) = (
                        q.dot(ex) / ex.length_squared(),
                        q.dot(ey) / ey.length_squared(),
                    );
                    assert!(
                        (-1e-3..=1.001).contains(&s) && (-1e-3..=1.001).contains(&t),
                        "{s} {t}"
                    );
                    let plane = (q - s * ex - t * ey).length();
                    assert!(
                        plane < 1e-3 * (ex.length() + ey.length()),
                        "off the plane: {plane}"
                    );
                    let (a, b) = (((s * 4.0) as usize).min(3), ((t * 4.0) as usize).min(3));
                    cells[b * 4 + a] += 1;
                }
            }
            for a in 0..4 {
                for b in 0..4 {
                    let (s0, t0) = (a as f32 / 4.0, b as f32 / 4.0);
                    let share = rect_omega(p, c, ex, ey, (s0, s0 + 0.25), (t0, t0 + 0.25))
                        / r.solid_angle();
                    let got = cells[b * 4 + a] as f32 / (n * n) as f32;
                    assert!(
                        (got - share).abs() < 4e-3,
                        "from {p}, cell ({a},{b}): {got} vs {share}"
                    );
                }
            }
        }
    }
}
