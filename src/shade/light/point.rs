//! Point lights: `light bulb = point { position (0, 4, 0)  intensity rgb(10, 10, 10) }`.
//!
//! A point light is a delta distribution: [`PointLight::sample`] gives the one direction light
//! arrives from, and [`PointLight::pdf`] of any direction a BRDF ray could take is 0 (no ray
//! can hit a point), so point lights are always light-sampled, never weighted by MIS.

use glam::Vec3;

/// An isotropic point emitter.
#[derive(Debug, Clone)]
pub struct PointLight {
    /// World-space position.
    pub position: Vec3,
    /// Radiant intensity, W/sr per channel.
    pub intensity: Vec3,
}

/// The light a point light sends to a shading point (see [`PointLight::sample`]).
#[derive(Debug, Clone, Copy)]
pub struct PointSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// The light's position: the shadow ray's end.
    pub position: Vec3,
    /// Radiant intensity towards the shading point, W/sr.
    pub intensity: Vec3,
    /// Squared distance to the light. The irradiance at normal incidence is
    /// `intensity / dist2`; the estimator divides by it last, so it is kept apart.
    pub dist2: f32,
}

impl PointLight {
    /// Radiant flux (W per channel, averaged over channels) used to pick lights by power.
    pub fn power(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.intensity.element_sum() / 3.0
    }

    /// The one direction light arrives from at the shading point `p`, with probability 1 (a
    /// delta: no density, no random numbers).
    pub fn sample(&self, p: Vec3) -> PointSample {
        let to_light = self.position - p;
        let dist2 = to_light.length_squared();
        PointSample {
            wi: to_light / dist2.sqrt(),
            position: self.position,
            intensity: self.intensity,
            dist2,
        }
    }

    /// The solid-angle density of [`PointLight::sample`] at any direction `_wi` from `_p`:
    /// always 0, since it is a delta that no BRDF-sampled direction hits.
    pub fn pdf(&self, _p: Vec3, _wi: Vec3) -> f32 {
        0.0
    }
}
