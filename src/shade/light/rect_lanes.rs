//! Shading layer: a rectangle light's samples ([`AreaLight::sample`] of a `quad` emitter, cornell's)
//! for [`LANES`] shading points side by side.
//!
//! `render::rect_lit` shades a run of camera samples at once; this is the run's light samples.
//! Each lane runs the scalar path's own functions (`spherical_rect`'s `FrameCoordinates`,
//! `Angles` and `SphericalRect::sample_at`, `shadow_end`'s target, glam's normalisation) in
//! loops over arrays, one lane per iteration, so that the compiler can run the lanes in vector
//! registers: the set-up's f64 square roots and divisions two (SSE2) or four (AVX2) at a time,
//! the sample's f32 chain four or eight. The same IEEE operations in the same order and no fused
//! multiply-add: each lane has the bits the scalar [`AreaLight::sample`] gives. The one call
//! per lane is libm's `sincosf` (its bits are libm's), in a loop of its own.
//!
//! A lane that leaves the common branch is marked [`LaneSample::Scalar`] for the scalar path,
//! which gives it its bits: a point in the light's plane, light-frame coordinates outside the
//! set-up's unscaled range, Ω > π or outside the solid-angle range (sampled by triangle then),
//! a shadow end too close to the plane (the point rebuilt on its triangle).

use glam::{Vec2, Vec3};

use super::area::AreaLight;
use super::spherical;
use super::spherical_rect::{Angles, FrameCoordinates, RectFrame, SphericalRect};

/// Shading points in a run (a power of two, so runs tile a pixel's 4, 16, 64… samples).
pub const LANES: usize = 8;

/// One `f32` per lane.
pub type Lanes = [f32; LANES];

/// One vector per lane, as three arrays of coordinates.
#[derive(Debug, Clone, Copy, Default)]
pub struct LaneVecs {
    /// The lanes' x coordinates.
    pub x: Lanes,
    /// The lanes' y coordinates.
    pub y: Lanes,
    /// The lanes' z coordinates.
    pub z: Lanes,
}

impl LaneVecs {
    /// Lane `i`'s vector.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Vec3 {
        Vec3::new(self.x[i], self.y[i], self.z[i])
    }

    /// Sets lane `i`'s vector.
    #[inline(always)]
    pub fn set(&mut self, i: usize, v: Vec3) {
        (self.x[i], self.y[i], self.z[i]) = (v.x, v.y, v.z);
    }
}

/// What [`AreaLight::sample`] gives a lane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LaneSample {
    /// Nothing: an inactive lane, a point behind the one-sided light, a direction that
    /// rounds to zero (`sample` returns `None`).
    #[default]
    Nothing,
    /// The lane's `wi`, `shadow_target` and `inv_pdf_solid_angle` are `sample`'s.
    Sampled,
    /// Off the common branch: ask [`AreaLight::sample`].
    Scalar,
}

/// A run's light samples (the fields of [`AreaSample`](super::AreaSample) that shading reads).
#[derive(Debug, Clone, Copy, Default)]
pub struct AreaLanes {
    /// What each lane holds.
    pub kind: [LaneSample; LANES],
    /// Unit directions towards the sampled points.
    pub wi: LaneVecs,
    /// Where the shadow rays end.
    pub shadow_target: LaneVecs,
    /// `1 / pdf_solid_angle`: the spherical rectangle's Ω.
    pub inv_pdf_solid_angle: Lanes,
}

/// [`SphericalRect`]s in lanes: the fields that vary from point to point (the frame's axes
/// and reciprocal sizes are the light's).
#[derive(Debug, Clone, Copy, Default)]
struct RectLanes {
    z: LaneVecs,
    z0: Lanes,
    x0: Lanes,
    x1: Lanes,
    y0: Lanes,
    y1: Lanes,
    b0: Lanes,
    b1: Lanes,
    one_minus_b0_sq: Lanes,
    cos_k: Lanes,
    sin_k: Lanes,
    solid_angle: Lanes,
}

impl RectLanes {
    #[inline(always)]
    fn set(&mut self, i: usize, r: &SphericalRect) {
        self.z.set(i, r.z);
        (self.z0[i], self.x0[i], self.x1[i], self.y0[i], self.y1[i]) =
            (r.z0, r.x0, r.x1, r.y0, r.y1);
        (self.b0[i], self.b1[i], self.one_minus_b0_sq[i]) = (r.b0, r.b1, r.one_minus_b0_sq);
        (self.cos_k[i], self.sin_k[i], self.solid_angle[i]) = (r.cos_k, r.sin_k, r.solid_angle);
    }

