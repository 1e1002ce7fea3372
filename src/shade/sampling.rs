//! Sampling routines: warps from the unit square to directions (cosine-weighted hemisphere,
//! Phong lobe, uniform sphere) with their densities, and Veach's power heuristic that combines
//! two strategies in multiple importance sampling.
//!
//! Every routine is a pure function of its random numbers `u ∈ [0, 1)²`: where those come from
//! (hashed per pixel sample, stratified over the pixel) is the render loop's business
//! (`render::rng`), not this layer's.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

/// A direction around unit `n` with density `cos θ / π` (Malley's method on a concentric disk).
pub fn cosine_hemisphere(n: Vec3, u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    let (t, b) = n.any_orthonormal_pair();
    (d.x * t + d.y * b + z * n).normalize()
}

/// A direction around unit `axis` with density `(n + 1)/(2π) · cos^n α` over the hemisphere
/// of `axis`.
pub fn phong_lobe(axis: Vec3, n: f32, u: Vec2) -> Vec3 {
    let cos_alpha = u.x.powf(1.0 / (n + 1.0));
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    let (t, b) = axis.any_orthonormal_pair();
    (sin_alpha * (phi.cos() * t + phi.sin() * b) + cos_alpha * axis).normalize()
}

fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    // θ = a in the wedges around ±x, θ = π/2 − a around ±y, with |a| ≤ π/4 either way.
    if o.x.abs() > o.y.abs() {
        let (sin, cos) = quarter_sin_cos(PI / 4.0 * (o.y / o.x));
        o.x * Vec2::new(cos, sin)
    } else {
        let (sin, cos) = quarter_sin_cos(PI / 4.0 * (o.x / o.y));
        o.y * Vec2::new(sin, cos)
    }
}

/// `(sin a, cos a)` for `|a| ≤ π/4`, within 2e-7 of the exact values: the minimax
/// polynomials of Cephes' `sinf`/`cosf` on that interval (no range reduction, no libm call:
/// libm's `sincosf` was a fifth of the cosine direction's time on env-bench,
/// docs/speed.md).
#[inline]
fn quarter_sin_cos(a: f32) -> (f32, f32) {
    let a2 = a * a;
    let sin = a + a * a2 * (-1.666_665_5e-1 + a2 * (8.332_161e-3 + a2 * -1.951_529_6e-4));
    let cos =
        1.0 - 0.5 * a2 + a2 * a2 * (4.166_664_6e-2 + a2 * (-1.388_731_6e-3 + a2 * 2.443_315_7e-5));
    (sin, cos)
}

/// A direction uniform over the unit sphere (density `1 / 4π`).
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Veach's power heuristic (β = 2) for a sample of the strategy with effective density `own`
/// (sample count × density) against `other`: `own² / (own² + other²)`.
#[inline]
pub fn power_heuristic(own: f32, other: f32) -> f32 {
    // NaN densities count as zero.
    if own.is_nan() || own <= 0.0 {
        return 0.0;
    }
    if other.is_nan() || other <= 0.0 {
        return 1.0;
    }
    let r = other / own;
    1.0 / (1.0 + r * r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_sin_cos_matches_the_exact_values() {
        let mut worst = 0.0f64;
        for k in -2000..=2000 {
            let a = (PI / 4.0) * k as f32 / 2000.0;
            let (sin, cos) = quarter_sin_cos(a);
            let exact = (a as f64).sin_cos();
            worst = worst.max(
                (sin as f64 - exact.0)
                    .abs()
                    .max((cos as f64 - exact.1).abs()),
            );
        }
        assert!(worst < 2e-7, "worst error {worst:e}");
    }

    #[test]
    fn power_heuristic_weights_sum_to_one() {
        for (a, b) in [(1.0, 1.0), (3.0, 0.5), (1e-20, 1e20), (0.0, 2.0)] {
            let s = power_heuristic(a, b) + power_heuristic(b, a);
            assert!((s - 1.0).abs() < 1e-6, "{a} {b}");
        }
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
