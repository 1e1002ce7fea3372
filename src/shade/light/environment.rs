//! The environment light: radiance from every direction no geometry blocks, from a constant
//! colour and/or an equirectangular map ([`EnvMap`]), sampled as a mixture of the two.
//!
//! Syntax: `light sky = environment { image("sky.hdr")  intensity 1  rotate 90deg  visible true }`
//! or `environment { rgb(0.2, 0.3, 0.5) }`. Several constant environments add up; at most one
//! image is supported.
//!
//! A constant part is sampled uniformly over the sphere (`1 / 4π`); with a map as well, the two
//! are mixed in proportion to their average radiance. [`Environment::sample`] and
//! [`Environment::pdf`] sit side by side: the pdf is the density of exactly that mixture.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::env_harmonics::SkyHarmonics;
use super::env_map::{EnvMap, EnvSample};
use crate::shade::color::luminance;
use crate::shade::sampling::uniform_sphere;

/// The scene's environment: a constant part plus an optional map.
#[derive(Debug, Clone)]
pub struct Environment {
    /// The sum of the scene's constant environments (radiance from every direction).
    pub constant: Vec3,
    /// The image environment, if any (added to `constant`).
    pub map: Option<EnvMap>,
    /// Whether escaped camera rays show it.
    pub visible: bool,
    /// Probability of sampling the map rather than the uniform sphere (set by
    /// [`Environment::prepare_sampling`]).
    map_fraction: f32,
    /// Whether the sampling tables were built (only for scenes with geometry).
    sampled: bool,
    /// The sky without the map's bright set, as spherical harmonics (set by
    /// [`Environment::prepare_sampling`]; `env_harmonics`).
    harmonics: Option<SkyHarmonics>,
    /// The sky's exact irradiance for the normals `+y` and `−y`, the bright set left out (set
    /// by [`Environment::prepare_sampling`]; `env_vertical`).
    vertical: Option<[Vec3; 2]>,
}

impl Environment {
    /// An environment whose sampling is not prepared yet (see
    /// [`Environment::prepare_sampling`]).
    pub fn new(constant: Vec3, map: Option<EnvMap>, visible: bool) -> Environment {
        Environment {
            constant,
            map,
            visible,
            map_fraction: 0.0,
            sampled: false,
            harmonics: None,
            vertical: None,
        }
    }

    /// Whether nothing is emitted at all.
    pub fn is_black(&self) -> bool {
        self.constant.max_element() <= 0.0 && self.map.is_none()
    }

    /// Builds the map's table; returns `false` if the map turned out black (it is then dropped).
    pub fn prepare_sampling(&mut self) -> bool {
        let mut black_map = false;
        if let Some(map) = &mut self.map {
            // A map reused from the watch cache keeps the table it was given last time.
            if !map.has_distribution() && !map.build_distribution() {
                black_map = true;
                self.map = None;
            }
        }
        let map_weight = self.map.as_ref().map_or(0.0, |m| luminance(m.average()));
        let constant_weight = luminance(self.constant.max(Vec3::ZERO));
        self.map_fraction = if map_weight > 0.0 {
            map_weight / (map_weight + constant_weight)
        } else {
            0.0
        };
        self.harmonics = match &self.map {
            Some(map) => map.sky_harmonics().map(|h| h.with_constant(self.constant)),
            None => Some(SkyHarmonics::constant(self.constant)),
        };
        let constant = PI * self.constant;
        let [up, down] = self
            .map
            .as_ref()
            .map_or([Vec3::ZERO; 2], EnvMap::vertical_irradiance);
        self.vertical = Some([up + constant, down + constant]);
        self.sampled = true;
        !black_map
    }

    /// The smooth fit of the sky without the map's bright set (`env_harmonics`), for the
    /// render's control variate; `None` before [`Environment::prepare_sampling`].
    pub fn harmonics(&self) -> Option<&SkyHarmonics> {
        self.harmonics.as_ref()
    }

    /// The exact `∫ L(ω) max(0, n·ω) dω` of the environment without the map's bright set, for
    /// `n = +y` (`up`) or `−y` (`env_vertical`); `None` before
    /// [`Environment::prepare_sampling`].
    pub fn vertical_irradiance(&self, up: bool) -> Option<Vec3> {
        self.vertical.map(|[u, d]| if up { u } else { d })
    }

