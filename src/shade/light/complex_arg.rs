//! Shading layer: the argument of a complex number in f64, for the spherical rectangle's
//! set-up (`spherical_rect`), whose solid angle Ω is the argument of a product of the four
//! corners' unnormalised turns.
//!
//! libm's `atan2f` was 5% of a cornell render's time (a call, its own range reduction and
//! special cases, and the f64 → f32 conversions before it). This is a reduction to
//! `|t| ≤ tan(π/8)` (one division) and an odd polynomial of degree 13 fitted to `atan` there,
//! relative error 2.1e-11: three thousand times under f32's half ulp (6e-8), which is all the
//! sampling reads (Ω is stored as f32). `tests` check the bound against libm's f64
//! `atan2` over seeded points of every quadrant and magnitude, tiny angles included (where Ω's
//! relative precision is what matters: a relative error in the polynomial, not an absolute
//! one).

use glam::DVec2;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// `tan(π/8)`: the reduced argument's bound.
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;

/// The documented relative bound on [`arg`]'s error against the exact argument (the fit's
/// 2.1e-11 plus a few f64 roundings).
pub const ARG_RELATIVE_ERROR: f64 = 5e-11;

/// `atan(t) / t ≈ Σ cᵢ·t²ⁱ` on `t² ≤ (1.001·tan(π/8))²`: a least-squares fit at Chebyshev
/// nodes (near-minimax), maximum relative error 2.1e-11 on that range (measured on 200,001
/// points; `tests` check the resulting bound).
const ATAN_FIT: [f64; 7] = [
    0.999_999_999_978_855_7,
    -0.333_333_321_145_363_3,
    0.199_998_848_628_381_55,
    -0.142_816_103_096_417_7,
    0.110_406_929_572_651_64,
    -0.084_570_527_732_413_22,
    0.047_086_432_724_996_55,
];

/// `atan(t)` for `|t| ≤ tan(π/8)` (a little beyond, where the thresholds round), the
/// polynomial in `s = t²` evaluated by Estrin's scheme (a short dependency chain: the set-up
/// waits on it).
#[inline]
fn atan_reduced(t: f64) -> f64 {
    let c = ATAN_FIT;
    let s = t * t;
    let s2 = s * s;
    let s4 = s2 * s2;
    let low = (c[0] + c[1] * s) + s2 * (c[2] + c[3] * s);
    let high = (c[4] + c[5] * s) + s2 * c[6];
    t * (low + s4 * high)
}

/// The argument of `v` in [−π, π] (as `atan2(v.y, v.x)`, 0 for the origin), to within
/// [`ARG_RELATIVE_ERROR`] of its magnitude. Not finite for a non-finite `v`.
#[inline]
pub fn arg(v: DVec2) -> f64 {
    let (a, b) = (v.x.abs(), v.y.abs());
    // The angle of (a, b) in [0, π/2] as base ± atan(n / d), |n / d| ≤ tan(π/8): chosen by
    // selects, one division.
    let (n, d, base, sign) = if b <= a * TAN_PI_8 {
        (b, a, 0.0, 1.0)
    } else if a <= b * TAN_PI_8 {
        (a, b, FRAC_PI_2, -1.0)
    } else {
        (b - a, b + a, FRAC_PI_4, 1.0)
    };
    let first_quadrant = base + sign * atan_reduced(n / d);
    let half = if v.x < 0.0 {
        PI - first_quadrant
    } else {
        first_quadrant
    };
    // Selects rather than branches, so that several lanes' arguments can be taken side by
    // side (`rect_lanes`); the origin's `0 / 0` above is NaN, its argument 0 (as `atan2`'s).
    if a == 0.0 && b == 0.0 {
        0.0
    } else {
        half.copysign(v.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seeded xorshift: points over every quadrant, magnitudes from 1e-30 to 1e30, and angles
    /// from 1e-12 rad up.
    fn points() -> Vec<DVec2> {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut unit = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut out = Vec::new();
        for _ in 0..200_000 {
            let angle = (unit() * 2.0 - 1.0) * PI;
            let scale = 10f64.powf(unit() * 60.0 - 30.0);
            out.push(DVec2::new(angle.cos(), angle.sin()) * scale);
            // Tiny angles off each axis (the spherical rectangle's Ω of a far light).
            let tiny = 10f64.powf(-12.0 * unit());
            out.push(DVec2::new(1.0, tiny) * scale);
            out.push(DVec2::new(-tiny, 1.0) * scale);
            out.push(DVec2::new(-1.0, -tiny) * scale);
        }
        out
    }

    #[test]
    fn arg_is_atan2_within_its_bound() {
        let mut worst = 0.0f64;
        for v in points() {
            let (got, want) = (arg(v), v.y.atan2(v.x));
            let rel = (got - want).abs() / want.abs().max(f64::MIN_POSITIVE);
            worst = worst.max(rel);
            assert!(rel <= ARG_RELATIVE_ERROR, "{v}: {got} vs {want}");
        }
        // The bound is not loose by orders of magnitude: the polynomial's own error shows.
        assert!(worst > ARG_RELATIVE_ERROR / 1e3, "{worst}");
    }

    #[test]
    fn arg_at_the_axes_and_the_origin() {
        assert_eq!(arg(DVec2::ZERO), 0.0);
        assert_eq!(arg(DVec2::new(2.0, 0.0)), 0.0);
        assert!((arg(DVec2::new(0.0, 3.0)) - FRAC_PI_2).abs() < 1e-15);
        assert!((arg(DVec2::new(-1.0, 0.0)) - PI).abs() < 1e-15);
        assert!((arg(DVec2::new(-1.0, -0.0)) + PI).abs() < 1e-15);
        assert!((arg(DVec2::new(0.0, -5.0)) + FRAC_PI_2).abs() < 1e-15);
        assert!(arg(DVec2::new(f64::NAN, 1.0)).is_nan());
    }
}
