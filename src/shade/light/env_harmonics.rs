//! Shading layer: the sky's smooth part as spherical harmonics, a control variate for the
//! direct lighting of diffuse surfaces under an environment (`light sky = environment { … }`).
//!
//! The sky without its bright set (`env_bright`) and with the constant part added is
//! projected onto the real spherical harmonics of degree ≤ [`DEGREE`] at build time
//! ([`SkyHarmonics`]). For that band-limited radiance `L̃`, the cosine-weighted integral over a
//! hemisphere has a closed form (Funk–Hecke; Ramamoorthi & Hanrahan 2001):
//! `∫ L̃(ω) max(0, n·ω) dω = Σ A_l c_lm Y_lm(n)`, exactly, whatever the coefficients. So the
//! render estimates `∫ L V f cos` as `f · E(n) + ∫ (L V − L̃) f cos`, the second integral by
//! the usual samples (`render::mis`): the sum stays unbiased (the closed form is the integral
//! of exactly the function subtracted), and where the sky is seen whole (open ground, the tops
//! of objects) the samples only estimate the small difference between the sky and its smooth
//! fit. On env-bench's gradient sky (a step at the horizon) the fit to degree 2 leaves 13–30% of
//! the cosine-sampled variance on open ground, degree 4 4–11%; in the render the two measured
//! the same (the rest is visibility), so degree 2, with 9 coefficients per channel, is kept
//! (docs/speed.md).

use std::f32::consts::PI;

use glam::{DVec3, Vec3, Vec3A};

use crate::shade::color::luminance;

/// The highest degree `l` of the fit.
pub const DEGREE: usize = 2;
/// Coefficients per colour channel: `(DEGREE + 1)²`.
pub const COEFFS: usize = (DEGREE + 1) * (DEGREE + 1);

/// `A_l`: the clamped cosine's Funk–Hecke factors, `∫ Y_lm(ω) max(0, n·ω) dω = A_l Y_lm(n)`
/// (`π`, `2π/3`, `π/4`, `0`, `−π/24`).
const COSINE_LOBE: [f32; 5] = [PI, 2.0 * PI / 3.0, PI / 4.0, 0.0, -PI / 24.0];

/// A radiance function over directions as spherical-harmonic coefficients (world space, linear
/// RGB).
#[derive(Debug, Clone, PartialEq)]
pub struct SkyHarmonics {
    coeffs: [Vec3A; COEFFS],
    /// `A_l c_lm`, for [`SkyHarmonics::irradiance`].
    irradiance_coeffs: [Vec3A; COEFFS],
    /// [`SkyHarmonics::relative_residual`].
    residual: f32,
}

/// The real, orthonormal spherical harmonics of degree ≤ [`DEGREE`] at unit direction `d`, by
/// degree and order (`l² + l + m`).
#[inline]
pub fn basis(d: Vec3) -> [f32; COEFFS] {
    let all = basis_to_degree_4(d);
    std::array::from_fn(|i| all[i])
}

/// The real, orthonormal spherical harmonics of degree ≤ 4 (Sloan, "Stupid spherical harmonics
/// tricks", 2008, appendix A2), by degree and order.
#[inline(always)]
fn basis_to_degree_4(d: Vec3) -> [f32; 25] {
    let (x, y, z) = (d.x, d.y, d.z);
    let (x2, y2, z2) = (x * x, y * y, z * z);
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z2 - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x2 - y2),
        0.590_043_6 * y * (3.0 * x2 - y2),
        2.890_611_4 * x * y * z,
        0.457_045_8 * y * (5.0 * z2 - 1.0),
        0.373_176_33 * z * (5.0 * z2 - 3.0),
        0.457_045_8 * x * (5.0 * z2 - 1.0),
        1.445_305_7 * z * (x2 - y2),
        0.590_043_6 * x * (x2 - 3.0 * y2),
        2.503_343 * x * y * (x2 - y2),
        1.770_130_8 * y * z * (3.0 * x2 - y2),
        0.946_174_7 * x * y * (7.0 * z2 - 1.0),
        0.669_046_5 * y * z * (7.0 * z2 - 3.0),
        0.105_785_55 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0),
        0.669_046_5 * x * z * (7.0 * z2 - 3.0),
        0.473_087_35 * (x2 - y2) * (7.0 * z2 - 1.0),
        1.770_130_8 * x * z * (x2 - 3.0 * y2),
        0.625_835_7 * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2)),
    ]
}

