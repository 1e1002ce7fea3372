//! Stage 4: the per-sample path of a scene lit by one rectangle light, a run of samples at a
//! time.
//!
//! [`integrator::radiance_scaled`](super::integrator::radiance_scaled) serves every scene:
//! textures, normal maps, specular lobes, the environment, several lights, multiple importance
//! sampling. A scene with none of them (constant Lambertian materials, one area light that is a
//! rectangle sampled by solid angle once per camera sample, no environment, a fixed sample
//! count: cornell) needs per camera sample a camera ray, its hit and, at a shading point, one
//! light sample and one shadow ray (MIS gives way to light sampling alone on such surfaces:
//! `mis::strategy_at`). [`RectLit::of`] recognises such a scene once per render, and its
//! pixels take this path, which carries none of the other branches' state. The same
//! floating-point operations in the same order as the general path, so the same bits (tests
//! compare whole images), a run of [`LANES`] samples at a time:
//!
//! 1. each sample's camera ray is traced and its hit rebuilt: an emitter's radiance, black for a
//!    miss, or a shading point;
//! 2. the run's light samples and shadow rays computed side by side
//!    (`shade::light::rect_lanes`, then the rays' origins), in a function compiled for AVX2
//!    where the CPU has it (entered with `geom::avx2`'s token);
//! 3. the shadow rays traced, and the samples' radiance added to the pixel in order.
//!
//! BVH queries run on the tile's own traversal stacks ([`Scratch`]).

use std::f32::consts::FRAC_1_PI;

use glam::{Vec2, Vec3};

use super::camera::PinholeCamera;
use super::estimate::Accumulator;
use super::integrator::{divided, RayCounts, STREAM_LIGHTS};
use super::rng::{self, PixelBatch};
use crate::bvh::{Accel, Scratch};
use crate::geom::avx2::{Avx2, Kernel};
use crate::geom::Ray;
use crate::ir::{ColorInput, ScalarInput};
use crate::scene::{DirectStrategy, LightSampling, Scene, Surface};
use crate::shade::light::rect_lanes::{LaneSample, LaneVecs, Lanes, LANES};
use crate::shade::surface::{leaving_origin, seen_hit, SeenHit, SurfaceHit};
use crate::shade::{AreaLight, Light, Picked};

/// A scene this path renders (see the module doc), with what its samples read.
pub(super) struct RectLit<'a> {
    scene: &'a Scene,
    accel: &'a Accel,
    light: &'a AreaLight,
    /// The light's pick probability (the power table's one entry).
    pmf: f32,
    /// By material index.
    materials: Vec<Lambert>,
    avx2: Option<Avx2>,
}

/// A constant material without a specular lobe or normal map.
#[derive(Debug, Clone, Copy, Default)]
struct Lambert {
    /// `diffuse / π`: what `Phong::eval` returns without a specular lobe.
    f: Vec3,
    /// Added at every hit.
    ambient: Vec3,
}

/// A run's shading points, one per lane.
#[derive(Debug, Clone, Copy, Default)]
struct Run {
    /// Lanes with a shading point (the others are done: `value`).
    shaded: [bool; LANES],
    /// The radiance of a lane without a shading point (an emitter's, or black).
    value: [Vec3; LANES],
    material: [Lambert; LANES],
    /// The light's sample point for each lane's sample.
    u: [Vec2; LANES],
    p: LaneVecs,
    p_error: LaneVecs,
    /// The face normal as rebuilt (`SurfaceHit::ng`).
    face: LaneVecs,
    /// The geometric and shading normals on the viewer's side.
    ng: LaneVecs,
    ns: LaneVecs,
    /// The shadow-terminator offsets, front and back (`SurfaceHit::bulge`).
    bulge: [LaneVecs; 2],
}

/// A run's shadow rays.
#[derive(Debug, Clone, Copy, Default)]
struct Shadows {
    kind: [LaneSample; LANES],
    /// Whether the light sample is above both horizons, so a ray is traced.
    traced: [bool; LANES],
    /// The shading cosine.
    cos: Lanes,
    inv_pdf_solid_angle: Lanes,
    origin: LaneVecs,
    /// To the ray's end (`t_max = 1`).
    to_end: LaneVecs,
}

