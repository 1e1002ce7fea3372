//! A ray with a parametric extent, as traced by cameras, shadow tests and the BVH.

use glam::Vec3;

/// Points `origin + t·dir` for `t` in `(0, t_max)`. `dir` need not be unit length; `t` is
/// measured in multiples of `dir`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_max: f32,
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir,
            t_max: f32::INFINITY,
        }
    }

    pub fn segment(origin: Vec3, dir: Vec3, t_max: f32) -> Ray {
        Ray { origin, dir, t_max }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}
