//! Shading layer: where a shadow ray towards a point sampled on a rectangular light stops
//! (`area::AreaLight::sample` of a `quad` emitter, cornell's), so that the emitter never
//! occludes its own sample while anything between still does.
//!
//! The sample is `p + offset`, the offset computed in the rectangle's frame (`spherical_rect`),
//! whose component across the rectangle's plane is `z₀`. The ray stops short of it at
//! `p + (1 − δ)·offset`, which lies `δ·|z₀|` off the plane on `p`'s side. `δ` is set so that
//! distance is twice a bound `B` on how far the computed end point, or the accel's hit on the
//! emitter's own triangles, can stray across the plane: the mesh's own departure from the ideal
//! rectangle (what `area`'s rectangle test tolerates, measured once per light) plus 64 unit
//! roundoffs of the coordinates involved (the shading point's and the light's largest). One
//! division per sample, where rebuilding the point on its triangle from barycentrics with its
//! own error bound, then offsetting it (the triangles' way), cost a dependent chain of about
//! forty operations. Where `δ` would exceed [`MAX_SHORTENING`] (a point almost in the light's
//! plane), the caller falls back to that rebuilt point.

use glam::Vec3;

/// The largest fraction of the way to the sample a shadow ray gives up; beyond, the caller
/// rebuilds the point on its triangle instead.
pub const MAX_SHORTENING: f32 = 1.0 / 16.0;

/// Unit roundoffs, relative to the largest coordinate involved, in the bound on the end point's
/// error across the plane (the offset's few products and sums, the final sum, and the accel's
/// watertight test on the emitter's triangles: each a few unit roundoffs), with room to spare.
const ROUNDOFFS: f32 = 64.0 * f32::EPSILON * 0.5;

/// What a rectangular light keeps to place its shadow rays' ends (see the module doc).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RectShadowEnd {
    /// The largest distance of a vertex of the mesh's triangles from the ideal rectangle's plane.
    slack: f32,
    /// The largest absolute coordinate of those vertices.
    magnitude: f32,
}

impl RectShadowEnd {
    /// For the rectangle `corner + s·ex + t·ey` that `triangles` form.
    pub fn new(triangles: &[[Vec3; 3]], corner: Vec3, ex: Vec3, ey: Vec3) -> RectShadowEnd {
        let n = ex.cross(ey).normalize_or_zero();
        let vertices = triangles.iter().flatten();
        RectShadowEnd {
            slack: vertices
                .clone()
                .map(|v| n.dot(*v - corner).abs())
                .fold(0.0, f32::max),
            magnitude: vertices.map(|v| v.abs().max_element()).fold(0.0, f32::max),
        }
    }

    /// Where a shadow ray from near `p` towards the sample `p + offset` ends (the ray's segment
    /// ends there, `t_max = 1`), the offset's component across the plane being `z0`; `None` where
    /// that would give up more than [`MAX_SHORTENING`] of the way, or for a non-finite figure.
    #[inline]
    pub fn target(&self, p: Vec3, offset: Vec3, z0: f32) -> Option<Vec3> {
        let bound = self.slack + ROUNDOFFS * (p.abs().max_element() + self.magnitude);
        let shortening = 2.0 * bound / z0.abs();
        (shortening < MAX_SHORTENING).then(|| p + (1.0 - shortening) * offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The end lies on `p`'s side of the plane, at least the bound off it, and on the segment.
    #[test]
    fn the_end_stays_off_the_plane_on_the_points_side() {
        for scale in [1e-4f32, 1.0, 1e5] {
            let (c, ex, ey) = (
                Vec3::new(0.2, 1.0, 0.1) * scale,
                Vec3::new(0.5, 0.0, 0.0) * scale,
                Vec3::new(0.0, 0.0, 0.5) * scale,
            );
            let (a, b, q) = (c + ex, c + ey, c + ex + ey);
            let end = RectShadowEnd::new(&[[c, a, b], [b, a, q]], c, ex, ey);
            let p = Vec3::new(0.3, 0.0, -0.2) * scale;
            let offset = c + 0.3 * ex + 0.6 * ey - p;
            let target = end.target(p, offset, -scale).expect("far from the plane");
            let below = c.y - target.y;
            assert!(
                below > 0.0 && below < 1e-4 * scale,
                "scale {scale}: {below}"
            );
            let along = (target - p).normalize().dot(offset.normalize());
            assert!(along > 1.0 - 1e-6, "scale {scale}");
        }
    }

    /// A mesh that departs from its rectangle widens the bound; a point almost in the plane
    /// gets no end (the caller falls back).
    #[test]
    fn slack_widens_the_bound_and_a_point_in_the_plane_falls_back() {
        let (c, ex, ey) = (Vec3::ZERO, Vec3::X, Vec3::Z);
        let flat = RectShadowEnd::new(&[[c, ex, ey], [ey, ex, ex + ey]], c, ex, ey);
        let bent = [[c, ex, ey], [ey, ex, ex + ey + Vec3::Y * 1e-5]];
        let bent = RectShadowEnd::new(&bent, c, ex, ey);
        assert!(bent.slack >= 1e-5 && flat.slack == 0.0);
        let p = Vec3::new(0.5, -1.0, 0.5);
        let offset = Vec3::new(0.0, 1.0, 0.0);
        let (t_flat, t_bent) = (
            flat.target(p, offset, -1.0).expect("far"),
            bent.target(p, offset, -1.0).expect("far"),
        );
        assert!(t_bent.y < t_flat.y && t_bent.y <= -2e-5);
        let grazing = Vec3::new(0.5, -1e-6, 2.0);
        assert!(flat
            .target(grazing, Vec3::new(0.0, 1e-6, -1.5), -1e-6)
            .is_none());
    }
}