    #[inline(always)]
    fn get(&self, i: usize, frame: &RectFrame) -> SphericalRect {
        SphericalRect {
            x: frame.x,
            y: frame.y,
            z: self.z.get(i),
            z0: self.z0[i],
            x0: self.x0[i],
            x1: self.x1[i],
            y0: self.y0[i],
            y1: self.y1[i],
            inv_width: frame.inv_width,
            inv_height: frame.inv_height,
            b0: self.b0[i],
            b1: self.b1[i],
            one_minus_b0_sq: self.one_minus_b0_sq[i],
            cos_k: self.cos_k[i],
            sin_k: self.sin_k[i],
            solid_angle: self.solid_angle[i],
        }
    }
}

impl AreaLight {
    /// Whether [`AreaLight::sample_lanes`] samples this light in lanes: a rectangle.
    pub fn samples_in_lanes(&self) -> bool {
        self.rect_frame.is_some()
    }

    /// [`AreaLight::sample`] by solid angle (`LightSampling::SolidAngle`) from the points `p`
    /// of the lanes `active` marks, for `u`: see the module doc. Every lane is
    /// [`LaneSample::Scalar`] for a light that is not a rectangle.
    ///
    /// Each loop's body is branch-free (selects; `&` on flags, not `&&`) and reads nothing but
    /// arrays and values held outside it, which is what lets the compiler vectorise it.
    #[inline(always)]
    pub fn sample_lanes(
        &self,
        p: &LaneVecs,
        u: &[Vec2; LANES],
        active: &[bool; LANES],
    ) -> AreaLanes {
        self.sample_first_lanes::<LANES>(p, u, active)
    }

