//! Shading layer: sampling a triangle light by solid angle (Arvo 1995, "Stratified Sampling of
//! Spherical Triangles"; the formulation of pbrt-v4).
//!
//! Area sampling picks points uniformly on the triangle, so its estimator carries the factor
//! `cos θ_l / r²`, which varies wildly over a light that is large or close compared with its
//! distance. Sampling the spherical triangle the light subtends uniformly removes that factor
//! (the estimate becomes `L_e · f · cos θ · Ω`), leaving only the BRDF and cosine to vary.
//! `area` uses it when the subtended solid angle is in
//! [`MIN_SOLID_ANGLE`, `MAX_SOLID_ANGLE`]: below, f64 rounding makes the angles unreliable and
//! the two methods are equivalent anyway; above, the triangle nearly covers the hemisphere.
//! The measurement that justifies it is `tests/render_light_sampling.rs`. Arithmetic is in f64
//! because the spherical angles lose precision quickly for small triangles.

use glam::{DVec3, Vec2, Vec3};

/// Below this solid angle (sr) a triangle is sampled by area: f64 rounding makes the spherical
/// angles unreliable, and the two methods agree anyway.
pub const MIN_SOLID_ANGLE: f32 = 1e-4;
/// Above this solid angle (sr, just under 2π) the triangle nearly covers the hemisphere and is
/// sampled by area.
pub const MAX_SOLID_ANGLE: f32 = 6.22;

/// Solid angle of triangle `tri` seen from `p` (Van Oosterom & Strackee 1983).
pub fn solid_angle(p: Vec3, tri: &[Vec3; 3]) -> f32 {
    let [a, b, c] = tri.map(|v| (v - p).as_dvec3().normalize_or_zero());
    let det = a.dot(b.cross(c)).abs();
    let denom = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    (2.0 * det.atan2(denom)) as f32
}

fn gram_schmidt(v: DVec3, w: DVec3) -> DVec3 {
    v - v.dot(w) * w
}

fn angle_between(v1: DVec3, v2: DVec3) -> f64 {
    // Numerically stable for nearly parallel and nearly opposite vectors.
    if v1.dot(v2) < 0.0 {
        std::f64::consts::PI - 2.0 * ((v1 + v2).length() / 2.0).clamp(-1.0, 1.0).asin()
    } else {
        2.0 * ((v2 - v1).length() / 2.0).clamp(-1.0, 1.0).asin()
    }
}

/// A unit direction from `p` uniform over the spherical triangle `tri` subtends, and that
/// triangle's solid angle (the pdf is its inverse). `None` if the triangle is degenerate as
/// seen from `p`.
pub fn sample(p: Vec3, tri: &[Vec3; 3], u: Vec2) -> Option<(Vec3, f32)> {
    let [a, b, c] = tri.map(|v| (v - p).as_dvec3().normalize_or_zero());
    let (n_ab, n_bc, n_ca) = (a.cross(b), b.cross(c), c.cross(a));
    if n_ab.length_squared() == 0.0 || n_bc.length_squared() == 0.0 || n_ca.length_squared() == 0.0
    {
        return None;
    }
    let (n_ab, n_bc, n_ca) = (n_ab.normalize(), n_bc.normalize(), n_ca.normalize());
    let alpha = angle_between(n_ab, -n_ca);
    let beta = angle_between(n_bc, -n_ab);
    let gamma = angle_between(n_ca, -n_bc);
    let pi = std::f64::consts::PI;
    let a_pi = alpha + beta + gamma;
    let area = a_pi - pi;
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    // Sample the sub-triangle area A' uniformly in [0, A].
    let ap_pi = pi + (u.x as f64) * (a_pi - pi);
    let (cos_alpha, sin_alpha) = (alpha.cos(), alpha.sin());
    let sin_phi = ap_pi.sin() * cos_alpha - ap_pi.cos() * sin_alpha;
    let cos_phi = ap_pi.cos() * cos_alpha + ap_pi.sin() * sin_alpha;
    let k1 = cos_phi + cos_alpha;
    let k2 = sin_phi - sin_alpha * a.dot(b);
    let cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha)
        / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    if !cos_bp.is_finite() {
        return None;
    }
    let cos_bp = cos_bp.clamp(-1.0, 1.0);
    let sin_bp = (1.0 - cos_bp * cos_bp).max(0.0).sqrt();
    let cp = cos_bp * a + sin_bp * gram_schmidt(c, a).normalize_or_zero();
    // Then a point on the arc from b to c' with the right density.
    let cos_theta = 1.0 - (u.y as f64) * (1.0 - cp.dot(b));
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let w = cos_theta * b + sin_theta * gram_schmidt(cp, b).normalize_or_zero();
    let w = w.normalize_or_zero().as_vec3();
    (w != Vec3::ZERO).then_some((w, area as f32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{triangle::moller_trumbore, Ray};

    const TRI: [Vec3; 3] = [
        Vec3::new(-0.5, 1.0, -0.3),
        Vec3::new(0.8, 1.2, 0.1),
        Vec3::new(0.1, 0.9, 0.9),
    ];

    #[test]
    fn solid_angle_of_an_octant_is_half_pi() {
        let octant = [Vec3::X, Vec3::Y, Vec3::Z];
        assert!((solid_angle(Vec3::ZERO, &octant) - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
        let (_, omega) = sample(Vec3::ZERO, &octant, Vec2::splat(0.3)).expect("proper");
        assert!((omega - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn samples_hit_the_triangle_and_are_uniform_in_solid_angle() {
        let p = Vec3::new(0.1, 0.0, 0.2);
        let omega = solid_angle(p, &TRI);
        let n = 64;
        // ∫ cos θ dω over the spherical triangle (Lambert's form factor integrand), estimated
        // with uniform directions, must match the exact polygon formula.
        let mut integral = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (w, pdf_inv) = sample(p, &TRI, u).expect("proper triangle");
                assert!((pdf_inv - omega).abs() < 1e-4 * omega);
                let hit = moller_trumbore(&Ray::new(p, w), TRI[0], TRI[1], TRI[2]);
                assert!(hit.is_some(), "direction {w} misses");
                integral += (w.y * pdf_inv) as f64;
            }
        }
        integral /= (n * n) as f64;
        let mut exact = 0.0f64;
        for k in 0..3 {
            let a = (TRI[k] - p).normalize().as_dvec3();
            let b = (TRI[(k + 1) % 3] - p).normalize().as_dvec3();
            exact += a.dot(b).acos() * DVec3::Y.dot(a.cross(b).normalize());
        }
        exact = (exact / 2.0).abs();
        assert!(
            (integral - exact).abs() < 2e-3 * exact,
            "{integral} vs {exact}"
        );
    }
}
