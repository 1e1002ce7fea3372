//! Stage 4: multiple importance sampling of area lights and the environment (`light … = area
//! { … }`, `light sky = environment { image("sky.hdr") }`).
//!
//! Two strategies estimate the same direct lighting: light sampling (`integrator`: a light
//! picked by power, then a point or direction on it) and BRDF sampling (here: a direction from
//! the Phong mixture of `shade::brdf`, traced to the first surface; if that is an emitter, or
//! nothing and the sky is there, its radiance counts). Each sample is weighted by Veach's power
//! heuristic on effective densities, so the weights of the two strategies sum to one for every
//! direction and the sum stays unbiased:
//!
//! - light side: `samples · pmf_pick · pdf_light` (an area light takes `samples` points per
//!   pick; the environment one direction), where `pdf_light` is the solid-angle density of the
//!   light's own sampling at that direction, given by the light beside its sampler
//!   ([`AreaLight::pdf`](crate::shade::AreaLight::pdf),
//!   [`Environment::pdf`](crate::shade::Environment::pdf)), never re-derived here;
//! - BRDF side: `pdf_brdf` (one BRDF ray per pick).
//!
//! Both strategies take `light_samples` samples per shading point, so that count cancels. With
//! [`DirectStrategy::LightOnly`] no BRDF ray is traced and light samples weigh 1; with
//! [`DirectStrategy::BrdfOnly`] area lights and the environment are reached by BRDF rays
//! alone (weight 1), and only point lights are still sampled.

use glam::Vec3;

use super::integrator::{
    divided, RayCounts, Shading, STREAM_BRDF, STREAM_ENVIRONMENT, STREAM_ENVIRONMENT_BRIGHT,
};
use super::rng::Sampler;
use crate::geom::Ray;
use crate::scene::{DirectStrategy, LightSampling, Scene, Surface};
use crate::shade::brdf::Phong;
use crate::shade::light::env_harmonics::SkyHarmonics;
use crate::shade::light::EnvSample;
use crate::shade::sampling::power_heuristic;
use crate::shade::{Environment, Light, Picked};

/// The strategy at a shading point with BRDF `phong`: the scene's, except that MIS falls back
/// to light sampling alone on a purely diffuse surface in a scene without an environment whose
/// area lights are sampled by solid angle. There a light sample's MIS weight is within a
/// fraction of a percent of 1 wherever the light's solid angle is below a steradian or so
/// (`1 / Ω` against at most `1 / π` for the cosine lobe), and the BRDF rays, which nearly all
/// miss the lights, cost a direction, an origin and a box test each (on cornell: 3.9 million
/// directions of which 23,000 reach the light). The choice depends on the point alone, never on
/// a sample, and both strategies read it here, so each stays unbiased: light samples weigh 1,
/// and no BRDF ray is drawn. Measured in docs/speed.md.
pub(super) fn strategy_at(scene: &Scene, phong: &Phong) -> DirectStrategy {
    let lights = &scene.lights;
    let light_only_pays = scene.strategy == DirectStrategy::Mis
        && scene.light_sampling == LightSampling::SolidAngle
        && phong.specular == Vec3::ZERO
        && lights.pmf_environment() == 0.0;
    if light_only_pays {
        DirectStrategy::LightOnly
    } else {
        scene.strategy
    }
}

