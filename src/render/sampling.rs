//! Stage 4: direction sampling for the BRDF strategy of multiple importance sampling
//! (`material m = phong { diffuse …  specular …  shininess n }`), and the power heuristic.
//!
//! The Phong BRDF (see `brdf`) is sampled as a mixture of its two lobes, chosen by their albedo
//! weights (`Σ kd` against `Σ ks`, the lobes' albedos at normal incidence): the diffuse lobe by a
//! cosine-weighted hemisphere (`pdf = cos θ / π`), the specular lobe by `cos^n α` around the
//! mirror direction `r = 2 (ns·wo) ns − wo` (`pdf = (n + 1)/(2π) · cos^n α`, exactly
//! proportional to the lobe). [`Phong::pdf`] is the mixture's density, which is what the MIS
//! weights need whichever lobe produced the direction.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::brdf::Phong;

impl Phong {
    /// Probability of sampling the diffuse lobe; `None` for a black material (nothing to sample).
    #[inline]
    pub fn diffuse_share(&self) -> Option<f32> {
        let d = self.diffuse.max(Vec3::ZERO).element_sum();
        let s = self.specular.max(Vec3::ZERO).element_sum();
        let total = d + s;
        (total > 0.0 && total.is_finite()).then(|| d / total)
    }

    /// A direction for `u` in [0, 1)² (`u.x` also chooses the lobe, then is rescaled), around
    /// the unit shading normal `ns` seen from unit `wo`. May point below the surface (the
    /// specular lobe crosses the horizon): such samples contribute nothing but count.
    pub fn sample(&self, ns: Vec3, wo: Vec3, u: Vec2) -> Option<Vec3> {
        let pd = self.diffuse_share()?;
        if u.x < pd {
            let ux = (u.x / pd).min(1.0 - f32::EPSILON / 2.0);
            Some(cosine_hemisphere(ns, Vec2::new(ux, u.y)))
        } else {
            let ux = ((u.x - pd) / (1.0 - pd)).clamp(0.0, 1.0);
            let axis = 2.0 * ns.dot(wo) * ns - wo;
            Some(phong_lobe(axis, self.exponent(), Vec2::new(ux, u.y)))
        }
    }

    /// The density over solid angle of [`Phong::sample`] at `wi`.
    #[inline]
    pub fn pdf(&self, ns: Vec3, wo: Vec3, wi: Vec3) -> f32 {
        let Some(pd) = self.diffuse_share() else {
            return 0.0;
        };
        let mut pdf = pd * ns.dot(wi).max(0.0) * FRAC_1_PI;
        if pd < 1.0 {
            let axis = 2.0 * ns.dot(wo) * ns - wo;
            let n = self.exponent();
            let cos_alpha = axis.dot(wi).max(0.0);
            pdf += (1.0 - pd) * (n + 1.0) / (2.0 * PI) * cos_alpha.powf(n);
        }
        pdf
    }

    fn exponent(&self) -> f32 {
        self.shininess.max(0.0)
    }
}

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
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
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

    /// Integrates `pdf` over the sphere on a fine (θ, φ) grid.
    fn sphere_integral(pdf: impl Fn(Vec3) -> f32) -> f64 {
        let (nt, np) = (1200, 240);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let theta = (i as f32 + 0.5) / nt as f32 * PI;
            for j in 0..np {
                let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let d = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                );
                sum += (pdf(d) * theta.sin()) as f64;
            }
        }
        sum * (PI as f64 / nt as f64) * (2.0 * PI as f64 / np as f64)
    }

    #[test]
    fn mixture_pdf_integrates_to_one_and_matches_samples() {
        let ns = Vec3::Y;
        let wo = Vec3::new(0.6, 0.8, 0.0);
        for (kd, ks, n) in [(0.8, 0.0, 1.0), (0.5, 0.3, 20.0), (0.0, 0.9, 5.0)] {
            let phong = Phong {
                diffuse: Vec3::splat(kd),
                specular: Vec3::splat(ks),
                shininess: n,
            };
            let total = sphere_integral(|wi| phong.pdf(ns, wo, wi));
            assert!((total - 1.0).abs() < 5e-3, "{kd} {ks} {n}: {total}");
            // E[f·cos/pdf] over samples = the directional albedo ∫ f cos (what the BRDF
            // strategy estimates); stratified samples make this tight.
            let m = 256;
            let mut est = 0.0f64;
            for i in 0..m {
                for j in 0..m {
                    let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                    let wi = phong.sample(ns, wo, u).expect("not black");
                    let pdf = phong.pdf(ns, wo, wi);
                    assert!(pdf > 0.0, "sampled a zero-density direction");
                    if wi.y > 0.0 {
                        est += (phong.eval(ns, wi, wo).x * wi.y / pdf) as f64;
                    }
                }
            }
            est /= (m * m) as f64;
            let albedo = sphere_integral(|wi| {
                wi.y.max(0.0) * phong.eval(ns, wi, wo).x * (wi.y > 0.0) as u8 as f32
            });
            assert!(
                (est - albedo).abs() < 0.01 * albedo,
                "{kd} {ks} {n}: {est} vs {albedo}"
            );
        }
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