/// The degree of coefficient `i` (`l² + l + m`).
const fn degree_of(i: usize) -> usize {
    let mut l = 0;
    while (l + 1) * (l + 1) <= i {
        l += 1;
    }
    l
}

impl SkyHarmonics {
    /// The projection of a radiance function given at quadrature points: `(direction (unit),
    /// radiance, solid angle)` each, and the fit's [`SkyHarmonics::relative_residual`] over the
    /// same points. `None` if a coefficient is not finite.
    pub fn project(points: &[(Vec3, Vec3, f64)]) -> Option<SkyHarmonics> {
        let mut sums = [DVec3::ZERO; COEFFS];
        for &(d, radiance, solid_angle) in points {
            let weighted = radiance.as_dvec3() * solid_angle;
            for (sum, y) in sums.iter_mut().zip(basis(d)) {
                *sum += weighted * y as f64;
            }
        }
        let coeffs = sums.map(|s| Vec3A::from(s.as_vec3()));
        if !coeffs.iter().all(|c| c.is_finite()) {
            return None;
        }
        let mut fit = SkyHarmonics::from_coeffs(coeffs);
        let (mut departure, mut energy) = (0.0f64, 0.0f64);
        for &(d, radiance, solid_angle) in points {
            let seen = luminance(radiance) as f64;
            let fitted = luminance(fit.radiance(d)) as f64;
            departure += (seen - fitted) * (seen - fitted) * solid_angle;
            energy += seen * seen * solid_angle;
        }
        fit.residual = if energy > 0.0 {
            (departure / energy).sqrt() as f32
        } else {
            0.0
        };
        Some(fit)
    }

    fn from_coeffs(coeffs: [Vec3A; COEFFS]) -> SkyHarmonics {
        let mut irradiance_coeffs = coeffs;
        for (i, c) in irradiance_coeffs.iter_mut().enumerate() {
            *c *= COSINE_LOBE[degree_of(i)];
        }
        SkyHarmonics {
            coeffs,
            irradiance_coeffs,
            residual: 0.0,
        }
    }

    /// How far the projected radiance departs from its fit, relative to the radiance itself:
    /// `sqrt(∫ (ℓ − ℓ̃)² dω / ∫ ℓ² dω)` over the projection's points, `ℓ` the luminance (0
    /// for a black or constant sky). env-bench's sky without its sun: 0.15 (the step at the
    /// horizon); a 30° window five times as bright as the rest of a constant sky: 0.40.
    pub fn relative_residual(&self) -> f32 {
        self.residual
    }

    /// The fit plus a radiance `constant` from every direction (its residual kept: the
    /// constant is fitted exactly).
    pub fn with_constant(&self, constant: Vec3) -> SkyHarmonics {
        let mut coeffs = self.coeffs;
        // ∫ c · Y_00 dω = c · 4π · Y_00.
        coeffs[0] += Vec3A::from(constant) * (4.0 * PI * basis(Vec3::Y)[0]);
        SkyHarmonics {
            residual: self.residual,
            ..SkyHarmonics::from_coeffs(coeffs)
        }
    }

    /// A constant radiance from every direction.
    pub fn constant(radiance: Vec3) -> SkyHarmonics {
        SkyHarmonics::from_coeffs([Vec3A::ZERO; COEFFS]).with_constant(radiance)
    }

    /// The fitted radiance arriving from unit direction `d`.
    #[inline]
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        dot(&self.coeffs, d)
    }

    /// `∫ L̃(ω) max(0, n·ω) dω` over the sphere, for unit `n` (exact for the fit).
    #[inline]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        dot(&self.irradiance_coeffs, n)
    }
}