    /// The radiance from direction `d` (unit) with the map's bright set left out: the function
    /// [`Environment::vertical_irradiance`] integrates.
    pub fn radiance_apart_from_bright(&self, d: Vec3) -> Vec3 {
        self.constant
            + self
                .map
                .as_ref()
                .map_or(Vec3::ZERO, |m| m.radiance_apart_from_bright(d))
    }

    /// Whether unit direction `d` may read a texel of the map's bright set (`false`: surely
    /// not, or there is no set).
    pub fn may_be_bright(&self, d: Vec3) -> bool {
        self.map
            .as_ref()
            .is_some_and(|m| m.has_bright() && m.may_be_bright(d))
    }

    /// Solid-angle-weighted mean radiance (for picking lights by power).
    pub fn average_radiance(&self) -> Vec3 {
        self.constant + self.map.as_ref().map_or(Vec3::ZERO, EnvMap::average)
    }

    /// The power used to pick the environment among the lights, `None` before
    /// [`Environment::prepare_sampling`] or when it emits nothing: `π · (π R²) · L̄`, the flux an
    /// area light of the scene's cross-section (`R` = bounding-sphere radius) and the
    /// environment's mean radiance `L̄` (averaged over channels) would emit, so that it compares
    /// with [`super::AreaLight::power`] (`π · A · L`).
    pub fn power(&self, scene_radius: f32) -> Option<f32> {
        let mean = self.average_radiance().element_sum() / 3.0;
        let power = PI * PI * scene_radius * scene_radius * mean;
        (self.sampled && power > 0.0 && power.is_finite()).then_some(power)
    }

