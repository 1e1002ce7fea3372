//! Area lights: `light panel = area { mesh panel  transform { ... }  radiance 5  two_sided false
//! samples 4 }`, and the emitters of OBJ materials with `Ke`.
//!
//! The triangles are kept in world space with a CDF over their areas. A light that is one
//! rectangle (two triangles, as `quad` meshes) is sampled whole, uniformly over the spherical
//! rectangle it subtends (`pdf = 1 / Ω`, see `spherical_rect`), when solid-angle sampling is
//! chosen and Ω is in the safe range (`AreaLight::rect_in_range`, shared by `sample` and
//! `pdf`). Otherwise [`AreaLight::sample`] picks a triangle by area, then a direction towards it: uniform over the spherical triangle
//! it subtends (`pdf = pmf / Ω`, see `spherical`) when [`LightSampling::SolidAngle`] is chosen
//! and Ω is in the safe range, else a point uniform by area (`pdf = pmf · r² / (cos θ_l · a)`).
//! [`AreaLight::pdf`], beside it, is the solid-angle density of that same procedure at a
//! direction a BRDF ray found, which multiple importance sampling needs. The two share the rules
//! they must agree on, written once: which side emits and with what cosine
//! (`AreaLight::emitting_cosine`), and when a triangle is sampled by solid angle rather than
//! by area (`solid_angle_in_range`).
//!
//! Each sample also names where its shadow ray stops (`AreaSample::shadow_target`): a
//! triangle's point is rebuilt from barycentrics with its error bound and offset off the
//! emitter; a rectangle's is cut short of the point by a per-light bound instead
//! (`shadow_end`), which needs no rebuilt point.

use glam::{Vec2, Vec3};

use super::shadow_end::RectShadowEnd;
use super::spherical;
use super::spherical_rect::{RectFrame, SphericalRect};
use crate::geom::triangle::moller_trumbore;
use crate::geom::Ray;
use crate::scene::LightSampling;
use crate::shade::distribution::Distribution1D;
use crate::shade::surface::offset_origin;

/// An emitting triangle mesh in world space, with the table that samples its triangles by area.
#[derive(Debug, Clone)]
pub struct AreaLight {
    /// Emitted radiance (W/(sr·m²) per channel), the same everywhere on the emitting side(s).
    pub radiance: Vec3,
    /// Whether the back (against the winding's normal) emits too.
    pub two_sided: bool,
    /// Shadow rays each time this light is picked (its `samples`; the scene's `light_samples`
    /// sets how many picks a shading point makes).
    pub samples: u32,
    /// World-space triangles.
    pub triangles: Vec<[Vec3; 3]>,
    /// Unit front-face normals `(p1 − p0) × (p2 − p0)`, world space.
    pub normals: Vec<Vec3>,
    /// Sum of the triangles' areas.
    pub total_area: f32,
    by_area: Distribution1D,
    /// The frame of the rectangle the mesh is, when it is one (two triangles): it is then
    /// sampled whole as a spherical rectangle (see `spherical_rect`).
    pub(super) rect_frame: Option<RectFrame>,
    /// For a rectangle: how a sampled point is placed (boxed, so that `Light`'s variants stay
    /// close in size).
    pub(super) rect_points: Box<RectPoints>,
}

/// How a rectangle light places a point it sampled (see `AreaLight::sample_rect`).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct RectPoints {
    /// Per triangle, the affine map from the rectangle's parameters (s, t) to the triangle's
    /// barycentrics (b₁, b₂), so a sampled point is rebuilt on its triangle without a
    /// ray–triangle test (where the shadow ray's end needs it).
    barycentrics: [RectToBarycentric; 2],
    /// Where its shadow rays end, without rebuilding the point.
    pub(super) shadow: RectShadowEnd,
}

/// `(b₁, b₂) = m · ((s, t) − origin)`: a triangle of the rectangle in its (s, t) parameters.
#[derive(Debug, Clone, Copy, Default)]
struct RectToBarycentric {
    origin: Vec2,
    m: glam::Mat2,
}

