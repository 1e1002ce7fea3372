//! Ray–triangle intersection.
//!
//! [`moller_trumbore`] is the reference formulation from the course material
//! (`s1 = d × e2`, `s2 = s × e1`, with `s = o − p0`). The accelerated paths may use a faster or
//! watertight variant; tests prove they agree with this one away from edges.

use glam::Vec3;

use super::Ray;

/// Where a ray meets a triangle: `p = (1 − u − v)·p0 + u·p1 + v·p2` at parameter `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// Möller–Trumbore: solves `o + t·d = p0 + u·e1 + v·e2` by Cramer's rule.
/// Returns a hit with `0 < t < ray.t_max`, `u ≥ 0`, `v ≥ 0`, `u + v ≤ 1`; both faces count.
#[inline]
pub fn moller_trumbore(ray: &Ray, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<TriangleHit> {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let s1 = ray.dir.cross(e2);
    let det = s1.dot(e1);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - p0;
    let u = s.dot(s1) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let s2 = s.cross(e1);
    let v = ray.dir.dot(s2) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(s2) * inv_det;
    if t > 0.0 && t < ray.t_max {
        Some(TriangleHit { t, u, v })
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_the_centroid_with_barycentrics_one_third() {
        let (p0, p1, p2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let c = (p0 + p1 + p2) / 3.0;
        let ray = Ray::new(c + Vec3::Z * 2.0, -Vec3::Z);
        let hit = moller_trumbore(&ray, p0, p1, p2).expect("ray through the centroid hits");
        assert!((hit.t - 2.0).abs() < 1e-6);
        assert!((hit.u - 1.0 / 3.0).abs() < 1e-6 && (hit.v - 1.0 / 3.0).abs() < 1e-6);
    }

    #[test]
    fn misses_outside_and_respects_t_max() {
        let ray = Ray::new(Vec3::new(2.0, 2.0, 1.0), -Vec3::Z);
        assert!(moller_trumbore(&ray, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
        let short = Ray::segment(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z, 0.5);
        assert!(moller_trumbore(&short, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
    }

    #[test]
    fn parallel_ray_misses() {
        let ray = Ray::new(Vec3::new(0.2, 0.2, 0.0), Vec3::X);
        assert!(moller_trumbore(&ray, Vec3::ZERO, Vec3::X, Vec3::Y).is_none());
    }
}
