//! Shading layer: where the emitters are, so that a BRDF-sampled ray that cannot reach one is
//! not traced at all.
//!
//! In a scene without an environment, a BRDF-sampled ray (the second strategy of multiple
//! importance sampling, `render::mis`) adds something only if it hits an area light. Most of
//! them do not: on cornell, whose light covers a few percent of the hemisphere, they were a
//! third of all rays traced. A ray that misses every emitter's bounding box cannot hit one, so
//! its contribution is zero whatever the BVH would say, and the trace is skipped; the image is
//! unchanged bit for bit (the boxes are padded well beyond any rounding of the intersection
//! tests, so a ray the BVH could find on an emitter always passes).

use glam::Vec3;

use super::Light;
use crate::geom::Aabb;

/// Boxes tested one by one up to this many area lights; beyond, one box around them all.
const MAX_BOXES: usize = 16;

/// The padded bounding boxes of the area lights (none when there is no area light).
#[derive(Debug, Clone, Default)]
pub struct EmitterBounds {
    boxes: Vec<Aabb>,
}

impl EmitterBounds {
    /// The boxes of the area lights among `lights`.
    pub fn new(lights: &[Light]) -> EmitterBounds {
        let mut boxes: Vec<Aabb> = lights
            .iter()
            .filter_map(|l| match l {
                Light::Area(a) => Some(
                    a.triangles
                        .iter()
                        .fold(Aabb::EMPTY, |b, t| b.union(Aabb::from_points(t))),
                ),
                Light::Point(_) => None,
            })
            .filter(|b| !b.is_empty())
            .map(padded)
            .collect();
        if boxes.len() > MAX_BOXES {
            boxes = vec![boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(*b))];
        }
        EmitterBounds { boxes }
    }

    /// Whether a ray from `origin` along `dir` (any length) may hit an emitter: `false` only
    /// when it misses every box.
    #[inline]
    pub fn may_reach(&self, origin: Vec3, dir: Vec3) -> bool {
        // A reciprocal of ±0 becomes a huge finite value of the same sign, so that
        // (bound − origin) · inv is never 0 · ∞.
        let inv = dir.recip();
        let inv = Vec3::select(
            inv.is_finite_mask(),
            inv,
            Vec3::splat(f32::MAX).copysign(dir),
        );
        self.boxes.iter().any(|b| {
            let t0 = (b.min - origin) * inv;
            let t1 = (b.max - origin) * inv;
            let near = t0.min(t1).max_element().max(0.0);
            let far = t0.max(t1).min_element();
            near <= far
        })
    }
}

/// `b` grown by a margin far above the rounding of any intersection test: 1e-4 of its largest
/// extent, and at least 1e-5 of its largest coordinate (a flat light has zero extent across).
fn padded(b: Aabb) -> Aabb {
    let size = b.extent().max_element() * 1e-4;
    let magnitude = b.min.abs().max(b.max.abs()).max_element() * 1e-5;
    let pad = Vec3::splat(size.max(magnitude).max(f32::MIN_POSITIVE));
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shade::light::area::AreaLight;

    fn panel() -> Vec<Light> {
        // A 1 × 1 panel at height 2, facing down.
        let (a, b, c, d) = (
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(1.0, 2.0, 1.0),
            Vec3::new(0.0, 2.0, 1.0),
        );
        let light = AreaLight::new(Vec3::ONE, false, 1, vec![[a, c, b], [a, d, c]]);
        vec![Light::Area(light.expect("a valid panel"))]
    }

    #[test]
    fn rays_towards_the_panel_may_reach_it_and_others_do_not() {
        let e = EmitterBounds::new(&panel());
        let o = Vec3::new(0.5, 0.0, 0.5);
        assert!(e.may_reach(o, Vec3::Y));
        assert!(e.may_reach(o, Vec3::new(0.2, 1.0, -0.2).normalize()));
        assert!(!e.may_reach(o, -Vec3::Y), "away from it");
        assert!(!e.may_reach(o, Vec3::X), "parallel to its plane, below it");
        assert!(
            !e.may_reach(o, Vec3::new(2.0, 1.0, 0.0).normalize()),
            "past its edge"
        );
        // Grazing its edge exactly still counts (the box is padded).
        assert!(e.may_reach(o, (Vec3::new(1.0, 2.0, 0.5) - o).normalize()));
        // A ray starting on the panel's plane, inside it, may reach it.
        assert!(e.may_reach(Vec3::new(0.5, 2.0, 0.5), Vec3::X));
    }

    #[test]
    fn no_area_light_means_nothing_to_reach() {
        let e = EmitterBounds::new(&[]);
        assert!(!e.may_reach(Vec3::ZERO, Vec3::Y));
    }
}