/// The sky's fit for a control variate at a shading point with BRDF `phong` and strategy
/// `strategy` (`shade::light::env_harmonics`): used when the environment is the scene's only
/// light, the surface is purely diffuse (the fit's cosine-weighted integral is then known in
/// closed form) and both strategies are combined by MIS (cosine-sampled BRDF rays cover every
/// direction above the shading normal's horizon, where the fit is subtracted). Then the
/// point's direct light is `ρ/π · E(n_s)` from the fit plus the MIS estimate of
/// `∫ (L V [ω·n_g > 0] − L̃) ρ/π cos⁺`: every sample that lands in that hemisphere adds
/// `(seen − fit)` where it used to add `seen` (a blocked or below-the-geometric-horizon sample
/// adds `−fit`), and no ray is traced that was not before. Unbiased; where the whole sky is
/// seen, only the sky's departure from its smooth fit is left to the samples.
pub(super) fn sky_control<'a>(
    scene: &'a Scene,
    phong: &Phong,
    strategy: DirectStrategy,
) -> Option<&'a SkyHarmonics> {
    if strategy != DirectStrategy::Mis || phong.specular != Vec3::ZERO {
        return None;
    }
    match scene.lights.single() {
        Some((Picked::Environment(env), _)) if !scene.lights.has_emitters() => env.harmonics(),
        _ => None,
    }
}

/// The largest [`SkyHarmonics::relative_residual`] of a sky left to BRDF rays by
/// [`sky_by_cosine`]: env-bench's sky without its sun has 0.15, a 30° window five times as
/// bright as the rest of a constant sky 0.40.
pub(super) const SMOOTH_SKY_RESIDUAL: f32 = 0.25;

/// Whether, under the control variate `sky_fit` ([`sky_control`]), the sky without its bright
/// set is estimated by cosine-sampled BRDF rays alone: two per pick, the sky's light sample
/// given up for a second BRDF direction (the same rays). Only where the fit is close to the
/// sky (relative residual at most [`SMOOTH_SKY_RESIDUAL`]): then what the samples estimate is
/// nearly all visibility, `−fit` over the hidden directions, which a cosine-distributed
/// sample follows as well as the sky's tables do, and two stratified cosine directions cover
/// it better than one of each, for less (no table lookups). A sky with bright parts the fit
/// misses keeps its tables. The bright set is still sampled on its own, weighted against the
/// BRDF alone. On env-bench, at equal samples: squared error −24% (16 spp), −20% (64 spp),
/// CPU −16% (docs/speed.md).
///
/// Fixed-count renders only: an adaptive render (`render { noise … }`) of env at 10% then
/// stops at 0.48× the target's error (`tests/quality_calibration.rs`' band is 0.5–1.1×), its
/// pixels held by the sample floor (`estimate::min_samples`) with error to spare; that floor's
/// recalibration is the adaptive sampler's (issue 21).
pub(super) fn sky_by_cosine(scene: &Scene, sky_fit: Option<&SkyHarmonics>) -> bool {
    scene.settings.noise.is_none()
        && sky_fit.is_some_and(|fit| fit.relative_residual() <= SMOOTH_SKY_RESIDUAL)
}

/// What a shading point facing straight up or down subtracts, when it subtracts the sky itself
/// ([`vertical_sky`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct VerticalSky {
    /// The sky's exact irradiance for the point's normal, its bright set left out.
    pub(super) irradiance: Vec3,
    /// The environment's constant part: what is subtracted on the bright set's texels.
    constant: Vec3,
}

/// Under the control variate with the sky left to cosine rays ([`sky_by_cosine`]), a point
/// whose shading normal is exactly `+y` or `−y` (a floor, a ceiling) subtracts the sky itself,
/// its bright set left out, instead of the sky's smooth fit: the sky's cosine integral for
/// that normal is exact (`shade::light::env_vertical`). Then a cosine direction that sees the
/// sky outside the bright set's cone adds exactly nothing and reads no texel; a hidden one
/// adds `−L` (its texel read) where it added `−L̃`; the bright set's samples subtract only the
/// constant part. Unbiased as the fit is (the closed form is the integral of exactly what is
/// subtracted); the variance that is left is the visibility's, as with the fit (whose
/// departure from the sky left open ground nearly noise-free already), so what this buys is
/// the texel lookups of the directions that see the sky (docs/speed.md). The choice depends on
/// the point alone.
pub(super) fn vertical_sky(scene: &Scene, ns: Vec3, sky_by_cosine: bool) -> Option<VerticalSky> {
    if !sky_by_cosine || ns.x != 0.0 || ns.z != 0.0 {
        return None;
    }
    let env = scene.lights.environment.as_ref()?;
    Some(VerticalSky {
        irradiance: env.vertical_irradiance(ns.y > 0.0)?,
        constant: env.constant,
    })
}

