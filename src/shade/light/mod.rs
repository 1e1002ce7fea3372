//! Lights: the closed set of emitters ([`Light`]: point and area lights, plus the scene's
//! [`Environment`]) and the table that picks one by power.
//!
//! Syntax: `light bulb = point { position (0, 4, 0)  intensity rgb(10, 10, 10) }`,
//! `light panel = area { mesh panel  transform { ... }  radiance 5  two_sided false  samples 4 }`,
//! `light sky = environment { rgb(0.2, 0.3, 0.5)  intensity 1  visible true }`.
//!
//! One file per light type, each keeping its `sample` beside its `pdf` (pbrt's `SampleLi`
//! beside `PDF_Li`): `point` (a delta: sample only, pdf 0), `area` (triangles by area, then by
//! solid angle or area; the spherical-triangle maths in `spherical`, a rectangle's in
//! `spherical_rect`), `environment` (a constant
//! and/or the map of `env_map`). The scene build creates them; the integrator picks one with
//! [`Lights::pick`] and calls its `sample`; MIS calls the `pdf` of what a BRDF ray reached.
//!
//! Point and area lights are picked by power through one [`Distribution1D`], so a scene with 100
//! lights traces the same number of shadow rays per shading point as a scene with one. The
//! environment, when the scene has one and geometry to light, is the table's last entry (index
//! `lights.len()`), with the power estimate of [`Environment::power`].

pub mod area;
pub mod complex_arg;
pub mod emitter_bounds;
pub mod env_angles;
pub mod env_bright;
pub mod env_harmonics;
pub mod env_map;
pub mod env_sampler;
pub mod env_texels;
pub mod env_vertical;
pub mod environment;
pub mod point;
pub mod rect_lanes;
pub mod shadow_end;
pub mod spherical;
pub mod spherical_rect;

pub use area::{AreaLight, AreaSample, LightPoint};
pub use emitter_bounds::EmitterBounds;
pub use env_map::{EnvMap, EnvSample};
pub use environment::Environment;
pub use point::{PointLight, PointSample};

use glam::Vec3;

use crate::shade::distribution::Distribution1D;

/// A light the build placed in the scene (the environment is kept apart, in
/// [`Lights::environment`]: it has no position and is also what escaped rays see).
#[derive(Debug, Clone)]
pub enum Light {
    /// `light … = point { … }`.
    Point(PointLight),
    /// `light … = area { … }`, or an OBJ material's `Ke`.
    Area(AreaLight),
}

/// Every light of the scene, with the table that picks one by power.
#[derive(Debug, Clone, Default)]
pub struct Lights {
    /// Point and area lights; an instance's `Surface::Emitter(i)` is `lights[i]`.
    pub lights: Vec<Light>,
    /// `None` when there is no light with positive power: no shadow rays at all.
    pub by_power: Option<Distribution1D>,
    /// The environment, if the scene has one that emits or shows.
    pub environment: Option<Environment>,
    /// Whether `by_power` has the environment as its entry `lights.len()`.
    environment_in_table: bool,
    /// Whether any light is an area light.
    has_emitters: bool,
    /// The area lights' boxes, for skipping BRDF-sampled rays that cannot reach one.
    emitter_bounds: EmitterBounds,
}

/// What [`Lights::pick`] chose.
#[derive(Debug, Clone, Copy)]
pub enum Picked<'a> {
    /// `lights[i]` and the light itself.
    Light(usize, &'a Light),
    /// The environment.
    Environment(&'a Environment),
}

impl Lights {
    /// `scene_radius` is the radius of the scene's bounding sphere (for the environment's
    /// power); the environment joins the table only if its sampling was prepared.
    pub fn new(lights: Vec<Light>, environment: Option<Environment>, scene_radius: f32) -> Lights {
        let mut powers: Vec<f32> = lights
            .iter()
            .map(|l| match l {
                Light::Point(p) => p.power(),
                Light::Area(a) => a.power(),
            })
            .collect();
        let environment = environment.filter(|e| !e.is_black() || e.visible);
        let env_power = environment.as_ref().and_then(|e| e.power(scene_radius));
        if let Some(p) = env_power {
            powers.push(p);
        }
        Lights {
            by_power: Distribution1D::new(&powers),
            has_emitters: lights.iter().any(|l| matches!(l, Light::Area(_))),
            emitter_bounds: EmitterBounds::new(&lights),
            lights,
            environment,
            environment_in_table: env_power.is_some(),
        }
    }

    /// A light picked by power for `u` in [0, 1): what, its probability, `u` rescaled.
    pub fn pick(&self, u: f32) -> Option<(Picked<'_>, f32, f32)> {
        let (i, pmf, rest) = self.by_power.as_ref()?.sample(u);
        let picked = match self.lights.get(i) {
            Some(l) => Picked::Light(i, l),
            None => Picked::Environment(self.environment.as_ref()?),
        };
        Some((picked, pmf, rest))
    }

    /// What [`Lights::pick`] chooses for every `u` when the table has one entry (and its
    /// probability, 1): the caller then need not draw the pick's random number.
    pub fn single(&self) -> Option<(Picked<'_>, f32)> {
        let table = self.by_power.as_ref()?;
        if table.len() != 1 {
            return None;
        }
        let picked = match self.lights.first() {
            Some(l) => Picked::Light(0, l),
            None => Picked::Environment(self.environment.as_ref()?),
        };
        Some((picked, table.pmf(0)))
    }

    /// Whether any light is an area light (something a BRDF-sampled ray can hit).
    pub fn has_emitters(&self) -> bool {
        self.has_emitters
    }

    /// Whether a ray from `origin` along `dir` may hit an area light (`false` only when it
    /// misses all their boxes; see [`EmitterBounds`]).
    pub fn may_reach_emitter(&self, origin: Vec3, dir: Vec3) -> bool {
        self.emitter_bounds.may_reach(origin, dir)
    }

    /// The probability that [`Lights::pick`] chooses `lights[i]`.
    pub fn pmf_light(&self, i: usize) -> f32 {
        self.by_power.as_ref().map_or(0.0, |d| d.pmf(i))
    }

    /// The probability that [`Lights::pick`] chooses the environment (0 when it is not sampled).
    pub fn pmf_environment(&self) -> f32 {
        match (&self.by_power, self.environment_in_table) {
            (Some(d), true) => d.pmf(self.lights.len()),
            _ => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn no_positive_power_means_no_table() {
        let dark = Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: Vec3::ZERO,
        });
        assert!(Lights::new(vec![dark], None, 1.0).by_power.is_none());
    }
}
