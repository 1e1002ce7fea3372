//! Stage 4: direct lighting along one camera ray.
//!
//! At a hit: the material's `ambient` is always added; then `light_samples` lights (the
//! environment among them) are picked by power. A point light gives one shadow ray; an area
//! light `samples` shadow rays (`shade::light::area`: a triangle by area, then a direction by
//! solid angle or a point by area); the environment one direction from its importance table
//! (`shade::light::environment`). Each light type's `sample` is called here; none is derived
//! here. Then, for area lights and the environment, `light_samples` BRDF-sampled rays
//! (`shade::brdf`) are traced, and
//! an emitter or the sky they reach adds its radiance. The two strategies are combined by
//! multiple importance sampling with the power heuristic (see `mis`); point lights (a delta
//! distribution no BRDF ray can hit) keep pure light sampling. [`DirectStrategy`] switches to
//! one strategy alone for tests and measurements. Under a sky alone, a diffuse surface adds the
//! closed-form integral of the sky's smooth fit and its samples estimate only the rest (a
//! control variate, `mis::sky_control`); where that fit is close to the sky, the sky's light
//! sample gives way to a second BRDF direction (`mis::sky_by_cosine`).
//!
//! Textured materials look their inputs up with the pixel's ray-cone footprint
//! (`shade::texture::footprint`: an ellipse, scaled down as the pixel's sample count grows, so
//! the filtered image converges; computed only when the scene has a mip-filtered texture),
//! normal maps included; a normal map replaces the shading
//! normal (`shade::normal_map`, bent by
//! the Iray reflection fix where it faces away from the viewer). Untextured materials skip both
//! behind one branch.
//!
//! Every random choice is stratified over all the samples of the pixel, not just within one
//! pixel sample: sample `s` of `S` uses points `s·m … s·m + m − 1` of one set of `S·m` scrambled
//! Hammersley points per pixel and stream (`Sampler::stratified_2d`), so 16 pixel samples with
//! one shadow ray each sample an area light as evenly as one pixel sample with 16. Visibility is
//! decided by the geometric normal (a light behind the surface contributes nothing, whatever the
//! shading normal says); the BRDF uses the shading normal flipped to the viewer's side of the
//! geometric one.
//!
//! Shadow rays start at the offset origin (see `shade::surface`) and stop short of the light: towards a
//! point light at `(1 − 1e-4)` of the distance, towards an area light at the point its sample
//! names (`AreaSample::shadow_target`: off the emitter's surface on the shading point's side,
//! `shade::light::shadow_end` for a rectangle), so the sampled emitter never occludes itself
//! while any other geometry in between still does.

use glam::Vec3;

use std::f32::consts::FRAC_1_PI;

use super::mis::{sky_by_cosine, sky_control, strategy_at, vertical_sky, VerticalSky};
use super::rng::Sampler;
use crate::geom::Ray;
use crate::scene::{DirectStrategy, Scene, Surface};
use crate::shade::brdf::Phong;
use crate::shade::light::env_harmonics::SkyHarmonics;
use crate::shade::normal_map;
use crate::shade::surface::{facing_viewer, seen_hit, SeenHit, SurfaceHit};
use crate::shade::texture::footprint::{self, Footprint};
use crate::shade::texture::FilterStats;
use crate::shade::{AreaLight, Light, Picked};

/// Rays traced, by kind, and how often the per-sample loop took the paths of optional features
/// (so a test can prove a scene without them never pays for them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays (one per pixel sample).
    pub camera: u64,
    /// Shadow rays (any-hit) towards light samples.
    pub shadow: u64,
    /// BRDF-sampled rays looking for emitters and the sky (closest-hit).
    pub brdf: u64,
    /// BRDF-sampled directions not traced: no sky, and they miss every emitter's box.
    pub brdf_skipped: u64,
    /// Shading points whose material looked up a texture.
    pub textured: u64,
    /// Shading points that evaluated a specular lobe.
    pub specular: u64,
    /// Camera rays that escaped to a visible environment, and environment light picks.
    pub environment: u64,
    /// Pixel samples whose radiance was NaN or infinite and was dropped (counted by the film
    /// loop, never by `radiance`).
    pub nonfinite: u64,
    /// Anisotropic texture lookups and their taps.
    pub filter: FilterStats,
}

