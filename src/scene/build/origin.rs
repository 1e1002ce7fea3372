//! Stage 3, build: the world origin the render-ready scene is kept relative to.
//!
//! f32 resolves a coordinate `x` to about `|x| · 2⁻²³`. A small scene far from the origin
//! (`group { transform { scale 1e-3  translate (1e4, 1e4, 1e4) } … }`) would keep only a few
//! hundred steps across itself, and a light 0.02% of the scene below its ceiling would fall on
//! the ceiling's plane. So the build picks an origin near the scene's centre, computes every
//! world-space position relative to it in f64 (transforms, area-light triangles, point lights,
//! the camera's eye) and only then rounds to f32: the renderer sees small numbers whatever the
//! placement, at no cost per ray. Directions, and with them the environment map, are unchanged.
//!
//! A scene within 64 times its own size of the world origin keeps the origin (0, 0, 0), where
//! f32 already resolves it to ~1e-5 of its size: every such scene renders bit for bit as
//! before. Otherwise the origin is the scene's centre snapped to a power-of-two grid about the
//! size of the scene, so that a camera move or a small edit does not move it (which would
//! rebuild the cached acceleration structure in `scnc watch`).
//!
//! What f32 cannot hold even then — an object placed far from the others in a large scene, or
//! vertices written in world coordinates far from their mesh's origin — is reported per object
//! ([`resolution`]).

use glam::{Affine3A, DMat3, DMat4, DVec3, Vec3};

/// How far from the world origin, in multiples of its size, a scene stays where it is.
const KEEP_WITHIN: f64 = 64.0;

/// The origin for a scene whose placed geometry spans `lo..hi` (world space, f64).
pub fn world_origin(lo: DVec3, hi: DVec3) -> DVec3 {
    let (centre, size) = ((lo + hi) / 2.0, (hi - lo).max_element());
    let far = centre.abs().max_element();
    if !(centre.is_finite() && size.is_finite()) || far <= KEEP_WITHIN * size {
        return DVec3::ZERO;
    }
    let step = size.max(far * 1e-12).log2().ceil().exp2();
    (centre / step).round() * step
}

/// `world_from_object` (f64, as the checker composed it) relative to `origin`, rounded to f32
/// once: with the origin at zero, bit for bit `Affine3A::from_mat4(m.as_mat4())`.
pub fn recentred(m: DMat4, origin: DVec3) -> Affine3A {
    let translation = (m.w_axis.truncate() - origin).as_vec3();
    Affine3A::from_mat3_translation(DMat3::from_mat4(m).as_mat3(), translation)
}

/// A point relative to `origin`, rounded once.
pub fn relative(p: DVec3, origin: DVec3) -> Vec3 {
    (p - origin).as_vec3()
}

/// The world-space bounds (f64) of an object-space box placed by `m`; `None` if not finite.
pub fn placed_bounds(lo: Vec3, hi: Vec3, m: DMat4) -> Option<(DVec3, DVec3)> {
    let (mut out_lo, mut out_hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for i in 0..8 {
        let pick = |bit: usize, a: f32, b: f32| f64::from(if i & bit == 0 { a } else { b });
        let c = DVec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        );
        let w = m.transform_point3(c);
        out_lo = out_lo.min(w);
        out_hi = out_hi.max(w);
    }
    (out_lo.is_finite() && out_hi.is_finite()).then_some((out_lo, out_hi))
}

/// The smallest step an object's world positions can move by once rounded to f32, and its size:
/// its object-space coordinates' own rounding (scaled by the transform) plus that of its
/// recentred world coordinates.
pub fn resolution(lo: Vec3, hi: Vec3, m: DMat4, origin: DVec3) -> Option<(f64, f64)> {
    let (w_lo, w_hi) = placed_bounds(lo, hi, m)?;
    let size = (w_hi - w_lo).max_element();
    let object_far = f64::from(lo.abs().max(hi.abs()).max_element());
    let scale = DMat3::from_mat4(m)
        .to_cols_array()
        .iter()
        .fold(0.0f64, |a, &b| a.max(b.abs()));
    let world_far = (w_lo - origin)
        .abs()
        .max((w_hi - origin).abs())
        .max_element();
    let ulp = f64::from(f32::EPSILON);
    Some(((object_far * scale + world_far) * ulp, size))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_near_the_origin_keep_it_and_far_ones_move_it_to_their_centre() {
        let cornell = (DVec3::ZERO, DVec3::new(556.0, 548.8, 559.2));
        assert_eq!(world_origin(cornell.0, cornell.1), DVec3::ZERO);
        let far = DVec3::splat(1e4);
        let small = (far, far + DVec3::splat(0.55));
        let o = world_origin(small.0, small.1);
        assert!((o - far).abs().max_element() <= 1.0, "{o}");
        assert_eq!(o.x.fract(), 0.0, "snapped to the grid of the scene's size");
        assert_eq!(world_origin(DVec3::NAN, DVec3::ONE), DVec3::ZERO);
    }

    #[test]
    fn recentring_at_zero_changes_no_bit() {
        let m = DMat4::from_scale_rotation_translation(
            DVec3::new(0.3, 2.0, 1.5),
            glam::DQuat::from_rotation_y(0.7),
            DVec3::new(1.25, -3.0, 7.1),
        );
        let a = recentred(m, DVec3::ZERO);
        assert_eq!(a, Affine3A::from_mat4(m.as_mat4()));
        let far = recentred(
            DMat4::from_translation(DVec3::splat(1e4 + 0.1)),
            DVec3::splat(1e4),
        );
        assert!(
            (far.translation - glam::Vec3A::splat(0.1))
                .abs()
                .max_element()
                < 1e-7
        );
        let far = recentred(
            DMat4::from_translation(DVec3::splat(1e4)),
            DVec3::splat(1e4 - 0.5),
        );
        assert_eq!(far.translation, glam::Vec3A::splat(0.5));
    }
}