impl RectToBarycentric {
    /// The map for a triangle whose vertices sit at rectangle parameters `st[0..3]`.
    fn new(st: [Vec2; 3]) -> RectToBarycentric {
        let m = glam::Mat2::from_cols(st[1] - st[0], st[2] - st[0]);
        RectToBarycentric {
            origin: st[0],
            m: if m.determinant() != 0.0 {
                m.inverse()
            } else {
                glam::Mat2::ZERO
            },
        }
    }

    fn barycentrics(&self, st: Vec2) -> (f32, f32) {
        let b = (self.m * (st - self.origin)).clamp(Vec2::ZERO, Vec2::ONE);
        // Keep b₀ = 1 − b₁ − b₂ non-negative where the point rounds onto the diagonal.
        let excess = (b.x + b.y - 1.0).max(0.0) * 0.5;
        (b.x - excess, b.y - excess)
    }
}

/// The rectangle parameters (s, t) of each vertex of the two triangles: the corner is (0, 0),
/// `corner + ex` is (1, 0), `corner + ey` is (0, 1), the opposite vertex (1, 1).
fn rect_barycentric_maps(
    triangles: &[[Vec3; 3]],
    rect: Option<(Vec3, Vec3, Vec3)>,
) -> [RectToBarycentric; 2] {
    let (Some((c, ex, ey)), [t0, t1]) = (rect, triangles) else {
        return [RectToBarycentric::default(); 2];
    };
    let (inv_x, inv_y) = (1.0 / ex.length_squared(), 1.0 / ey.length_squared());
    let st = |v: Vec3| {
        let q = v - c;
        Vec2::new((q.dot(ex) * inv_x).round(), (q.dot(ey) * inv_y).round())
    };
    [
        RectToBarycentric::new(t0.map(st)),
        RectToBarycentric::new(t1.map(st)),
    ]
}

/// The rectangle two triangles form, as (corner, edge, edge): they share a diagonal, face the
/// same way, and the corners opposite it make a right-angled parallelogram.
fn rectangle(triangles: &[[Vec3; 3]], normals: &[Vec3]) -> Option<(Vec3, Vec3, Vec3)> {
    let ([t0, t1], [n0, n1]) = (triangles, normals) else {
        return None;
    };
    let q = *t1.iter().find(|v| !t0.contains(v))?;
    let c = *t0.iter().find(|v| !t1.contains(v))?;
    let mut shared = t0.iter().filter(|v| t1.contains(v));
    let (a, b) = (*shared.next()?, *shared.next()?);
    let (ex, ey) = (a - c, b - c);
    let tolerance = 1e-5 * ex.length() * ey.length();
    let parallelogram = (a + b - c - q).length() <= 1e-5 * (ex.length() + ey.length());
    (n0.dot(*n1) > 0.9999 && parallelogram && ex.dot(ey).abs() <= tolerance).then_some((c, ex, ey))
}

/// A point on an emitter and its front normal.
#[derive(Debug, Clone, Copy)]
pub struct LightPoint {
    /// World-space position.
    pub position: Vec3,
    /// Per-axis bound on the rounding error of `position` (`γ(7)·Σ|bᵢ pᵢ|`, rounded up to
    /// 8 ulps), used to offset shadow-ray end points off the emitter.
    pub error: Vec3,
    /// Unit front-face normal of its triangle.
    pub normal: Vec3,
}

impl LightPoint {
    /// Where a shadow ray arriving in direction `wi` (unit, towards the light) stops: the point
    /// offset off the emitter's surface by its error bound, on the side the ray comes from.
    fn shadow_target(&self, wi: Vec3) -> Vec3 {
        offset_origin(self.position, self.error, self.normal, -wi)
    }
}