impl RayCounts {
    /// Adds another tile's counts.
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.brdf += o.brdf;
        self.brdf_skipped += o.brdf_skipped;
        self.textured += o.textured;
        self.specular += o.specular;
        self.environment += o.environment;
        self.nonfinite += o.nonfinite;
        self.filter.add(&o.filter);
    }
}

const SHADOW_EPSILON: f32 = 1e-4;

/// `v / d`, without the division where `d` is 1 (one light, one pick, one sample per pick: the
/// common case, cornell's): the same bits, and three divisions fewer on the chain of a sample
/// each time.
#[inline]
pub(super) fn divided(v: Vec3, d: f32) -> Vec3 {
    if d == 1.0 {
        v
    } else {
        v / d
    }
}

/// Per-pixel stratification streams: light picks, the environment, BRDF directions, then one
/// per light.
const STREAM_PICK: u64 = 0;
pub(super) const STREAM_ENVIRONMENT: u64 = 1;
pub(super) const STREAM_BRDF: u64 = 2;
pub(super) const STREAM_LIGHTS: u64 = 3;
/// The environment's bright set (`render::mis`), far above the per-light streams.
pub(super) const STREAM_ENVIRONMENT_BRIGHT: u64 = (1 << 40) + 1;

/// Radiance arriving at the camera along `ray` (a unit-direction camera ray), textures filtered
/// over the whole pixel's footprint (a one-sample pixel's).
pub fn radiance(scene: &Scene, ray: &Ray, sampler: &mut Sampler, counts: &mut RayCounts) -> Vec3 {
    radiance_scaled(scene, ray, 1.0, sampler, counts)
}

/// [`radiance`], with the texture footprint scaled by `footprint_scale`
/// (`shade::texture::footprint::footprint_scale` of the pixel's sample count).
pub fn radiance_scaled(
    scene: &Scene,
    ray: &Ray,
    footprint_scale: f32,
    sampler: &mut Sampler,
    counts: &mut RayCounts,
) -> Vec3 {
    counts.camera += 1;
    let found = scene.accel.as_ref().and_then(|a| a.closest_hit(ray));
    let seen = found.and_then(|h| seen_hit(scene, &h));
    let hit = match &seen {
        // An emitter seen directly needs only its face normal.
        Some(SeenHit::Emitter { light, ng }) => {
            return match scene.lights.lights.get(*light as usize) {
                Some(Light::Area(a)) => a.radiance_towards(*ng, -ray.dir.normalize()),
                _ => Vec3::ZERO,
            };
        }
        Some(SeenHit::Surface(hit)) => hit,
        None => {
            return match &scene.lights.environment {
                Some(env) if env.visible => {
                    counts.environment += 1;
                    env.radiance(ray.dir.normalize())
                }
                _ => Vec3::ZERO,
            };
        }
    };
    let Surface::Material(m) = hit.surface else {
        // `seen_hit` reports every emitter as one.
        return Vec3::ZERO;
    };
    let at = Camera {
        dir: ray.dir.normalize(),
        footprint_scale,
    };
    shade(scene, hit, m, at, sampler, counts)
}

/// The camera ray that found a hit: its unit direction and its footprint scale.
#[derive(Clone, Copy)]
struct Camera {
    dir: Vec3,
    footprint_scale: f32,
}

