//! Stage 4: the pin-hole camera, film coordinates → world rays.
//!
//! Syntax: `camera main { eye (0, 1, -5)  target (0, 1, 0)  up (0, 1, 0)  fov 40deg }` (the
//! checker turns it into an orthonormal frame). The vertical field of view is `fov`; the
//! horizontal one follows from the aspect ratio. Film coordinates are in pixels with (0, 0) the
//! top-left corner of the image: +x maps to the camera's `right`, −y (up the image) to `up`.

use glam::{Vec2, Vec3};

use crate::geom::Ray;
use crate::ir;

/// A pinhole camera ready to make rays for one image size.
#[derive(Debug, Clone, Copy)]
pub struct PinholeCamera {
    eye: Vec3,
    forward: Vec3,
    /// `right · tan(fov_y / 2) · aspect`: the image plane's half width at distance 1.
    half_width: Vec3,
    /// `up · tan(fov_y / 2)`.
    half_height: Vec3,
    size_px: Vec2,
    /// `1 / size_px` when both sides are powers of two (then exact, and a multiplication by
    /// it is the division's bits without its latency on every camera ray); `None` otherwise.
    exact_inv_size_px: Option<Vec2>,
}

impl PinholeCamera {
    /// The scene's camera for a `width` × `height` image.
    pub fn new(camera: &ir::Camera, width: u32, height: u32) -> PinholeCamera {
        let size_px = Vec2::new(width.max(1) as f32, height.max(1) as f32);
        let tan_half = (camera.fov_y_rad / 2.0).tan();
        let aspect = size_px.x / size_px.y;
        PinholeCamera {
            // The build made the eye relative to the scene's origin: a small number.
            eye: camera.eye.as_vec3(),
            forward: camera.forward,
            half_width: camera.right * tan_half * aspect,
            half_height: camera.up * tan_half,
            size_px,
            exact_inv_size_px: (width.max(1).is_power_of_two() && height.max(1).is_power_of_two())
                .then(|| size_px.recip()),
        }
    }

    /// The eye (the centre of projection), world space.
    pub fn eye(&self) -> Vec3 {
        self.eye
    }

    /// The ray through film position `film_px` (pixels, from the top-left corner); its
    /// direction is unit length so that `t` is a distance.
    pub fn ray(&self, film_px: Vec2) -> Ray {
        let film = match self.exact_inv_size_px {
            Some(inv) => 2.0 * film_px * inv,
            None => 2.0 * film_px / self.size_px,
        };
        let (x, y) = (film.x - 1.0, 1.0 - film.y);
        let dir = self.forward + x * self.half_width + y * self.half_height;
        Ray::new(self.eye, dir.normalize())
    }

    /// Where `point` appears on the film (pixels from the top-left corner, possibly off the
    /// image): the inverse of [`PinholeCamera::ray`]. `None` for a point not in front of the
    /// camera.
    pub fn project(&self, point: Vec3) -> Option<Vec2> {
        let v = point - self.eye;
        let depth = v.dot(self.forward);
        if !depth.is_finite() || depth <= 0.0 {
            return None;
        }
        // `forward`, `half_width` and `half_height` are orthogonal (the checker's frame).
        let x = v.dot(self.half_width) / (depth * self.half_width.length_squared());
        let y = v.dot(self.half_height) / (depth * self.half_height.length_squared());
        let film = Vec2::new(
            (x + 1.0) * 0.5 * self.size_px.x,
            (1.0 - y) * 0.5 * self.size_px.y,
        );
        film.is_finite().then_some(film)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(fov_y_deg: f32) -> ir::Camera {
        ir::Camera {
            name: "main".into(),
            eye: glam::DVec3::new(1.0, 2.0, 3.0),
            forward: Vec3::Z,
            up: Vec3::Y,
            right: Vec3::Z.cross(Vec3::Y),
            fov_y_rad: fov_y_deg.to_radians(),
            span: crate::source::Span::new(crate::source::FileId(0), 0, 0),
        }
    }

    #[test]
    fn project_inverts_ray() {
        let c = PinholeCamera::new(&camera(50.0), 64, 32);
        for p in [
            Vec2::new(32.0, 16.0),
            Vec2::new(3.5, 30.25),
            Vec2::new(63.0, 0.5),
        ] {
            let r = c.ray(p);
            let back = c.project(r.origin + 7.0 * r.dir).expect("in front");
            assert!((back - p).length() < 1e-3, "{p} -> {back}");
        }
        assert_eq!(c.project(Vec3::new(1.0, 2.0, 3.0) - Vec3::Z), None);
    }

    #[test]
    fn power_of_two_films_make_the_same_rays_as_the_division() {
        for (w, h) in [(512, 512), (64, 32), (1, 1), (160, 120), (64, 48)] {
            let c = PinholeCamera::new(&camera(39.3), w, h);
            assert_eq!(
                c.exact_inv_size_px.is_some(),
                w.is_power_of_two() && h.is_power_of_two()
            );
            for p in [
                Vec2::new(0.37, 0.91),
                Vec2::new(w as f32 * 0.5 + 0.123, h as f32 - 0.01),
                Vec2::new(w as f32 - 1e-3, 1e-3),
            ] {
                let x = 2.0 * p.x / w as f32 - 1.0;
                let y = 1.0 - 2.0 * p.y / h as f32;
                let dir = c.forward + x * c.half_width + y * c.half_height;
                assert_eq!(c.ray(p).dir, dir.normalize(), "{w}x{h} at {p}");
            }
        }
    }

    #[test]
    fn centre_ray_is_forward_and_starts_at_the_eye() {
        let c = PinholeCamera::new(&camera(50.0), 64, 32);
        let r = c.ray(Vec2::new(32.0, 16.0));
        assert!((r.dir - Vec3::Z).length() < 1e-6);
        assert_eq!(r.origin, Vec3::new(1.0, 2.0, 3.0));
    }

    #[test]
    fn edges_and_corners_make_the_expected_angles() {
        let fov_y = 40.0_f32.to_radians();
        let (w, h) = (80u32, 40u32);
        let cam = camera(40.0);
        let c = PinholeCamera::new(&cam, w, h);
        let tan_y = (fov_y / 2.0).tan();
        let tan_x = tan_y * w as f32 / h as f32;
        let angle = |p: Vec2| c.ray(p).dir.dot(Vec3::Z).clamp(-1.0, 1.0).acos();
        // Top edge centre: exactly half the vertical fov, pointing up.
        let top = c.ray(Vec2::new(40.0, 0.0));
        assert!((angle(Vec2::new(40.0, 0.0)) - fov_y / 2.0).abs() < 1e-5);
        assert!(top.dir.y > 0.0);
        // Right edge centre: half the horizontal fov, towards camera.right.
        let right = c.ray(Vec2::new(80.0, 20.0));
        assert!((angle(Vec2::new(80.0, 20.0)) - tan_x.atan()).abs() < 1e-5);
        assert!(right.dir.dot(cam.right) > 0.0);
        // Top-left corner.
        let corner = (tan_x * tan_x + tan_y * tan_y).sqrt().atan();
        assert!((angle(Vec2::ZERO) - corner).abs() < 1e-5);
        let d = c.ray(Vec2::ZERO).dir;
        assert!(d.dot(cam.right) < 0.0 && d.dot(cam.up) > 0.0);
    }
}