/// A direction towards an area light, sampled from a shading point by [`AreaLight::sample`].
#[derive(Debug, Clone, Copy)]
pub struct AreaSample {
    /// Unit direction from the shading point towards `point`.
    pub wi: Vec3,
    /// Where the direction meets the emitter.
    pub point: Vec3,
    /// Where the shadow ray towards `point` ends (its segment's end, `t_max = 1`): off the
    /// emitter on the shading point's side, so the emitter never occludes its own sample.
    pub shadow_target: Vec3,
    /// The triangle of `point` (what [`AreaLight::pdf`] takes).
    pub triangle: usize,
    /// Radiance emitted towards the shading point.
    pub radiance: Vec3,
    /// `1 / pdf_solid_angle` of the sampling, triangle pick included (`Ω / pmf` or
    /// `cos θ_l · a / (r² · pmf)`), as the estimator multiplies by it: the reciprocal of
    /// [`AreaLight::pdf`] would round differently.
    pub inv_pdf_solid_angle: f32,
}

/// The solid angle `Ω` that `tri` subtends from `p` if, under `mode`, directions towards it are
/// sampled uniformly by solid angle; `None` if they are sampled by area (area sampling chosen,
/// or `Ω` outside [`spherical::MIN_SOLID_ANGLE`, `spherical::MAX_SOLID_ANGLE`], where the
/// spherical construction is unreliable).
fn solid_angle_in_range(p: Vec3, tri: &[Vec3; 3], mode: LightSampling) -> Option<f32> {
    if mode == LightSampling::SolidAngle {
        let omega = spherical::solid_angle(p, tri);
        if (spherical::MIN_SOLID_ANGLE..=spherical::MAX_SOLID_ANGLE).contains(&omega) {
            return Some(omega);
        }
    }
    None
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
        let normals: Vec<Vec3> = crosses.iter().map(|c| c.normalize_or_zero()).collect();
        let rect = rectangle(&triangles, &normals);
        Some(AreaLight {
            radiance,
            two_sided,
            samples: samples.max(1),
            rect_frame: rect.and_then(|(c, ex, ey)| RectFrame::new(c, ex, ey)),
            rect_points: Box::new(RectPoints {
                barycentrics: rect_barycentric_maps(&triangles, rect),
                shadow: rect.map_or(RectShadowEnd::default(), |(c, ex, ey)| {
                    RectShadowEnd::new(&triangles, c, ex, ey)
                }),
            }),
            normals,
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

    /// A direction from the shading point `p` towards this light for `u` in [0, 1)²: a triangle
    /// by area (with `u.x`, then rescaled), then a direction by solid angle or a point by area
    /// (see the module doc). `None` when it sends nothing to `p` (`p` behind a one-sided
    /// emitter, a degenerate configuration): a zero sample, no shadow ray.
    pub fn sample(&self, p: Vec3, u: Vec2, mode: LightSampling) -> Option<AreaSample> {
        // Behind a one-sided rectangle (cornell's ceiling, above its light): nothing, and no
        // set-up to pay for first.
        if self.rect_frame.is_some() && !self.rect_front_faces(p) {
            return None;
        }
        if let Some(rect) = self.rect_in_range(p, mode) {
            return self.sample_rect(p, &rect, u);
        }
        let (t, pmf_triangle, u0) = self.pick(u.x);
        let u = Vec2::new(u0, u.y);
        let tri = &self.triangles[t];
        // The back of a one-sided emitter sends nothing: no ray needed.
        if !self.two_sided && self.normals[t].dot(p - tri[0]) <= 0.0 {
            return None;
        }
        if solid_angle_in_range(p, tri, mode).is_some() {
            let (wi, omega) = spherical::sample(p, tri, u)?;
            // The point where the direction meets the triangle, rebuilt from barycentrics so
            // its error bound is the same as for area samples. A direction that rounds to just
            // outside an edge is dropped (a bias of the order of f32 rounding).
            let b = moller_trumbore(&Ray::new(p, wi), tri[0], tri[1], tri[2])?;
            let point = self.at_barycentrics(t, b.u, b.v);
            return Some(AreaSample {
                wi,
                point: point.position,
                shadow_target: point.shadow_target(wi),
                triangle: t,
                radiance: self.radiance,
                inv_pdf_solid_angle: omega / pmf_triangle,
            });
        }
        let point = self.point_on(t, u);
        let to_light = point.position - p;
        let dist2 = to_light.length_squared();
        if dist2 == 0.0 || !dist2.is_finite() {
            return None;
        }
        let wi = to_light / dist2.sqrt();
        let cos_light = self.emitting_cosine(t, wi)?;
        let area = pmf_triangle * self.total_area;
        Some(AreaSample {
            wi,
            point: point.position,
            shadow_target: point.shadow_target(wi),
            triangle: t,
            radiance: self.radiance,
            inv_pdf_solid_angle: cos_light * area / (dist2 * pmf_triangle),
        })
    }

    /// The solid-angle density with which [`AreaLight::sample`] produces direction `wi` (unit)
    /// from `p`, reaching `p_light` on triangle `t` (triangle pick included). `None` when that
    /// side of the triangle emits nothing (or `t` is not a triangle of this light): such a
    /// direction carries no light at all.
    pub fn pdf(
        &self,
        p: Vec3,
        wi: Vec3,
        t: usize,
        p_light: Vec3,
        mode: LightSampling,
    ) -> Option<f32> {
        let tri = self.triangles.get(t)?;
        let cos_light = self.emitting_cosine(t, wi)?;
        if let Some(rect) = self.rect_in_range(p, mode) {
            return Some(1.0 / rect.solid_angle());
        }
        let pmf_triangle = self.triangle_pmf(t);
        if let Some(omega) = solid_angle_in_range(p, tri, mode) {
            return Some(pmf_triangle / omega);
        }
        let dist2 = (p_light - p).length_squared();
        Some(dist2 / (cos_light * self.total_area))
    }

    /// The spherical rectangle this light subtends from `p` if, under `mode`, it is sampled
    /// whole by solid angle (a rectangle, solid angle sampling, Ω in the range where f32 is
    /// reliable). The one rule [`AreaLight::sample`] and [`AreaLight::pdf`] share.
    fn rect_in_range(&self, p: Vec3, mode: LightSampling) -> Option<SphericalRect> {
        let frame = self
            .rect_frame
            .filter(|_| mode == LightSampling::SolidAngle)?;
        let rect = SphericalRect::seen_from(p, &frame)?;
        let range = spherical::MIN_SOLID_ANGLE..=spherical::MAX_SOLID_ANGLE;
        range.contains(&rect.solid_angle()).then_some(rect)
    }

    /// A direction uniform over the spherical rectangle `rect` (`pdf = 1 / Ω`), from a `p` the
    /// light faces (the caller, [`AreaLight::sample`], checked). `None` for a direction that
    /// rounds off both triangles.
    fn sample_rect(&self, p: Vec3, rect: &SphericalRect, u: Vec2) -> Option<AreaSample> {
        let sample = rect.sample(u);
        let wi = sample.offset.normalize_or_zero();
        if wi == Vec3::ZERO {
            return None;
        }
        // The corner's triangle holds s + t ≤ 1 (see `rectangle`), the other one the rest.
        let t = usize::from(sample.s + sample.t > 1.0);
        let end = self.rect_shadow_end(p, sample.offset, rect.plane_offset());
        let (point, shadow_target) = match end {
            Some(end) => (p + sample.offset, end),
            // Almost in the light's plane: the point rebuilt on its triangle and offset off it.
            None => {
                let st = Vec2::new(sample.s, sample.t);
                let (b1, b2) = self.rect_points.barycentrics[t].barycentrics(st);
                let point = self.at_barycentrics(t, b1, b2);
                (point.position, point.shadow_target(wi))
            }
        };
        Some(AreaSample {
            wi,
            point,
            shadow_target,
            triangle: t,
            radiance: self.radiance,
            inv_pdf_solid_angle: rect.solid_angle(),
        })
    }

    /// Where the shadow ray from `p` towards the rectangle's sample `p + offset` ends
    /// (`shadow_end`; `z0` the offset's component across the plane), if not too close to it.
    #[inline(always)]
    pub(super) fn rect_shadow_end(&self, p: Vec3, offset: Vec3, z0: f32) -> Option<Vec3> {
        self.rect_points.shadow.target(p, offset, z0)
    }

    /// Whether a rectangle light sends anything to `p`: it is two-sided, or `p` is in front.
    fn rect_front_faces(&self, p: Vec3) -> bool {
        match (self.normals.first(), self.triangles.first()) {
            (Some(n), Some(t)) => self.two_sided || n.dot(p - t[0]) > 0.0,
            _ => false,
        }
    }

    /// The radiance a point of this light with unit front normal `ng` emits in direction `w`:
    /// zero from the back of a one-sided emitter.
    pub fn radiance_towards(&self, ng: Vec3, w: Vec3) -> Vec3 {
        if self.two_sided || ng.dot(w) > 0.0 {
            self.radiance
        } else {
            Vec3::ZERO
        }
    }

    /// `cos θ_l` between triangle `t`'s emitting side and the light travelling against `wi` (a
    /// unit direction towards the light): the absolute cosine for a two-sided emitter. `None`
    /// when the light would leave through a side that does not emit.
    fn emitting_cosine(&self, t: usize, wi: Vec3) -> Option<f32> {
        let cos_light = -self.normals[t].dot(wi);
        let cos_light = if self.two_sided {
            cos_light.abs()
        } else {
            cos_light
        };
        if cos_light <= 0.0 {
            return None;
        }
        Some(cos_light)
    }

    /// A triangle chosen with probability proportional to its area: its index, that
    /// probability, and `u` rescaled to [0, 1) for reuse.
    fn pick(&self, u: f32) -> (usize, f32, f32) {
        self.by_area.sample(u)
    }

    /// The probability that [`AreaLight::pick`] chooses triangle `i`.
    fn triangle_pmf(&self, i: usize) -> f32 {
        self.by_area.pmf(i)
    }

    /// A point uniform by area on triangle `i`.
    fn point_on(&self, i: usize, u: Vec2) -> LightPoint {
        let s = u.x.sqrt();
        self.at_barycentrics(i, s * (1.0 - u.y), s * u.y)
    }

    /// The point `(1 − b1 − b2)·p0 + b1·p1 + b2·p2` of triangle `i`.
    fn at_barycentrics(&self, i: usize, b1: f32, b2: f32) -> LightPoint {
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
                let (t, _, u0) = light.pick(u.x);
                let p = light.point_on(t, Vec2::new(u0, u.y));
                assert_eq!(p.normal, Vec3::Z);
                assert!(p.position.z == 0.0 && p.position.y >= 0.0 && p.position.y <= 1.0);
                if p.position.x >= 10.0 {
                    on_second += 1;
                }
            }
        }
        assert_eq!(on_second, 3 * n * n / 4);
    }

    /// Every sample's `1 / inv_pdf_solid_angle` is what `pdf` says for its direction, in both
    /// sampling modes and for a two-sided light seen from behind.
    #[test]
    fn pdf_is_the_density_of_sample() {
        let tri = [
            Vec3::new(-0.5, 1.0, -0.3),
            Vec3::new(0.8, 1.2, 0.1),
            Vec3::new(0.1, 0.9, 0.9),
        ];
        let big = [tri[0] * 3.0, tri[1] * 3.0, tri[2] * 3.0].map(|v| v + Vec3::Y);
        let light = AreaLight::new(Vec3::ONE, true, 1, vec![tri, big]).expect("has area");
        for mode in [LightSampling::SolidAngle, LightSampling::Area] {
            for p in [Vec3::new(0.1, 0.0, 0.2), Vec3::new(0.0, 9.0, 0.0)] {
                for k in 0..64 {
                    let u = Vec2::new((k as f32 + 0.5) / 64.0, (k * 37 % 64) as f32 / 64.0);
                    let Some(s) = light.sample(p, u, mode) else {
                        continue;
                    };
                    let pdf = light
                        .pdf(p, s.wi, s.triangle, s.point, mode)
                        .expect("a sampled direction emits");
                    let rel = (pdf * s.inv_pdf_solid_angle - 1.0).abs();
                    assert!(
                        rel < 1e-3,
                        "{mode:?} from {p}: {pdf} vs 1/{}",
                        s.inv_pdf_solid_angle
                    );
                }
            }
        }
    }

    /// A two-triangle rectangle is recognised and sampled whole: `pdf` is `1 / Ω` of the
    /// rectangle and agrees with every sample, whichever triangle it lands on.
    #[test]
    fn rectangle_is_sampled_whole_and_pdf_agrees() {
        let (c, ex, ey) = (
            Vec3::new(-0.3, 1.0, -0.15),
            Vec3::new(0.6, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.3),
        );
        let (a, b, q) = (c + ex, c + ey, c + ex + ey);
        let light =
            AreaLight::new(Vec3::ONE, true, 1, vec![[c, a, b], [b, a, q]]).expect("has area");
        assert!(light.rect_frame.is_some());
        let p = Vec3::new(0.2, 0.0, 0.1);
        let omega = SphericalRect::new(p, c, ex, ey)
            .expect("visible")
            .solid_angle();
        let mut on = [0, 0];
        for k in 0..64 {
            let u = Vec2::new((k as f32 + 0.5) / 64.0, (k * 37 % 64) as f32 / 64.0);
            let s = light
                .sample(p, u, LightSampling::SolidAngle)
                .expect("a direction");
            on[s.triangle] += 1;
            assert_eq!(s.inv_pdf_solid_angle, omega);
            // The point is rebuilt on the triangle the direction meets (what a ray–triangle
            // test would find), and lies along `wi`.
            let tri = light.triangles[s.triangle];
            let hit = moller_trumbore(&Ray::new(p, s.wi), tri[0], tri[1], tri[2]);
            let expected = hit.map(|h| light.at_barycentrics(s.triangle, h.u, h.v).position);
            let expected = expected.expect("the direction meets the point's triangle");
            assert!((expected - s.point).length() < 1e-5, "{k}");
            let along = (s.point - p).normalize();
            assert!(along.dot(s.wi) > 1.0 - 1e-6, "{k}");
            let pdf = light
                .pdf(p, s.wi, s.triangle, s.point, LightSampling::SolidAngle)
                .expect("emits");
            assert!((pdf * s.inv_pdf_solid_angle - 1.0).abs() < 1e-6);
        }
        assert!(on[0] > 0 && on[1] > 0, "{on:?}");
        // One-sided (front towards −y, the winding's normal): nothing reaches a point above it.
        let one_sided =
            AreaLight::new(Vec3::ONE, false, 1, vec![[c, a, b], [b, a, q]]).expect("has area");
        let above = Vec3::new(0.2, 2.0, 0.1);
        let u = Vec2::splat(0.5);
        assert!(one_sided
            .sample(above, u, LightSampling::SolidAngle)
            .is_none());
        assert!(one_sided.sample(p, u, LightSampling::SolidAngle).is_some());
        // Not a rectangle: a parallelogram with a 60° corner.
        let skew = vec![
            [c, a, c + ey + 0.2 * ex],
            [c + ey + 0.2 * ex, a, q + 0.2 * ex],
        ];
        assert!(AreaLight::new(Vec3::ONE, true, 1, skew)
            .expect("has area")
            .rect_frame
            .is_none());
    }
}