fn shade(
    scene: &Scene,
    hit: &SurfaceHit,
    material: u32,
    camera: Camera,
    sampler: &mut Sampler,
    counts: &mut RayCounts,
) -> Vec3 {
    let Some(mat) = scene.materials.get(material as usize) else {
        return Vec3::ZERO;
    };
    let dir = camera.dir;
    let wo = -dir;
    let (ng, mut ns, flip) = facing_viewer(hit.ng, hit.ns, dir);
    // Only textured materials pay for the footprint (and normal-mapped ones for the map), and
    // only when a texture is mip-filtered.
    let textured = mat.is_textured();
    let footprint = if textured && scene.textures.any_mip_filtered() {
        footprint::uv_footprint(scene, hit, dir, camera.footprint_scale)
    } else {
        Footprint::default()
    };
    counts.textured += u64::from(textured);
    let fs = &mut counts.filter;
    if let Some(map) = &mat.normal_map {
        if let Some(mapped) = normal_map::mapped_normal(scene, hit, map, footprint, fs) {
            let mapped = if flip { -mapped } else { mapped };
            ns = normal_map::ensure_valid_reflection(ng, wo, mapped);
        }
    }
    let t = &scene.textures;
    let phong = Phong {
        diffuse: t.color(mat.diffuse, hit.uv, footprint, fs),
        specular: t.color(mat.specular, hit.uv, footprint, fs),
        shininess: t.scalar(mat.shininess, hit.uv, footprint, fs),
    };
    if phong.specular != Vec3::ZERO {
        counts.specular += 1;
    }
    let strategy = strategy_at(scene, &phong);
    let sky_fit = sky_control(scene, &phong, strategy);
    let sky_by_cosine = sky_by_cosine(scene, sky_fit);
    let at = Shading {
        scene,
        hit,
        ng,
        ns,
        wo,
        sky_fit,
        sky_by_cosine,
        vertical_sky: vertical_sky(scene, ns, sky_by_cosine),
        strategy,
        phong,
    };
    let direct = mat.ambient + at.lights(sampler, counts) + at.brdf_rays(sampler, counts);
    // The control variate's closed-form part (`mis`): the samples above estimated the rest.
    match (at.vertical_sky, at.sky_fit) {
        (Some(v), _) => direct + at.phong.diffuse * FRAC_1_PI * v.irradiance,
        (None, Some(fit)) => direct + at.phong.diffuse * FRAC_1_PI * fit.irradiance(ns),
        (None, None) => direct,
    }
}

pub(super) struct Shading<'a> {
    pub(super) scene: &'a Scene,
    pub(super) hit: &'a SurfaceHit,
    /// Geometric and shading normals, both on the viewer's side.
    pub(super) ng: Vec3,
    pub(super) ns: Vec3,
    pub(super) wo: Vec3,
    pub(super) phong: Phong,
    /// The scene's strategy, or light sampling alone where BRDF rays cannot help
    /// ([`strategy_at`]).
    pub(super) strategy: DirectStrategy,
    /// The sky's smooth fit, when the environment's light is estimated as its closed-form
    /// integral plus sampled residuals ([`sky_control`]).
    pub(super) sky_fit: Option<&'a SkyHarmonics>,
    /// Whether the sky without its bright set is left to cosine-sampled BRDF rays alone, two
    /// per pick, instead of one of them and one sample of the sky's tables
    /// ([`sky_by_cosine`]).
    pub(super) sky_by_cosine: bool,
    /// When the point faces straight up or down under such a sky, the sky itself is what the
    /// control variate subtracts, not its fit ([`vertical_sky`]).
    pub(super) vertical_sky: Option<VerticalSky>,
}

