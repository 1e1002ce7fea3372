//! Area lights: `light panel = area { mesh panel  transform { ... }  radiance 5  two_sided false
//! samples 4 }`.

use glam::{Vec2, Vec3};

use crate::shade::distribution::Distribution1D;

#[derive(Debug, Clone)]
pub struct AreaLight {
    pub radiance: Vec3,
    pub two_sided: bool,
    /// Shadow rays each time this light is picked (its `samples`; the scene's `light_samples`
    /// sets how many picks a shading point makes).
    pub samples: u32,
    /// World-space triangles.
    pub triangles: Vec<[Vec3; 3]>,
    /// Unit front-face normals `(p1 − p0) × (p2 − p0)`, world space.
    pub normals: Vec<Vec3>,
    pub total_area: f32,
    by_area: Distribution1D,
}

/// A point on an emitter and its front normal.
#[derive(Debug, Clone, Copy)]
pub struct LightPoint {
    pub position: Vec3,
    /// Per-axis bound on the rounding error of `position` (`γ(7)·Σ|bᵢ pᵢ|`, rounded up to
    /// 8 ulps), used to offset shadow-ray end points off the emitter.
    pub error: Vec3,
    pub normal: Vec3,
}

impl AreaLight {
    /// `None` when no triangle has an area (nothing can emit).
    pub fn new(
        radiance: Vec3,
        two_sided: bool,
        samples: u32,
        triangles: Vec<[Vec3; 3]>,
    ) -> Option<AreaLight> {
        let crosses: Vec<Vec3> = triangles
            .iter()
            .map(|[p0, p1, p2]| (*p1 - *p0).cross(*p2 - *p0))
            .collect();
        let areas: Vec<f32> = crosses.iter().map(|c| c.length() / 2.0).collect();
        let by_area = Distribution1D::new(&areas)?;
        let total_area = areas.iter().filter(|a| a.is_finite()).sum();
        Some(AreaLight {
            radiance,
            two_sided,
            samples: samples.max(1),
            normals: crosses.iter().map(|c| c.normalize_or_zero()).collect(),
            triangles,
            total_area,
            by_area,
        })
    }

    /// Heap memory of the world-space triangles, normals and area table.
    pub fn bytes(&self) -> usize {
        self.triangles.len() * std::mem::size_of::<[Vec3; 3]>()
            + self.normals.len() * std::mem::size_of::<Vec3>()
            + self.by_area.bytes()
    }

    /// A point uniform by area over the whole mesh; its density is `1 / total_area`.
    pub fn sample(&self, u: Vec2) -> LightPoint {
        let (i, _, u0) = self.pick(u.x);
        self.point_on(i, Vec2::new(u0, u.y))
    }

    /// A triangle chosen with probability proportional to its area: its index, that
    /// probability, and `u` rescaled to [0, 1) for reuse.
    pub fn pick(&self, u: f32) -> (usize, f32, f32) {
        self.by_area.sample(u)
    }

    /// The probability that [`AreaLight::pick`] chooses triangle `i`.
    pub fn triangle_pmf(&self, i: usize) -> f32 {
        self.by_area.pmf(i)
    }

    /// A point uniform by area on triangle `i`.
    pub fn point_on(&self, i: usize, u: Vec2) -> LightPoint {
        let s = u.x.sqrt();
        self.at_barycentrics(i, s * (1.0 - u.y), s * u.y)
    }

    /// The point `(1 − b1 − b2)·p0 + b1·p1 + b2·p2` of triangle `i`.
    pub fn at_barycentrics(&self, i: usize, b1: f32, b2: f32) -> LightPoint {
        let [p0, p1, p2] = self.triangles[i];
        let b0 = 1.0 - b1 - b2;
        let abs_sum = (b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs();
        LightPoint {
            position: b0 * p0 + b1 * p1 + b2 * p2,
            error: 4.0 * f32::EPSILON * abs_sum,
            normal: self.normals[i],
        }
    }

    /// Radiant flux (W per channel, averaged over channels) used to pick lights by power.
    pub fn power(&self) -> f32 {
        let sides = if self.two_sided { 2.0 } else { 1.0 };
        std::f32::consts::PI * sides * self.total_area * self.radiance.element_sum() / 3.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_samples_land_on_the_mesh_uniformly() {
        // Two triangles of areas 1 and 3 (a 1×1 and a 3×1 rectangle half).
        let tris = vec![
            [
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            [
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(16.0, 0.0, 0.0),
                Vec3::new(10.0, 1.0, 0.0),
            ],
        ];
        let light = AreaLight::new(Vec3::ONE, false, 1, tris).expect("has area");
        assert!((light.total_area - 4.0).abs() < 1e-6);
        let n = 64;
        let mut on_second = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let p = light.sample(u);
                assert_eq!(p.normal, Vec3::Z);
                assert!(p.position.z == 0.0 && p.position.y >= 0.0 && p.position.y <= 1.0);
                if p.position.x >= 10.0 {
                    on_second += 1;
                }
            }
        }
        assert_eq!(on_second, 3 * n * n / 4);
    }
}
