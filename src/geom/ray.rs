//! A ray with a parametric extent, as traced by cameras, shadow tests and the BVH.

use glam::Vec3;

/// Points `origin + t·dir` for `t` in `(0, t_max)`. `dir` need not be unit length; `t` is
/// measured in multiples of `dir`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Start point (world space, or object space once an instance has transformed the ray).
    pub origin: Vec3,
    /// Direction, in the same space as `origin`; not normalised, and `t` counts multiples of it.
    pub dir: Vec3,
    /// Exclusive upper bound on `t`: hits at or beyond it do not count; `∞` when unbounded.
    pub t_max: f32,
}

impl Ray {
    /// An unbounded ray (`t_max = ∞`) from `origin` along `dir`.
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray {
            origin,
            dir,
            t_max: f32::INFINITY,
        }
    }

    /// A ray that ends before `origin + t_max·dir` (a shadow ray stopping short of its light).
    pub fn segment(origin: Vec3, dir: Vec3, t_max: f32) -> Ray {
        Ray { origin, dir, t_max }
    }

    /// The point `origin + t·dir`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}
