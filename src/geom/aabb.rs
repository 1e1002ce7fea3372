//! Axis-aligned bounding boxes: the bounds the BVH is built from and checked against. Pure
//! geometry, no scene or file knowledge.

use glam::Vec3;

/// An axis-aligned box; the empty box has `min = +∞`, `max = -∞` so that growing it by any point
/// gives that point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// Lower corner (componentwise minimum); `+∞` on every axis when empty.
    pub min: Vec3,
    /// Upper corner (componentwise maximum); `-∞` on every axis when empty.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Aabb {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The box that contains nothing: growing it by a point gives that point.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The smallest box containing every point; [`Aabb::EMPTY`] for none.
    pub fn from_points(points: &[Vec3]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, &p| b.grow(p))
    }

    /// This box enlarged just enough to contain `p`.
    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// The smallest box containing both (an empty box adds nothing).
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// Whether the box holds no point (`min > max` on some axis); a single point is not empty.
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The size along each axis: `max − min`, or zero for an empty box (never negative).
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// The midpoint of `min` and `max`; NaN for an empty box, so callers test emptiness first.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Total area of the six faces (the SAH cost weight); zero for an empty box.
    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Whether `o` lies inside this box, boundary included; every box contains an empty one.
    pub fn contains(&self, o: &Aabb) -> bool {
        o.is_empty() || (self.min.cmple(o.min).all() && self.max.cmpge(o.max).all())
    }

    /// The bounds of this box's eight corners under an affine map.
    pub fn transformed(&self, m: &glam::Affine3A) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        let mut out = Aabb::EMPTY;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { self.min.x } else { self.max.x },
                if i & 2 == 0 { self.min.y } else { self.max.y },
                if i & 4 == 0 { self.min.z } else { self.max.z },
            );
            out = out.grow(m.transform_point3(c));
        }
        out
    }
}