impl Shading<'_> {
    /// BRDF directions per pick: two when the sky is left to them ([`sky_by_cosine`]).
    fn brdf_per_pick(&self) -> u32 {
        if self.sky_by_cosine {
            2
        } else {
            1
        }
    }

    /// The BRDF strategy's effective density at unit direction `wi`: `brdf_per_pick` samples
    /// of density `phong.pdf`.
    fn brdf_density(&self, wi: Vec3) -> f32 {
        self.brdf_per_pick() as f32 * self.phong.pdf(self.ns, self.wo, wi)
    }

    /// The radiance from unit direction `wi` subtracted by the control variate
    /// ([`sky_control`]): the sky's fit, or the sky itself without its bright set
    /// ([`vertical_sky`]); zero without it.
    fn subtracted(&self, env: &Environment, wi: Vec3) -> Vec3 {
        match (self.vertical_sky, self.sky_fit) {
            (Some(_), _) => env.radiance_apart_from_bright(wi),
            (None, Some(fit)) => fit.radiance(wi),
            (None, None) => Vec3::ZERO,
        }
    }

    /// [`Shading::subtracted`] at an environment light sample `s`: a sample of the bright set
    /// when the point subtracts the sky itself (the sky is left to cosine rays then), whose
    /// texel the subtracted sky leaves out but for its constant part.
    fn subtracted_at_sample(&self, s: &EnvSample) -> Vec3 {
        match (self.vertical_sky, self.sky_fit) {
            (Some(v), _) => v.constant,
            (None, Some(fit)) => fit.radiance(s.wi),
            (None, None) => Vec3::ZERO,
        }
    }

    /// The MIS weight of a light sample in direction `wi` whose effective density is
    /// `light_density`.
    pub(super) fn light_weight(&self, light_density: f32, wi: Vec3) -> f32 {
        match self.strategy {
            DirectStrategy::Mis => power_heuristic(light_density, self.brdf_density(wi)),
            DirectStrategy::LightOnly | DirectStrategy::BrdfOnly => 1.0,
        }
    }

    /// The environment's light samples for one pick (probability `pmf`, the `pick`-th of
    /// `picks` in the pixel): one direction of the sky and, when the map has a bright set (a
    /// small sun, `shade::light::env_bright`), one of that set too, each weighted against the
    /// other and the BRDF by the power heuristic; `Σ L · f · cos θ / pdf · w` (the caller
    /// divides by `pmf`).
    pub(super) fn environment(
        &self,
        env: &Environment,
        pmf: f32,
        pick: u32,
        picks: u32,
        sampler: &mut Sampler,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let mut sum = Vec3::ZERO;
        if !self.sky_by_cosine {
            let u = sampler.stratified_2d(STREAM_ENVIRONMENT, pick, picks);
            if let Some((s, other)) = env.sample_sky_facing(u, Some(self.ns)) {
                sum += self.environment_sample(&s, pmf, other, counts);
            }
        }
        // A sun below the horizon of either normal adds nothing (`environment_sample` would
        // drop each of its samples): skip drawing them. Under the control variate a sample
        // below the geometric horizon still subtracts the fit, so only the shading normal's
        // horizon counts then.
        let below_ng = self.sky_fit.is_none() && env.bright_below_horizon_of(self.ng);
        let sun_up = !(env.bright_below_horizon_of(self.ns) || below_ng);
        if env.has_bright() && sun_up {
            let u = sampler.stratified_2d(STREAM_ENVIRONMENT_BRIGHT, pick, picks);
            if let Some((s, other)) = env.sample_bright(u) {
                // Without the sky's light sample, only the BRDF counts against it.
                let other = if self.sky_by_cosine { 0.0 } else { other };
                sum += self.environment_sample(&s, pmf, other, counts);
            }
        }
        sum
    }

    /// One light-sampled direction of the environment, drawn with density `s.pdf_solid_angle`
    /// by its strategy while the environment's other light strategy has density `other` there.
    fn environment_sample(
        &self,
        s: &EnvSample,
        pmf: f32,
        other: f32,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let cos = self.ns.dot(s.wi);
        if s.pdf_solid_angle <= 0.0 || cos <= 0.0 {
            return Vec3::ZERO;
        }
        let seen =
            s.wi.dot(self.ng) > 0.0 && s.radiance != Vec3::ZERO && !self.blocked(s.wi, counts);
        let radiance = match (seen, self.sky_fit.is_some()) {
            (true, false) => s.radiance,
            (true, true) => s.radiance - self.subtracted_at_sample(s),
            (false, true) => -self.subtracted_at_sample(s),
            (false, false) => return Vec3::ZERO,
        };
        let f = self.phong.eval(self.ns, s.wi, self.wo);
        let w = match self.strategy {
            DirectStrategy::Mis => {
                // Power heuristic over three strategies: own² / (own² + other² + brdf²).
                let brdf = self.brdf_density(s.wi);
                power_heuristic(pmf * s.pdf_solid_angle, (pmf * other).hypot(brdf))
            }
            DirectStrategy::LightOnly | DirectStrategy::BrdfOnly => {
                power_heuristic(s.pdf_solid_angle, other)
            }
        };
        radiance * f * (cos * w / s.pdf_solid_angle)
    }

    /// The sky's radiance in direction `wi` (unit) and the effective density of the
    /// environment's light strategies there (both count against a BRDF sample; the bright set
    /// alone when the sky is left to BRDF rays).
    fn sky_seen(&self, env: &Environment, wi: Vec3) -> (Vec3, f32) {
        let pmf = self.scene.lights.pmf_environment();
        if self.sky_by_cosine {
            let (radiance, bright) = env.radiance_and_bright_density(wi);
            return (radiance, pmf * bright);
        }
        let (radiance, sky, bright) = env.radiance_and_densities_facing(wi, Some(self.ns));
        let light = if bright > 0.0 { sky.hypot(bright) } else { sky };
        (radiance, pmf * light)
    }

    /// A cosine-sampled BRDF direction `wi` whose sky is not seen, under the control
    /// variate: `radiance` (minus the fit) weighted as the sky it would have seen.
    fn brdf_residual(&self, env: &Environment, wi: Vec3, radiance: Vec3) -> Vec3 {
        let pdf = self.phong.pdf(self.ns, self.wo, wi);
        if pdf <= 0.0 {
            return Vec3::ZERO;
        }
        let light_density = if self.sky_by_cosine {
            // Only the bright set's density counts, and no texel need be read for it.
            self.scene.lights.pmf_environment() * env.bright_density(wi)
        } else {
            self.sky_seen(env, wi).1
        };
        let w = power_heuristic(self.brdf_per_pick() as f32 * pdf, light_density);
        let f = self.phong.eval(self.ns, wi, self.wo);
        radiance * f * (self.ns.dot(wi) * w / pdf)
    }

    /// Whether anything lies along `ray` (any-hit).
    fn blocked_ray(&self, ray: &Ray) -> bool {
        self.scene.accel.as_ref().is_some_and(|a| a.any_hit(ray))
    }

    /// Whether anything lies in direction `wi` (unit) from the shading point.
    fn blocked(&self, wi: Vec3, counts: &mut RayCounts) -> bool {
        counts.shadow += 1;
        let origin = self.hit.ray_origin(self.ng, wi);
        let ray = Ray::new(origin, wi);
        self.scene.accel.as_ref().is_some_and(|a| a.any_hit(&ray))
    }

    /// The BRDF-sampling strategy: `light_samples` directions from the Phong mixture (twice as
    /// many when the sky is left to them, [`sky_by_cosine`]), each adding the MIS-weighted
    /// radiance of the emitter or sky it reaches.
    pub(super) fn brdf_rays(&self, sampler: &mut Sampler, counts: &mut RayCounts) -> Vec3 {
        let lights = &self.scene.lights;
        let env = lights
            .environment
            .as_ref()
            .filter(|_| lights.pmf_environment() > 0.0);
        if self.strategy == DirectStrategy::LightOnly
            || (env.is_none() && !lights.has_emitters())
            || self.phong.diffuse_share().is_none()
        {
            return Vec3::ZERO;
        }
        // Stratified over all the directions of all the pixel's samples.
        let picks = self.picks() * self.brdf_per_pick();
        let (s, count) = sampler.index();
        let mut sum = Vec3::ZERO;
        for k in 0..picks {
            let u = sampler.stratified_2d(STREAM_BRDF, s * picks + k, count * picks);
            let Some(wi) = self.phong.sample(self.ns, self.wo, u) else {
                continue;
            };
            let cos = self.ns.dot(wi);
            if cos <= 0.0 || !wi.is_finite() {
                continue;
            }
            if wi.dot(self.ng) <= 0.0 {
                // Below the geometric horizon nothing is seen; the control variate still
                // subtracts its fit there.
                if let (Some(e), Some(_)) = (env, self.sky_fit) {
                    sum += self.brdf_residual(e, wi, -self.subtracted(e, wi));
                }
                continue;
            }
            let origin = self.hit.ray_origin(self.ng, wi);
            if env.is_none() && !lights.may_reach_emitter(origin, wi) {
                // Nothing it could hit emits, and there is no sky: it adds exactly nothing.
                counts.brdf_skipped += 1;
                continue;
            }
            let pdf = self.phong.pdf(self.ns, self.wo, wi);
            if pdf <= 0.0 {
                continue;
            }
            counts.brdf += 1;
            let ray = Ray::new(origin, wi);
            let (radiance, light_density) = if !lights.has_emitters() {
                // Only the sky can be reached: whether anything is in the way is all that
                // matters, and an any-hit query stops at the first thing it finds.
                let Some(e) = env else {
                    continue;
                };
                if self.blocked_ray(&ray) {
                    if self.sky_fit.is_some() {
                        sum += self.brdf_residual(e, wi, -self.subtracted(e, wi));
                    }
                    continue;
                }
                counts.environment += 1;
                if self.vertical_sky.is_some() && !e.may_be_bright(wi) {
                    // It sees exactly what is subtracted: it adds nothing.
                    continue;
                }
                let (radiance, density) = self.sky_seen(e, wi);
                (radiance - self.subtracted(e, wi), density)
            } else {
                match self.scene.accel.as_ref().and_then(|a| a.closest_hit(&ray)) {
                    None => match env {
                        Some(e) => {
                            counts.environment += 1;
                            self.sky_seen(e, wi)
                        }
                        None => continue,
                    },
                    Some(h) => {
                        let Some(inst) = self.scene.instances.get(h.instance as usize) else {
                            continue;
                        };
                        let Surface::Emitter(i) = inst.surface else {
                            continue;
                        };
                        let Some(Light::Area(light)) = lights.lights.get(i as usize) else {
                            continue;
                        };
                        let p_light = ray.at(h.t);
                        let mode = self.scene.light_sampling;
                        let Some(pdf_light) =
                            light.pdf(self.hit.p, wi, h.prim as usize, p_light, mode)
                        else {
                            continue;
                        };
                        let pmf = lights.pmf_light(i as usize);
                        (light.radiance, light.samples as f32 * pmf * pdf_light)
                    }
                }
            };
            let w = match self.strategy {
                DirectStrategy::BrdfOnly => 1.0,
                _ => power_heuristic(self.brdf_per_pick() as f32 * pdf, light_density),
            };
            let f = self.phong.eval(self.ns, wi, self.wo);
            sum += radiance * f * (cos * w / pdf);
        }
        divided(sum, picks as f32)
    }
}
