//! Shading layer: the energy-normalised Phong BRDF (`material m = phong { diffuse …  specular …
//! shininess n  ambient … }`).
//!
//! ```text
//! f(wi, wo) = kd / π  +  ks · (n + 2) / (2π) · max(0, r · wo)^n,    r = 2 (ns · wi) ns − wi
//! ```
//! With this normalisation the directional albedo `∫ f cos θi dωi` of the diffuse term is `kd`
//! and that of the specular lobe is exactly `ks` at normal incidence and less elsewhere (the lobe
//! is cut by the horizon and weighted by cos θi), so `kd + ks ≤ 1` never creates energy.
//!
//! **Mapping from the classic form.** The course formula shades a point lit by a light of
//! "intensity" `L` as `kd_classic · L · cos θ + ks_classic · L · (r · v)^n`. Here the reflected
//! radiance is `f · E` with `E = I · cos θ / r²` for a point light (and `∫ L_e cos θ dω` for an
//! area light). Writing `E⊥ = I / r²` for the irradiance at normal incidence, the two agree when
//! `L = E⊥ / π` and `kd_classic = kd`, `ks_classic = ks · (n + 2) / 2`: the classic diffuse
//! colour is the albedo, its light value is irradiance divided by π, and its specular weight
//! hides the lobe's `(n + 2)/2` normalisation (which is why classic Phong highlights lose or
//! gain energy when `n` changes, and these do not). A white (`kd = 1`) plane lit head-on by a
//! point light of intensity `I` at distance `r` therefore renders `I / (π r²)`.
//!
//! **Sampling** (the BRDF strategy of multiple importance sampling): the BRDF is sampled as a
//! mixture of its two lobes, chosen by their albedo weights (`Σ kd` against `Σ ks`, the lobes'
//! albedos at normal incidence): the diffuse lobe by a cosine-weighted hemisphere
//! (`pdf = cos θ / π`), the specular lobe by `cos^n α` around the mirror direction
//! `r = 2 (ns·wo) ns − wo` (`pdf = (n + 1)/(2π) · cos^n α`, exactly proportional to the lobe).
//! [`Phong::pdf`] is the mixture's density, which is what the MIS weights need whichever lobe
//! produced the direction; it sits beside [`Phong::sample`] so the two cannot drift apart.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Vec2, Vec3};

use super::sampling::{cosine_hemisphere, phong_lobe};

/// A Phong lobe evaluated at one hit (inputs already looked up from textures).
#[derive(Debug, Clone, Copy)]
pub struct Phong {
    /// `kd`: the diffuse albedo.
    pub diffuse: Vec3,
    /// `ks`: the specular lobe's albedo at normal incidence.
    pub specular: Vec3,
    /// `n`: the lobe's exponent (negative values count as 0).
    pub shininess: f32,
}

impl Phong {
    /// `f(wi, wo)` for unit `wi` (towards the light) and `wo` (towards the viewer) on the side of
    /// the unit shading normal `ns`.
    #[inline]
    pub fn eval(&self, ns: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let mut f = self.diffuse * FRAC_1_PI;
        if self.specular != Vec3::ZERO {
            let r = 2.0 * ns.dot(wi) * ns - wi;
            let cos_alpha = r.dot(wo).max(0.0);
            let n = self.shininess.max(0.0);
            f += self.specular * ((n + 2.0) / (2.0 * PI) * cos_alpha.powf(n));
        }
        f
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f(wi, wo) cos θi dωi over the hemisphere, integrated in spherical coordinates around
    /// the lobe axis (the mirror direction of `wo`) so the narrow lobes of large n are resolved.
    fn albedo(phong: &Phong, wo: Vec3) -> f32 {
        let n = Vec3::Z;
        let axis = 2.0 * n.dot(wo) * n - wo;
        let (t1, t2) = axis.any_orthonormal_pair();
        let (steps_a, steps_p) = (4000, 128);
        let mut sum = 0.0f64;
        for ia in 0..steps_a {
            let alpha = (ia as f32 + 0.5) / steps_a as f32 * PI;
            let d_alpha = PI / steps_a as f32;
            for ip in 0..steps_p {
                let phi = (ip as f32 + 0.5) / steps_p as f32 * 2.0 * PI;
                let d_phi = 2.0 * PI / steps_p as f32;
                let wi = alpha.cos() * axis + alpha.sin() * (phi.cos() * t1 + phi.sin() * t2);
                let cos_i = wi.dot(n);
                if cos_i > 0.0 {
                    let f = phong.eval(n, wi, wo).x;
                    sum += (f * cos_i * alpha.sin() * d_alpha * d_phi) as f64;
                }
            }
        }
        sum as f32
    }

    #[test]
    fn specular_albedo_is_at_most_one_and_one_at_normal_incidence() {
        for shininess in [0.0, 1.0, 10.0, 100.0, 1000.0] {
            let lobe = Phong {
                diffuse: Vec3::ZERO,
                specular: Vec3::ONE,
                shininess,
            };
            let head_on = albedo(&lobe, Vec3::Z);
            assert!((head_on - 1.0).abs() < 2e-3, "n = {shininess}: {head_on}");
            for theta_deg in [30.0f32, 60.0, 85.0] {
                let t = theta_deg.to_radians();
                let a = albedo(&lobe, Vec3::new(t.sin(), 0.0, t.cos()));
                assert!(a <= 1.0 + 2e-3, "n = {shininess}, θ = {theta_deg}: {a}");
            }
        }
    }

    #[test]
    fn diffuse_albedo_equals_kd() {
        let d = Phong {
            diffuse: Vec3::splat(0.7),
            specular: Vec3::ZERO,
            shininess: 1.0,
        };
        assert!((albedo(&d, Vec3::new(0.6, 0.0, 0.8)) - 0.7).abs() < 1e-3);
    }

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
}
