//! Colour: what "how bright" means for the renderer's linear RGB.
//!
//! Radiance is linear RGB with Rec. 709 (sRGB) primaries from the scene's numbers to the film;
//! the film encodes it at the very end (`film::encode`). Wherever a colour must become one number
//! (the environment's importance table, the adaptive sampler's error estimate, the light-sliver
//! rule, the tests' error measures), it is this module's luminance, so every stage weighs the
//! channels the same way.

use glam::{DVec3, Vec3};

/// Rec. 709 luminance weights of linear R, G and B (ITU-R BT.709, the Y row of RGB → XYZ).
pub const LUMINANCE_WEIGHTS: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// Rec. 709 luminance of linear RGB.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::from_array(LUMINANCE_WEIGHTS))
}

/// Rec. 709 luminance of linear RGB in f64, for sums over many samples. The weights are the
/// decimal constants themselves (not their f32 roundings).
pub fn luminance_f64(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.2126, 0.7152, 0.0722))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_has_unit_luminance_and_green_weighs_most() {
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
        assert!((luminance_f64(DVec3::ONE) - 1.0).abs() < 1e-12);
        assert!(luminance(Vec3::Y) > luminance(Vec3::X));
        assert!(luminance(Vec3::X) > luminance(Vec3::Z));
    }
}
