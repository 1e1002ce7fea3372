//! The flattened BVH node (32 bytes, two per cache line) and the ray–box slab test.
//!
//! Layout: depth-first order; an interior node's first child is the next node, its second child
//! is at `right`. A leaf names `count` consecutive primitives starting at `first`. Stage: built by
//! `bvh::build`, read by `bvh::traverse`.

use glam::{Vec3, Vec3A};

use crate::geom::{Aabb, Ray};

/// Most primitives in one leaf (the builder never exceeds it).
pub const MAX_LEAF: u32 = 8;
/// Deepest path the builder produces; traversal stacks are sized from it.
pub const MAX_DEPTH: usize = 96;

/// One node of a flattened BVH: bounds, then either the second child (interior) or the first
/// primitive (leaf), and `count << 2 | split axis` (`count == 0` marks an interior node).
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
pub struct Node {
    pub min: [f32; 3],
    pub index: u32,
    pub max: [f32; 3],
    pub meta: u32,
}

impl Node {
    pub fn leaf(b: &Aabb, first: u32, count: u32) -> Node {
        debug_assert!(count > 0 && count <= MAX_LEAF);
        Node {
            min: b.min.to_array(),
            index: first,
            max: b.max.to_array(),
            meta: count << 2,
        }
    }

    pub fn interior(b: &Aabb, right: u32, axis: usize) -> Node {
        Node {
            min: b.min.to_array(),
            index: right,
            max: b.max.to_array(),
            meta: axis as u32 & 3,
        }
    }

    #[inline]
    pub fn count(&self) -> u32 {
        self.meta >> 2
    }

    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count() > 0
    }

    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::from_array(self.min),
            max: Vec3::from_array(self.max),
        }
    }
}

/// Slab-test form of a ray: origin and reciprocal direction, with reciprocals of zero (or so
/// small that they overflow) replaced by a huge finite value of the same sign, so that
/// `(bound − origin) · inv` is never `0 · ∞ = NaN`.
#[derive(Debug, Clone, Copy)]
pub struct RayBox {
    origin: Vec3A,
    inv_dir: Vec3A,
}

/// Slack on the exit distance: three roundings in the slab computation (Ize 2013).
const EXIT_SLACK: f32 = 1.0 + 2.0 * 3.0 * f32::EPSILON * 0.5 / (1.0 - 3.0 * f32::EPSILON * 0.5);

impl RayBox {
    pub fn new(ray: &Ray) -> RayBox {
        let fix = |d: f32| {
            let inv = 1.0 / d;
            if inv.is_finite() {
                inv
            } else {
                f32::MAX.copysign(d)
            }
        };
        let inv_dir = Vec3A::new(fix(ray.dir.x), fix(ray.dir.y), fix(ray.dir.z));
        RayBox {
            origin: Vec3A::from(ray.origin),
            inv_dir,
        }
    }

    /// Entry distance of the ray into the node's box within `(0, t_max)`, or `None`.
    #[inline(always)]
    pub fn hit(&self, n: &Node, t_max: f32) -> Option<f32> {
        // (bound − origin) · inv, not bound · inv − origin · inv: the latter is ∞ − ∞ = NaN
        // when a huge reciprocal meets a non-zero origin. Callers reject non-finite rays, so
        // no NaN reaches the min/max below.
        let lo = (Vec3A::from_array(n.min) - self.origin) * self.inv_dir;
        let hi = (Vec3A::from_array(n.max) - self.origin) * self.inv_dir;
        let t_near = lo.min(hi).max_element().max(0.0);
        let t_far = lo.max(hi).min_element().min(t_max) * EXIT_SLACK;
        (t_near <= t_far).then_some(t_near)
    }

    /// Whether a box entered at `t_entry` may still hold a hit closer than `t_max`.
    #[inline(always)]
    pub fn still_open(t_entry: f32, t_max: f32) -> bool {
        t_entry <= t_max * EXIT_SLACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_32_bytes() {
        assert_eq!(std::mem::size_of::<Node>(), 32);
    }

    #[test]
    fn slab_test_handles_axis_parallel_rays_and_flat_boxes() {
        let flat = Node::leaf(
            &Aabb {
                min: Vec3::new(0.0, 0.0, 1.0),
                max: Vec3::new(1.0, 1.0, 1.0),
            },
            0,
            1,
        );
        let down = RayBox::new(&Ray::new(Vec3::new(0.5, 0.5, 2.0), -Vec3::Z));
        assert_eq!(down.hit(&flat, f32::INFINITY), Some(1.0));
        // Origin exactly on the x = 0 face, travelling along +z only: 0 · ∞ must not be NaN.
        let grazing = RayBox::new(&Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Z));
        assert!(grazing.hit(&flat, f32::INFINITY).is_some());
        let outside = RayBox::new(&Ray::new(Vec3::new(-0.1, 0.5, 0.0), Vec3::Z));
        assert!(outside.hit(&flat, f32::INFINITY).is_none());
        assert!(down.hit(&flat, 0.5).is_none());
    }
}