    /// [`AreaLight::sample_lanes`] for the first `N` lanes alone (`N <= LANES`; the others
    /// are left [`LaneSample::Nothing`]): a short run's loops as long as the run, not
    /// [`LANES`]. Each lane's operations are the same for any `N`, so the same bits.
    // A lane index reads several arrays in each loop: one `for i in 0..N` per loop is the
    // vectorisable shape, not zipped iterators.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    pub fn sample_first_lanes<const N: usize>(
        &self,
        p: &LaneVecs,
        u: &[Vec2; LANES],
        active: &[bool; LANES],
    ) -> AreaLanes {
        const { assert!(N <= LANES) };
        let mut out = AreaLanes::default();
        let (Some(frame), Some(&normal), Some(&[corner, _, _])) = (
            self.rect_frame,
            self.normals.first(),
            self.triangles.first(),
        ) else {
            for i in 0..N {
                if active[i] {
                    out.kind[i] = LaneSample::Scalar;
                }
            }
            return out;
        };
        let two_sided = self.two_sided;
        let range = spherical::MIN_SOLID_ANGLE..=spherical::MAX_SOLID_ANGLE;
        let mut rects = RectLanes::default();
        for i in 0..N {
            let at = p.get(i);
            let c = FrameCoordinates::of(at, &frame);
            let a = Angles::of(c.as_f64());
            let solid_angle = a.omega as f32;
            // `sample`'s tests: the light faces the point (`rect_front_faces`), then its
            // set-up's common branch and the range (`rect_in_range`).
            let lit = active[i] & (two_sided | (normal.dot(at - corner) > 0.0));
            let common = c.in_front()
                & c.unscaled()
                & (a.omega > 0.0)
                & (solid_angle > 0.0)
                & range.contains(&solid_angle);
            out.kind[i] = match (lit, common) {
                (false, _) => LaneSample::Nothing,
                (true, true) => LaneSample::Sampled,
                (true, false) => LaneSample::Scalar,
            };
            rects.set(i, &a.rect(&c, &frame, solid_angle));
        }
        let (mut sin_u, mut cos_u) = ([0.0; LANES], [0.0; LANES]);
        for i in 0..N {
            if out.kind[i] == LaneSample::Sampled {
                let rect = rects.get(i, &frame);
                (sin_u[i], cos_u[i]) = rect.column_angle(u[i].x).sin_cos();
            }
        }
        let shadow = self.rect_points.shadow;
        for i in 0..N {
            let rect = rects.get(i, &frame);
            let sample = rect.sample_at(u[i].y, sin_u[i], cos_u[i]);
            let wi = sample.offset.normalize_or_zero();
            let end = shadow.target(p.get(i), sample.offset, rect.z0);
            out.kind[i] = match out.kind[i] {
                LaneSample::Sampled if wi == Vec3::ZERO => LaneSample::Nothing,
                LaneSample::Sampled if end.is_none() => LaneSample::Scalar,
                kind => kind,
            };
            out.wi.set(i, wi);
            out.shadow_target.set(i, end.unwrap_or(Vec3::ZERO));
            out.inv_pdf_solid_angle[i] = rect.solid_angle;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LightSampling;

    /// A small deterministic generator for the test's configurations.
    fn uniform(state: &mut u64) -> f32 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Every lane is what the scalar `sample` gives it, bit for bit, or is marked for it:
    /// points all around a one-sided and a two-sided rectangle (in front, behind, in its
    /// plane, grazing, close, far), runs with inactive lanes.
    #[test]
    fn lanes_are_the_scalar_samples_bit_for_bit() {
        let (c, ex, ey) = (
            Vec3::new(343.0, 548.7, 227.0),
            Vec3::new(0.0, 0.0, 105.0),
            Vec3::new(-130.0, 0.0, 0.0),
        );
        let (a, b, q) = (c + ex, c + ey, c + ex + ey);
        let mut state = 7u64;
        let mut seen = [0usize; 3];
        for two_sided in [false, true] {
            let light = AreaLight::new(
                Vec3::new(17.0, 12.0, 4.0),
                two_sided,
                1,
                vec![[c, a, b], [b, a, q]],
            )
            .expect("has area");
            assert!(light.samples_in_lanes());
            for run in 0..4000 {
                let mut p = LaneVecs::default();
                let mut u = [Vec2::ZERO; LANES];
                let mut active = [true; LANES];
                for i in 0..LANES {
                    let r = uniform(&mut state);
                    let point = match run % 5 {
                        // Inside the box, below the light.
                        0 | 1 => {
                            Vec3::new(556.0, 548.8, 559.2)
                                * Vec3::new(uniform(&mut state), r, uniform(&mut state))
                        }
                        // Just below or in the light's plane, or above it.
                        2 => Vec3::new(
                            150.0 + 250.0 * r,
                            548.7 - [0.0, 1e-3, 1e-6, -1.0][i % 4],
                            100.0 + 350.0 * uniform(&mut state),
                        ),
                        // Far and grazing.
                        3 => Vec3::new(
                            1e4 * (r - 0.5),
                            548.0 + uniform(&mut state),
                            1e4 * uniform(&mut state),
                        ),
                        _ => Vec3::new(278.0, 548.7 - 1e3 * r * r * r, 280.0),
                    };
                    p.set(i, point);
                    u[i] = Vec2::new(uniform(&mut state), uniform(&mut state));
                    active[i] = run % 7 != 0 || i % 3 != 0;
                }
                let lanes = light.sample_lanes(&p, &u, &active);
                for i in 0..LANES {
                    let scalar = light.sample(p.get(i), u[i], LightSampling::SolidAngle);
                    match lanes.kind[i] {
                        LaneSample::Nothing => {
                            assert!(!active[i] || scalar.is_none(), "lane {i} of run {run}")
                        }
                        LaneSample::Scalar => assert!(active[i]),
                        LaneSample::Sampled => {
                            let s = scalar.expect("a sampled lane has a scalar sample");
                            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                            assert_eq!(bits(lanes.wi.get(i)), bits(s.wi), "run {run} lane {i}");
                            assert_eq!(bits(lanes.shadow_target.get(i)), bits(s.shadow_target));
                            assert_eq!(
                                lanes.inv_pdf_solid_angle[i].to_bits(),
                                s.inv_pdf_solid_angle.to_bits()
                            );
                        }
                    }
                    seen[lanes.kind[i] as usize] += 1;
                }
            }
        }
        // Every kind of lane was met, the common one most (the far and grazing points fall
        // under the solid-angle range: scalar).
        assert!(
            seen[1] > seen[0] && seen[1] > seen[2] && seen[2] > 0,
            "{seen:?}"
        );
    }
}
