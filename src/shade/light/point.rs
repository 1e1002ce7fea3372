//! Point lights: `light bulb = point { position (0, 4, 0)  intensity rgb(10, 10, 10) }`.

use glam::Vec3;

#[derive(Debug, Clone)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity, W/sr per channel.
    pub intensity: Vec3,
}

impl PointLight {
    pub fn power(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.intensity.element_sum() / 3.0
    }
}