impl Shading<'_> {
    pub(super) fn picks(&self) -> u32 {
        self.scene.settings.light_samples.max(1)
    }

    /// The light-sampling strategy.
    fn lights(&self, sampler: &mut Sampler, counts: &mut RayCounts) -> Vec3 {
        let lights = &self.scene.lights;
        if lights.by_power.is_none() {
            return Vec3::ZERO;
        }
        let brdf_only = self.strategy == DirectStrategy::BrdfOnly;
        let picks = self.picks();
        let (s, count) = sampler.index();
        let mut sum = Vec3::ZERO;
        // One light (cornell's, or a sky alone): every pick is it, no random number needed.
        let single = lights.single();
        for k in 0..picks {
            // Stratified over all the picks of all the pixel's samples.
            let j = s * picks + k;
            let picked = single.or_else(|| {
                let u = sampler.stratified_2d(STREAM_PICK, j, count * picks).x;
                lights.pick(u).map(|(picked, pmf, _)| (picked, pmf))
            });
            let Some((picked, pmf)) = picked else {
                continue;
            };
            let contribution = match picked {
                Picked::Light(_, Light::Point(p)) => {
                    let s = p.sample(self.hit.p);
                    self.unoccluded(s.wi, s.position, SHADOW_EPSILON, counts)
                        .map_or(Vec3::ZERO, |cos| {
                            self.phong.eval(self.ns, s.wi, self.wo) * s.intensity * cos / s.dist2
                        })
                }
                Picked::Light(_, Light::Area(_)) | Picked::Environment(_) if brdf_only => {
                    Vec3::ZERO
                }
                Picked::Light(index, Light::Area(a)) => {
                    self.area_light(a, index, pmf, j, count * picks, sampler, counts)
                }
                Picked::Environment(env) => {
                    counts.environment += 1;
                    self.environment(env, pmf, j, count * picks, sampler, counts)
                }
            };
            sum += divided(contribution, pmf);
        }
        divided(sum, picks as f32)
    }

    /// `light` is `lights[index]`, picked with probability `pmf` for the `pick`-th of `picks`
    /// picks in the pixel.
    #[allow(clippy::too_many_arguments)] // reason: the pick's identity and its sampler slot
    fn area_light(
        &self,
        light: &AreaLight,
        index: usize,
        pmf: f32,
        pick: u32,
        picks: u32,
        sampler: &mut Sampler,
        counts: &mut RayCounts,
    ) -> Vec3 {
        let n = light.samples;
        let mut sum = Vec3::ZERO;
        for i in 0..n {
            let stream = STREAM_LIGHTS + index as u64;
            let u = sampler.stratified_2d(stream, pick * n + i, picks * n);
            let Some(s) = light.sample(self.hit.p, u, self.scene.light_sampling) else {
                continue;
            };
            // The shadow ray stops just off the emitter, on the shading point's side.
            if let Some(cos) = self.unoccluded(s.wi, s.shadow_target, 0.0, counts) {
                let f = self.phong.eval(self.ns, s.wi, self.wo);
                // Effective densities: `samples` light samples per pick of probability `pmf`
                // against one BRDF sample per pick.
                let mis = self.light_weight(n as f32 * pmf / s.inv_pdf_solid_angle, s.wi);
                sum += s.radiance * f * (cos * s.inv_pdf_solid_angle * mis);
            }
        }
        divided(sum, n as f32)
    }

    /// Traces the shadow ray towards `target` (direction `wi`, unit). Returns the shading
    /// cosine if the light is above the geometric surface, in front of the shading normal and
    /// unoccluded.
    fn unoccluded(
        &self,
        wi: Vec3,
        target: Vec3,
        shorten: f32,
        counts: &mut RayCounts,
    ) -> Option<f32> {
        let cos = self.ns.dot(wi);
        if wi.dot(self.ng) <= 0.0 || cos <= 0.0 || !wi.is_finite() {
            return None;
        }
        counts.shadow += 1;
        let origin = self.hit.ray_origin(self.ng, wi);
        let ray = Ray::segment(origin, target - origin, 1.0 - shorten);
        let blocked = self.scene.accel.as_ref().is_some_and(|a| a.any_hit(&ray));
        (!blocked).then_some(cos)
    }
}