impl Run {
    /// Lane `i`'s shadow ray towards a light sample in direction `wi` ending at `target`:
    /// `Integrator::unoccluded`'s test and ray, in the same operations.
    #[inline(always)]
    fn shadow_ray(&self, i: usize, wi: Vec3, target: Vec3) -> (bool, f32, Vec3, Vec3) {
        let (ng, ns) = (self.ng.get(i), self.ns.get(i));
        let cos = ns.dot(wi);
        let traced = !(wi.dot(ng) <= 0.0 || cos <= 0.0 || !wi.is_finite());
        let bulge = [self.bulge[0].get(i), self.bulge[1].get(i)];
        let origin = leaving_origin(
            self.p.get(i),
            self.p_error.get(i),
            self.face.get(i),
            bulge,
            ng,
            wi,
        );
        (traced, cos, origin, target - origin)
    }

    /// Lane `i` becomes shading point `hit` seen along unit direction `dir`, of `material`.
    #[inline(always)]
    fn set_shaded(&mut self, i: usize, hit: &SurfaceHit, dir: Vec3, material: Lambert) {
        let wo = -dir;
        let ng = if hit.ng.dot(wo) < 0.0 {
            -hit.ng
        } else {
            hit.ng
        };
        let ns = if hit.ns.dot(ng) < 0.0 {
            -hit.ns
        } else {
            hit.ns
        };
        self.shaded[i] = true;
        self.material[i] = material;
        self.p.set(i, hit.p);
        self.p_error.set(i, hit.p_error);
        self.face.set(i, hit.ng);
        self.ng.set(i, ng);
        self.ns.set(i, ns);
        self.bulge[0].set(i, hit.bulge[0]);
        self.bulge[1].set(i, hit.bulge[1]);
    }
}

