//! Shading layer: the sky's exact cosine integral for a vertical normal (a floor or a
//! ceiling), the control variate of `render::mis::vertical_sky`
//! (`light sky = environment { image("sky.hdr") }`).
//!
//! A nearest-texel map is piecewise constant over its texels, and a texel spans `φ ∈ [φ₀, φ₁)`,
//! `θ ∈ [θ₀, θ₁)` in map space, so for the normal `+y` (`−y`), which the map's rotation about
//! `y` leaves in place, the cosine-weighted integral over a texel has a closed form:
//! `∫ max(0, ±cos θ) sin θ dθ dφ = Δφ · |sin² θ_a − sin² θ_b| / 2` over the part of
//! `[θ₀, θ₁]` on the normal's side of the horizon. Summed over the texels (in f64), that is the
//! irradiance `∫ L(ω) max(0, n·ω) dω` of the sky itself, not of a fit: a diffuse point facing
//! straight up that subtracts the sky exactly needs to estimate only what it does not see, and
//! a direction it does see adds exactly nothing (no texel is read for it). The bright set
//! (`env_bright`, sampled on its own) is left out, as from the harmonics fit.

use glam::{DVec3, Vec3};

/// `[∫ L max(0, ω_y) dω, ∫ L max(0, −ω_y) dω]` (map space, so world space too: the rotation
/// is about `y`) of a `width × height` equirectangular map whose texel (`col`, `row`) has
/// radiance `texel(col, row)`, `None` for a texel left out.
pub fn vertical_irradiance(
    width: usize,
    height: usize,
    texel: impl Fn(usize, usize) -> Option<Vec3>,
) -> [Vec3; 2] {
    let half_pi = std::f64::consts::FRAC_PI_2;
    let d_phi = std::f64::consts::TAU / width.max(1) as f64;
    let theta = |r: usize| std::f64::consts::PI * r as f64 / height as f64;
    let sin2 = |t: f64| t.sin() * t.sin();
    let (mut up, mut down) = (DVec3::ZERO, DVec3::ZERO);
    for row in 0..height {
        let (t0, t1) = (theta(row), theta(row + 1));
        // ∫ cos θ sin θ dθ = sin² θ / 2, split at the horizon.
        let w_up = if t0 < half_pi {
            (sin2(t1.min(half_pi)) - sin2(t0)) * 0.5 * d_phi
        } else {
            0.0
        };
        let w_down = if t1 > half_pi {
            (sin2(t0.max(half_pi)) - sin2(t1)) * 0.5 * d_phi
        } else {
            0.0
        };
        let mut line = DVec3::ZERO;
        for col in 0..width {
            if let Some(l) = texel(col, row) {
                line += l.as_dvec3();
            }
        }
        up += line * w_up;
        down += line * w_down;
    }
    [up.as_vec3(), down.as_vec3()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map-space direction of the centre of texel (`col`, `row`) of a `w × h` map.
    fn centre(col: usize, row: usize, w: usize, h: usize) -> Vec3 {
        let theta = std::f32::consts::PI * (row as f32 + 0.5) / h as f32;
        let phi = std::f32::consts::TAU * (col as f32 + 0.5) / w as f32;
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.cos(),
            theta.sin() * phi.sin(),
        )
    }

    #[test]
    fn a_constant_sky_gives_pi_l_on_both_sides() {
        for (w, h) in [(64, 32), (7, 5), (1, 1)] {
            let [up, down] = vertical_irradiance(w, h, |_, _| Some(Vec3::new(0.5, 1.0, 2.0)));
            let expected = std::f32::consts::PI * Vec3::new(0.5, 1.0, 2.0);
            assert!((up - expected).abs().max_element() < 1e-5, "{w}x{h}: {up}");
            assert!(
                (down - expected).abs().max_element() < 1e-5,
                "{w}x{h}: {down}"
            );
        }
    }

    #[test]
    fn it_matches_a_fine_quadrature_of_a_textured_map_with_texels_left_out() {
        // A map with structure in both angles and an odd height (a row across the horizon),
        // a few texels left out; against a midpoint quadrature 64× finer in each angle.
        let (w, h) = (24, 13);
        let texel = |c: usize, r: usize| {
            ((c + 2 * r) % 7 != 3).then(|| {
                let d = centre(c, r, w, h);
                Vec3::new(
                    1.0 + d.x,
                    0.5 + 0.4 * (c as f32 * 0.7).sin(),
                    0.2 + r as f32 * 0.1,
                )
            })
        };
        let [up, down] = vertical_irradiance(w, h, texel);
        let k = 64;
        let (mut q_up, mut q_down) = (DVec3::ZERO, DVec3::ZERO);
        for r in 0..h * k {
            let t0 = std::f64::consts::PI * r as f64 / (h * k) as f64;
            let t1 = std::f64::consts::PI * (r + 1) as f64 / (h * k) as f64;
            let t = 0.5 * (t0 + t1);
            let omega = std::f64::consts::TAU / (w * k) as f64 * (t0.cos() - t1.cos());
            for c in 0..w * k {
                if let Some(l) = texel(c / k, r / k) {
                    q_up += l.as_dvec3() * t.cos().max(0.0) * omega;
                    q_down += l.as_dvec3() * (-t.cos()).max(0.0) * omega;
                }
            }
        }
        for (exact, quad) in [(up, q_up), (down, q_down)] {
            let quad = quad.as_vec3();
            assert!(
                (exact - quad).abs().max_element() < 1e-3 * quad.max_element(),
                "{exact} against {quad}"
            );
        }
    }
}