    /// Radiance from world direction `d` (unit).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.constant + self.map.as_ref().map_or(Vec3::ZERO, |m| m.radiance(d))
    }

    /// A direction with density `pdf_solid_angle` (the map by its table with probability
    /// `map_fraction`, otherwise uniform over the sphere).
    pub fn sample(&self, u: Vec2) -> Option<EnvSample> {
        self.sample_facing(u, None)
    }

    /// [`Environment::sample`] for a surface facing unit `normal`: the map part favours the
    /// directions above that surface's horizon (`env_sampler`); `None` samples by radiance.
    pub fn sample_facing(&self, u: Vec2, normal: Option<Vec3>) -> Option<EnvSample> {
        let f = self.map_fraction;
        if u.x < f {
            let map = self.map.as_ref()?;
            let u_map = Vec2::new((u.x / f).min(1.0 - f32::EPSILON / 2.0), u.y);
            let s = map.sample_facing(u_map, normal)?;
            return Some(EnvSample {
                wi: s.wi,
                radiance: self.constant + s.radiance,
                pdf_solid_angle: f * s.pdf_solid_angle + (1.0 - f) / (4.0 * PI),
            });
        }
        let u_sphere = Vec2::new(((u.x - f) / (1.0 - f)).clamp(0.0, 1.0), u.y);
        let wi = uniform_sphere(u_sphere);
        Some(EnvSample {
            wi,
            radiance: self.radiance(wi),
            pdf_solid_angle: self.pdf_facing(wi, normal),
        })
    }

    /// The density of [`Environment::sample`] at world direction `d` (unit).
    #[inline]
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_facing(d, None)
    }

    /// [`Environment::radiance`] and [`Environment::pdf_facing`] of one direction (the map's
    /// texel found once).
    pub fn radiance_and_pdf_facing(&self, d: Vec3, normal: Option<Vec3>) -> (Vec3, f32) {
        let f = self.map_fraction;
        let (map_radiance, map_pdf) = self
            .map
            .as_ref()
            .map_or((Vec3::ZERO, 0.0), |m| m.radiance_and_pdf_facing(d, normal));
        (
            self.constant + map_radiance,
            f * map_pdf + (1.0 - f) / (4.0 * PI),
        )
    }

    /// Whether the map has a bright set (a small sun) that the render samples on its own
    /// ([`Environment::sample_bright`]) beside the rest ([`Environment::sample_sky_facing`]).
    pub fn has_bright(&self) -> bool {
        self.map.as_ref().is_some_and(EnvMap::has_bright)
    }

    /// Whether every direction of the map's bright set lies below the horizon of unit `n`
    /// (`false` when unsure): a surface facing `n` then gets nothing from its samples.
    pub fn bright_below_horizon_of(&self, n: Vec3) -> bool {
        self.map
            .as_ref()
            .is_some_and(|m| m.bright_below_horizon_of(n))
    }

    /// The sky strategy of a split environment: the map without its bright set (probability
    /// `map_fraction`) or the uniform sphere. Its sample's `pdf_solid_angle` is this strategy's
    /// density; the second value is the bright strategy's density at the same direction.
    pub fn sample_sky_facing(&self, u: Vec2, normal: Option<Vec3>) -> Option<(EnvSample, f32)> {
        let f = self.map_fraction;
        if u.x < f {
            let map = self.map.as_ref()?;
            let u_map = Vec2::new((u.x / f).min(1.0 - f32::EPSILON / 2.0), u.y);
            let s = map.sample_sky_facing(u_map, normal)?;
            // The sky's tables leave the bright texels out: the bright density is 0 here.
            let sample = EnvSample {
                wi: s.wi,
                radiance: self.constant + s.radiance,
                pdf_solid_angle: f * s.pdf_solid_angle + (1.0 - f) / (4.0 * PI),
            };
            return Some((sample, 0.0));
        }
        let u_sphere = Vec2::new(((u.x - f) / (1.0 - f)).clamp(0.0, 1.0), u.y);
        let wi = uniform_sphere(u_sphere);
        let (radiance, sky, bright) = self.radiance_and_densities_facing(wi, normal);
        let sample = EnvSample {
            wi,
            radiance,
            pdf_solid_angle: sky,
        };
        Some((sample, bright))
    }

    /// The bright strategy of a split environment: a direction in the map's bright set, with
    /// this strategy's density, and the sky strategy's density at the same direction.
    pub fn sample_bright(&self, u: Vec2) -> Option<(EnvSample, f32)> {
        let s = self.map.as_ref()?.sample_bright(u)?;
        let sample = EnvSample {
            wi: s.wi,
            radiance: self.constant + s.radiance,
            pdf_solid_angle: s.pdf_solid_angle,
        };
        // The map's sky tables give the bright texels no weight; the uniform part does.
        Some((sample, (1.0 - self.map_fraction) / (4.0 * PI)))
    }

    /// The radiance from direction `d` (unit) and the densities of the split environment's two
    /// strategies there: sky ([`Environment::sample_sky_facing`]) and bright
    /// ([`Environment::sample_bright`]).
    pub fn radiance_and_densities_facing(&self, d: Vec3, normal: Option<Vec3>) -> (Vec3, f32, f32) {
        let f = self.map_fraction;
        let (map_radiance, sky, bright) = self
            .map
            .as_ref()
            .map_or((Vec3::ZERO, 0.0, 0.0), |m| m.densities_facing(d, normal));
        (
            self.constant + map_radiance,
            f * sky + (1.0 - f) / (4.0 * PI),
            bright,
        )
    }

    /// The radiance from direction `d` (unit) and the bright strategy's density there
    /// ([`Environment::sample_bright`]), without the sky strategy's: for renders that leave
    /// the sky to BRDF rays (`render::mis`).
    pub fn radiance_and_bright_density(&self, d: Vec3) -> (Vec3, f32) {
        let (map_radiance, bright) = self
            .map
            .as_ref()
            .map_or((Vec3::ZERO, 0.0), |m| m.radiance_and_bright_density(d));
        (self.constant + map_radiance, bright)
    }

    /// The bright strategy's density at direction `d` (unit) alone
    /// ([`Environment::radiance_and_bright_density`] without the radiance): for a BRDF
    /// direction whose sky is not seen.
    pub fn bright_density(&self, d: Vec3) -> f32 {
        self.map.as_ref().map_or(0.0, |m| m.bright_density(d))
    }

    /// The density of [`Environment::sample_facing`] for the same `normal`.
    #[inline]
    pub fn pdf_facing(&self, d: Vec3, normal: Option<Vec3>) -> f32 {
        let f = self.map_fraction;
        let map = self.map.as_ref().map_or(0.0, |m| m.pdf_facing(d, normal));
        f * map + (1.0 - f) / (4.0 * PI)
    }
}