impl<'a> RectLit<'a> {
    /// This path for `scene`, if the scene is one it renders (see the module doc).
    pub(super) fn of(scene: &'a Scene) -> Option<RectLit<'a>> {
        let settings = &scene.settings;
        let fixed = settings.noise.is_none() && settings.light_samples.max(1) == 1;
        let light_sampled = scene.light_sampling == LightSampling::SolidAngle
            && scene.strategy != DirectStrategy::BrdfOnly
            && scene.lights.environment.is_none();
        if !(fixed && light_sampled) {
            return None;
        }
        let (Picked::Light(0, Light::Area(light)), pmf) = scene.lights.single()? else {
            return None;
        };
        if light.samples != 1 || !light.samples_in_lanes() {
            return None;
        }
        let materials = scene
            .materials
            .iter()
            .map(
                |m| match (m.diffuse, m.specular, m.shininess, &m.normal_map) {
                    (
                        ColorInput::Constant(d),
                        ColorInput::Constant(s),
                        ScalarInput::Constant(_),
                        None,
                    ) if s == Vec3::ZERO => Some(Lambert {
                        f: d * FRAC_1_PI,
                        ambient: m.ambient,
                    }),
                    _ => None,
                },
            )
            .collect::<Option<Vec<_>>>()?;
        Some(RectLit {
            scene,
            accel: scene.accel.as_ref()?,
            light,
            pmf,
            materials,
            avx2: Avx2::detect(),
        })
    }

    /// The pixel (`x`, `y`)'s samples at `offsets` (each shifted by `shift`, wrapped), with
    /// the batch's samplers, added to `acc` in order: what `Job::batch` computes.
    #[allow(clippy::too_many_arguments)] // reason: the pixel, its pattern and the sinks
    pub(super) fn pixel(
        &self,
        camera: &PinholeCamera,
        (x, y): (u32, u32),
        (offsets, shift): (&[Vec2], Vec2),
        samplers: &PixelBatch,
        acc: &mut Accumulator,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        let count = offsets.len() as u32;
        let pixel = Vec2::new(x as f32, y as f32);
        for (first, run) in (0..).step_by(LANES).zip(offsets.chunks(LANES)) {
            let mut lanes = Run::default();
            samplers.stratified_run(STREAM_LIGHTS, first, count, &mut lanes.u[..run.len()]);
            for (i, offset) in run.iter().enumerate() {
                let o = *offset + shift;
                let o = Vec2::new(rng::wrap_unit(o.x), rng::wrap_unit(o.y));
                self.camera_sample(&camera.ray(pixel + o), i, &mut lanes, counts, scratch);
            }
            let shadows = match self.avx2 {
                Some(avx2) => avx2.run(ShadowKernel {
                    lit: self,
                    lanes: &lanes,
                }),
                None => self.shadows(&lanes),
            };
            for i in 0..run.len() {
                let l = self.radiance(i, &lanes, &shadows, counts, scratch);
                // As `Job::batch`: a non-finite sample is counted, not added.
                if l.is_finite() {
                    acc.add(l);
                } else {
                    counts.nonfinite += 1;
                }
            }
        }
    }

    /// Traces camera ray `ray` (a unit direction) into lane `i`: a shading point, or the
    /// radiance it sees (`integrator::radiance_scaled`'s first half).
    #[inline(always)]
    fn camera_sample(
        &self,
        ray: &Ray,
        i: usize,
        lanes: &mut Run,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        counts.camera += 1;
        let seen = self
            .accel
            .closest_hit_with(ray, scratch)
            .and_then(|h| seen_hit(self.scene, &h));
        lanes.value[i] = match seen {
            Some(SeenHit::Emitter { light, ng }) => {
                match self.scene.lights.lights.get(light as usize) {
                    Some(Light::Area(a)) => a.radiance_towards(ng, -ray.dir.normalize()),
                    _ => Vec3::ZERO,
                }
            }
            Some(SeenHit::Surface(hit)) => {
                if let Surface::Material(m) = hit.surface {
                    if let Some(&material) = self.materials.get(m as usize) {
                        lanes.set_shaded(i, &hit, ray.dir.normalize(), material);
                    }
                }
                Vec3::ZERO
            }
            None => Vec3::ZERO,
        };
    }

    /// The run's light samples and shadow rays, lane by lane (see the module doc).
    #[inline(always)]
    fn shadows(&self, lanes: &Run) -> Shadows {
        let samples = self.light.sample_lanes(&lanes.p, &lanes.u, &lanes.shaded);
        let mut out = Shadows {
            kind: samples.kind,
            inv_pdf_solid_angle: samples.inv_pdf_solid_angle,
            ..Shadows::default()
        };
        for i in 0..LANES {
            let (traced, cos, origin, to_end) =
                lanes.shadow_ray(i, samples.wi.get(i), samples.shadow_target.get(i));
            out.traced[i] = traced;
            out.cos[i] = cos;
            out.origin.set(i, origin);
            out.to_end.set(i, to_end);
        }
        out
    }

    /// Lane `i`'s radiance: its shadow ray traced, then `shade`'s sum.
    #[inline(always)]
    fn radiance(
        &self,
        i: usize,
        lanes: &Run,
        shadows: &Shadows,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) -> Vec3 {
        if !lanes.shaded[i] {
            return lanes.value[i];
        }
        let seen = match shadows.kind[i] {
            LaneSample::Nothing => None,
            LaneSample::Sampled => {
                let ray = (
                    shadows.traced[i],
                    shadows.cos[i],
                    shadows.origin.get(i),
                    shadows.to_end.get(i),
                );
                self.unoccluded(ray, counts, scratch)
                    .map(|cos| (cos, shadows.inv_pdf_solid_angle[i]))
            }
            LaneSample::Scalar => self
                .light
                .sample(lanes.p.get(i), lanes.u[i], LightSampling::SolidAngle)
                .and_then(|s| {
                    let ray = lanes.shadow_ray(i, s.wi, s.shadow_target);
                    self.unoccluded(ray, counts, scratch)
                        .map(|cos| (cos, s.inv_pdf_solid_angle))
                }),
        };
        // `Shading::area_light`'s sum (one sample, weight 1), `Shading::lights`' (one pick of
        // probability `pmf`), then `shade`'s ambient and BRDF rays (none).
        let material = lanes.material[i];
        let mut sum = Vec3::ZERO;
        if let Some((cos, inv_pdf)) = seen {
            sum += self.light.radiance * material.f * (cos * inv_pdf * 1.0);
        }
        let mut lights = Vec3::ZERO;
        lights += divided(sum, self.pmf);
        material.ambient + lights + Vec3::ZERO
    }

    /// The shading cosine of a shadow ray `(traced, cos, origin, to_end)` that reaches its end.
    #[inline(always)]
    fn unoccluded(
        &self,
        (traced, cos, origin, to_end): (bool, f32, Vec3, Vec3),
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) -> Option<f32> {
        if !traced {
            return None;
        }
        counts.shadow += 1;
        let blocked = self
            .accel
            .any_hit_with(&Ray::segment(origin, to_end, 1.0), scratch);
        (!blocked).then_some(cos)
    }
}

/// [`RectLit::shadows`] compiled for AVX2.
struct ShadowKernel<'r, 'a> {
    lit: &'r RectLit<'a>,
    lanes: &'r Run,
}

impl Kernel<Avx2> for ShadowKernel<'_, '_> {
    type Output = Shadows;

    #[inline(always)]
    fn call(self, _: Avx2) -> Shadows {
        self.lit.shadows(self.lanes)
    }
}