#[inline]
fn dot(coeffs: &[Vec3A; COEFFS], d: Vec3) -> Vec3 {
    let y = basis(d);
    let mut sum = Vec3A::ZERO;
    for (c, y) in coeffs.iter().zip(y) {
        sum += *c * y;
    }
    sum.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A midpoint quadrature over the sphere in `θ` × `φ` cells: (direction, solid angle).
    fn sphere_points(rows: usize) -> Vec<(Vec3, f64)> {
        let cols = 2 * rows;
        let mut out = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            let (t0, t1) = (
                std::f64::consts::PI * r as f64 / rows as f64,
                std::f64::consts::PI * (r + 1) as f64 / rows as f64,
            );
            let theta = 0.5 * (t0 + t1);
            let omega = std::f64::consts::TAU / cols as f64 * (t0.cos() - t1.cos());
            for c in 0..cols {
                let phi = std::f64::consts::TAU * (c as f64 + 0.5) / cols as f64;
                let d = glam::DVec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                out.push((d.as_vec3(), omega));
            }
        }
        out
    }

    #[test]
    fn the_basis_is_orthonormal() {
        let points = sphere_points(400);
        let mut gram = [[0.0f64; COEFFS]; COEFFS];
        for (d, w) in &points {
            let y = basis(*d);
            for i in 0..COEFFS {
                for j in 0..COEFFS {
                    gram[i][j] += y[i] as f64 * y[j] as f64 * w;
                }
            }
        }
        for (i, row) in gram.iter().enumerate() {
            for (j, &g) in row.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((g - expected).abs() < 2e-3, "<Y{i}, Y{j}> = {g}");
            }
        }
    }

    #[test]
    fn irradiance_is_the_cosine_weighted_integral_of_the_fit() {
        // A fit with every coefficient set, then the closed form against quadrature.
        let coeffs: [Vec3A; COEFFS] = std::array::from_fn(|i| {
            let t = i as f32;
            Vec3A::new((t * 0.37).sin(), (t * 0.71).cos(), 0.3 - 0.05 * t)
        });
        let sky = SkyHarmonics::from_coeffs(coeffs);
        let points = sphere_points(600);
        for n in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
            Vec3::new(-0.9, 0.1, 0.2).normalize(),
        ] {
            let mut sum = DVec3::ZERO;
            for (d, w) in &points {
                let cos = n.dot(*d).max(0.0) as f64;
                sum += sky.radiance(*d).as_dvec3() * cos * *w;
            }
            let closed = sky.irradiance(n).as_dvec3();
            assert!(
                (closed - sum).abs().max_element() < 2e-3 * sum.abs().max_element().max(1.0),
                "n = {n}: closed form {closed}, quadrature {sum}"
            );
        }
    }

    #[test]
    fn projection_reproduces_a_band_limited_sky_and_a_constant() {
        let sky = |d: Vec3| {
            Vec3::new(
                0.5 + 0.3 * d.y,
                0.2 + 0.1 * d.x * d.z,
                1.0 - 0.4 * d.y * d.y,
            )
        };
        let points = sphere_points(300);
        let points: Vec<_> = points.iter().map(|&(d, w)| (d, sky(d), w)).collect();
        let fit = SkyHarmonics::project(&points).unwrap();
        for d in [Vec3::Y, Vec3::X, Vec3::new(0.6, -0.64, 0.48)] {
            assert!((fit.radiance(d) - sky(d)).abs().max_element() < 1e-3, "{d}");
        }
        assert!(
            fit.relative_residual() < 1e-3,
            "{}",
            fit.relative_residual()
        );
        let c = SkyHarmonics::constant(Vec3::new(0.5, 1.0, 2.0));
        assert!(
            (c.radiance(Vec3::X) - Vec3::new(0.5, 1.0, 2.0))
                .abs()
                .max_element()
                < 1e-5
        );
        // A constant sky gives π L on any surface.
        let e = c.irradiance(Vec3::new(0.0, 0.6, 0.8));
        assert!(
            (e - PI * Vec3::new(0.5, 1.0, 2.0)).abs().max_element() < 1e-4,
            "{e}"
        );
    }

    #[test]
    fn the_residual_tells_a_smooth_sky_from_one_with_a_bright_window() {
        // A constant sky with a patch of about 30° × 30°, `gain` times as bright.
        let residual = |gain: f32| {
            let window = |d: Vec3| d.y > 0.5 && d.y < 0.87 && d.x > 0.0 && d.z.abs() < 0.25;
            let points: Vec<_> = sphere_points(200)
                .into_iter()
                .map(|(d, w)| (d, Vec3::splat(if window(d) { 0.3 * gain } else { 0.3 }), w))
                .collect();
            SkyHarmonics::project(&points).unwrap().relative_residual()
        };
        assert!(residual(1.0) < 1e-3, "constant: {}", residual(1.0));
        // The departure grows with the window's contrast.
        let (dim, bright) = (residual(2.0), residual(5.0));
        assert!(dim < bright, "{dim} {bright}");
        assert!(bright > 0.3, "{bright}");
        let black: Vec<_> = sphere_points(20)
            .into_iter()
            .map(|(d, w)| (d, Vec3::ZERO, w))
            .collect();
        assert_eq!(
            SkyHarmonics::project(&black).unwrap().relative_residual(),
            0.0
        );
    }
}
