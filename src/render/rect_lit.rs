//! Stage 4: the per-sample path of a scene lit by one rectangle light, a run of samples at a
//! time.
//!
//! [`integrator::radiance_scaled`](super::integrator::radiance_scaled) serves every scene:
//! textures, normal maps, specular lobes, the environment, several lights, multiple importance
//! sampling. A scene with none of them (constant Lambertian materials, one area light that is a
//! rectangle sampled by solid angle once per camera sample, no environment: cornell,
//! soft_shadows) needs per camera sample a camera ray, its hit and, at a shading point, one
//! light sample and one shadow ray (MIS gives way to light sampling alone on such surfaces:
//! `mis::strategy_at`). [`RectLit::of`] recognises such a scene once per render, and its
//! pixels take this path, which carries none of the other branches' state. The same
//! floating-point operations in the same order as the general path, so the same bits (tests
//! compare whole images), a run of [`LANES`] samples at a time (the last run of a batch may be
//! shorter, down to one sample):
//!
//! 1. the run's camera rays made side by side, traced one by one, and their hits rebuilt: an
//!    emitter's radiance, black for a miss, or a shading point (side by side for unmoved
//!    placements of meshes without vertex normals, cornell's; one by one otherwise);
//! 2. the run's light samples and shadow rays computed side by side
//!    (`shade::light::rect_lanes`, then the rays' origins);
//! 3. the shadow rays traced, and the samples' radiance added to the pixel in order.
//!
//! The sub-pixel positions and light points come from where the general path takes them
//! ([`Samples`]): a fixed-count render's per-pixel stratified set and its shift
//! (`rng::PixelBatch`), or an adaptive pixel's sequences, continued from batch to batch
//! (`rng::PixelSequences::points_2d`, each sample added to its replicate).
//!
//! "Side by side" is a loop over the run's lanes whose body is branch-free, which the compiler
//! vectorises; a pixel's runs are compiled for AVX2 where the CPU has it (entered with
//! `geom::avx2`'s token), eight `f32` or four `f64` lanes a vector. BVH queries run on the
//! tile's own traversal stacks ([`Scratch`]).

use std::f32::consts::FRAC_1_PI;

use glam::{Affine3A, Vec2, Vec3};

use super::camera::PinholeCamera;
use super::estimate::Accumulator;
use super::integrator::{divided, RayCounts, STREAM_LIGHTS};
use super::rng::{self, PixelBatch, PixelSequences, RunLanes, STREAM_SUBPIXEL};
use crate::bvh::Hit;
use crate::bvh::{Accel, Scratch};
use crate::geom::avx2::{Avx2, Kernel};
use crate::geom::Ray;
use crate::ir::{ColorInput, ScalarInput};
use crate::scene::{DirectStrategy, LightSampling, Scene, ShadingPath, Surface};
use crate::shade::light::rect_lanes::{LaneSample, LaneVecs, Lanes, LANES};
use crate::shade::surface::{
    facing_viewer, leaving_origin, point_and_error, seen_hit, unmoved_corners, SeenHit, SurfaceHit,
};
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
    /// By instance: whether it places its mesh unmoved and the mesh has no vertex normals and
    /// its face normals were computed at the build (its hits are rebuilt in lanes).
    flat: Vec<bool>,
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
    /// The camera rays' unit directions.
    dir: LaneVecs,
    /// Lanes with a shading point (the others are done: `value`).
    shaded: [bool; LANES],
    /// Shading points still to rebuild from `corners` and the barycentrics (`Run::rebuild`).
    flat: [bool; LANES],
    corners: [LaneVecs; 3],
    u_hit: Lanes,
    v_hit: Lanes,
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
        let (ng, ns, _) = facing_viewer(hit.ng, hit.ns, dir);
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

impl Run {
    /// The `flat` lanes' shading points, side by side: `seen_hit`'s rebuild of an unmoved
    /// placement's hit on a mesh without vertex normals (the shading normal is the face's, no
    /// shadow-terminator offset), then `shade`'s normals turned to the viewer.
    /// Only the first `N` lanes: a run's side-by-side loops are as long as the smallest of
    /// 2, 4 and [`LANES`] that holds it ([`RectLit::run`]), so an adaptive pixel's runs of 2
    /// samples do not pay for 8. Each lane's operations are the same for any `N`.
    #[inline(always)]
    fn rebuild<const N: usize>(&mut self) {
        const { assert!(N <= LANES) };
        for i in 0..N {
            let obj = [0, 1, 2].map(|k| self.corners[k].get(i));
            let (world, transform_error) = unmoved_corners(obj);
            let (p, p_error) =
                point_and_error(world, transform_error, self.u_hit[i], self.v_hit[i]);
            let face = self.face.get(i);
            let (ng, ns, _) = facing_viewer(face, face, self.dir.get(i).normalize());
            let flat = self.flat[i];
            let keep = |new: Vec3, old: Vec3| if flat { new } else { old };
            self.p.set(i, keep(p, self.p.get(i)));
            self.p_error.set(i, keep(p_error, self.p_error.get(i)));
            self.ng.set(i, keep(ng, self.ng.get(i)));
            self.ns.set(i, keep(ns, self.ns.get(i)));
            for side in 0..2 {
                self.bulge[side].set(i, keep(Vec3::ZERO, self.bulge[side].get(i)));
            }
        }
    }
}

impl<'a> RectLit<'a> {
    /// This path for `scene`, if the scene is one it renders (see the module doc).
    pub(super) fn of(scene: &'a Scene) -> Option<RectLit<'a>> {
        let settings = &scene.settings;
        let allowed = scene.shading_path == ShadingPath::Specialised;
        let one_pick = settings.light_samples.max(1) == 1;
        let light_sampled = scene.light_sampling == LightSampling::SolidAngle
            && scene.strategy != DirectStrategy::BrdfOnly
            && scene.lights.environment.is_none();
        if !(allowed && one_pick && light_sampled) {
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
        let flat = scene
            .instances
            .iter()
            .map(|inst| {
                let mesh = inst.mesh as usize;
                inst.world_from_object == Affine3A::IDENTITY
                    && scene.meshes.get(mesh).is_some_and(|m| m.normals.is_empty())
                    && scene.face_normals.get(mesh).is_some_and(|n| !n.is_empty())
            })
            .collect();
        Some(RectLit {
            scene,
            accel: scene.accel.as_ref()?,
            light,
            pmf,
            materials,
            flat,
            avx2: Avx2::detect(),
        })
    }

    /// The pixel (`x`, `y`)'s `samples`, added to `acc` in order: what `Job::batch` (a fixed
    /// count) or `Job::progressive_batch` (an adaptive pixel's batch) computes.
    pub(super) fn pixel(
        &self,
        camera: &PinholeCamera,
        (x, y): (u32, u32),
        samples: Samples,
        acc: &mut Accumulator,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        let pixel = PixelKernel {
            lit: self,
            camera,
            film: Vec2::new(x as f32, y as f32),
            samples,
            acc,
            counts,
            scratch,
        };
        match self.avx2 {
            Some(avx2) => avx2.run(pixel),
            None => pixel.run(),
        }
    }

    /// Samples `samples` (a batch of at most eight) of each of `n` pixels (`pixel(k)`: the
    /// `k`th pixel and its sequences; at most [`RectLit::pixels_a_run`] of them), each handed to
    /// `add(k, radiance, replicate)` in order: what [`RectLit::pixel`] computes for each pixel
    /// alone, in one run whose lanes are the pixels' samples side by side (an adaptive
    /// render's first two batches are 2 samples each, a run of 2 in an 8-lane kernel: four
    /// pixels take one run, not four). Each lane's operations are the same for any run, so
    /// each pixel's sums are the same bits.
    #[allow(clippy::too_many_arguments)] // reason: the pixels, their sink and the tile's state
    pub(super) fn side_by_side<'s>(
        &self,
        camera: &PinholeCamera,
        (n, pixel): (usize, impl Fn(usize) -> ((u32, u32), &'s PixelSequences)),
        samples: std::ops::Range<u32>,
        add: impl FnMut(usize, Vec3, Option<usize>),
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        debug_assert!(samples.len() <= LANES && n <= Self::pixels_a_run(samples.len() as u32));
        let kernel = SideBySideKernel {
            lit: self,
            camera,
            n,
            pixel,
            samples,
            add,
            counts,
            scratch,
        };
        match self.avx2 {
            Some(avx2) => avx2.run(kernel),
            None => kernel.run(),
        }
    }

    /// How many pixels' batches of `samples` samples [`RectLit::side_by_side`] takes in one
    /// run.
    pub(super) fn pixels_a_run(samples: u32) -> usize {
        (LANES / (samples as usize).max(1)).max(1)
    }

    /// Traces lane `i`'s camera ray (from the eye along the run's direction) into it: a
    /// shading point (to rebuild, for a flat hit), or the radiance it sees
    /// (`integrator::radiance_scaled`'s first half).
    #[inline(always)]
    fn camera_sample(
        &self,
        eye: Vec3,
        i: usize,
        lanes: &mut Run,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        counts.camera += 1;
        let ray = Ray::new(eye, lanes.dir.get(i));
        lanes.value[i] = Vec3::ZERO;
        let Some(h) = self.accel.closest_hit_with(&ray, scratch) else {
            return;
        };
        if let Some((material, corners, face)) = self.flat_hit(&h) {
            lanes.shaded[i] = true;
            lanes.flat[i] = true;
            lanes.material[i] = material;
            for (k, c) in corners.into_iter().enumerate() {
                lanes.corners[k].set(i, c);
            }
            (lanes.u_hit[i], lanes.v_hit[i]) = (h.u, h.v);
            lanes.face.set(i, face);
            return;
        }
        lanes.value[i] = match seen_hit(self.scene, &h) {
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

    /// For a hit on a material of a `flat` instance: the material, the triangle's corners and
    /// its face normal (what `Run::rebuild` takes, `seen_hit`'s look-ups).
    #[inline(always)]
    fn flat_hit(&self, h: &Hit) -> Option<(Lambert, [Vec3; 3], Vec3)> {
        if !self.flat.get(h.instance as usize).copied().unwrap_or(false) {
            return None;
        }
        let scene = self.scene;
        let inst = scene.instances.get(h.instance as usize)?;
        let mesh = scene.meshes.get(inst.mesh as usize)?;
        let tri = mesh.triangles.get(h.prim as usize)?;
        let Surface::Material(m) = scene.surface_of(inst, mesh, h.prim) else {
            return None;
        };
        let material = *self.materials.get(m as usize)?;
        let face = *scene
            .face_normals
            .get(inst.mesh as usize)?
            .get(h.prim as usize)?;
        let corners = tri.map(|v| mesh.positions.get(v as usize).copied());
        let [Some(a), Some(b), Some(c)] = corners else {
            return None;
        };
        Some((material, [a, b, c], face))
    }

    /// The run's light samples and shadow rays, lane by lane (see the module doc).
    /// Only the first `N` lanes (see [`Run::rebuild`]).
    #[inline(always)]
    fn shadows<const N: usize>(&self, lanes: &Run) -> Shadows {
        let samples = self
            .light
            .sample_first_lanes::<N>(&lanes.p, &lanes.u, &lanes.shaded);
        let mut out = Shadows {
            kind: samples.kind,
            inv_pdf_solid_angle: samples.inv_pdf_solid_angle,
            ..Shadows::default()
        };
        for i in 0..N {
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

/// Where a pixel's samples take their sub-pixel positions and light points.
pub(super) enum Samples<'r> {
    /// A fixed-count render's one batch: point `s` of the stratified `offsets` shifted by
    /// `shift` (wrapped), and the batch's samplers' stratified light points.
    Fixed {
        offsets: &'r [Vec2],
        shift: Vec2,
        samplers: &'r PixelBatch,
    },
    /// Samples `samples` (counted over all the pixel's batches) of an adaptive pixel: each
    /// continues its sequences (`PixelSequences::points_2d`) and is added to its replicate.
    Progressive {
        sequences: &'r PixelSequences,
        samples: std::ops::Range<u32>,
    },
}

/// One pixel's samples ([`RectLit::pixel`]), to run compiled for AVX2 or not.
struct PixelKernel<'r, 'a> {
    lit: &'r RectLit<'a>,
    camera: &'r PinholeCamera,
    /// The pixel's corner on the film.
    film: Vec2,
    samples: Samples<'r>,
    acc: &'r mut Accumulator,
    counts: &'r mut RayCounts,
    scratch: &'r mut Scratch,
}

impl PixelKernel<'_, '_> {
    #[inline(always)]
    fn run(self) {
        let PixelKernel {
            lit,
            camera,
            film,
            samples,
            acc,
            counts,
            scratch,
        } = self;
        let eye = camera.eye();
        let mut lanes = Run::default();
        match samples {
            Samples::Fixed {
                offsets,
                shift,
                samplers,
            } => {
                let count = offsets.len() as u32;
                for (first, run) in (0..).step_by(LANES).zip(offsets.chunks(LANES)) {
                    // Every lane's point (past the pixel's last sample too: unread), so the
                    // loop has a fixed length and runs side by side.
                    samplers.stratified_run(STREAM_LIGHTS, first, count, &mut lanes.u);
                    let mut at = [film; LANES];
                    for (a, offset) in at.iter_mut().zip(run) {
                        let o = *offset + shift;
                        *a += Vec2::new(rng::wrap_unit(o.x), rng::wrap_unit(o.y));
                    }
                    let add = |_: usize, l: Vec3| {
                        acc.add(l);
                    };
                    lit.run(
                        camera,
                        eye,
                        (&at, run.len()),
                        &mut lanes,
                        add,
                        counts,
                        scratch,
                    );
                }
            }
            Samples::Progressive { sequences, samples } => {
                let mut offsets = [Vec2::ZERO; LANES];
                let mut first = samples.start;
                while first < samples.end {
                    let len = (samples.end - first).min(LANES as u32) as usize;
                    let run = first..first + len as u32;
                    sequences.points_2d(STREAM_SUBPIXEL, run.clone(), &mut offsets[..len]);
                    // Lanes past the run keep their last points (unread).
                    sequences.points_2d(STREAM_LIGHTS, run.clone(), &mut lanes.u[..len]);
                    let mut at = [film; LANES];
                    for (a, o) in at.iter_mut().zip(&offsets[..len]) {
                        *a += *o;
                    }
                    let add = |i: usize, l: Vec3| {
                        acc.add_replicate(l, PixelSequences::replicate(first + i as u32));
                    };
                    lit.run(camera, eye, (&at, len), &mut lanes, add, counts, scratch);
                    first = run.end;
                }
            }
        }
    }
}

/// Pixels' batches side by side ([`RectLit::side_by_side`]), to run compiled for AVX2 or not.
struct SideBySideKernel<'r, 'a, P, A> {
    lit: &'r RectLit<'a>,
    camera: &'r PinholeCamera,
    n: usize,
    pixel: P,
    samples: std::ops::Range<u32>,
    add: A,
    counts: &'r mut RayCounts,
    scratch: &'r mut Scratch,
}

impl<'s, P, A> SideBySideKernel<'_, '_, P, A>
where
    P: Fn(usize) -> ((u32, u32), &'s PixelSequences),
    A: FnMut(usize, Vec3, Option<usize>),
{
    #[inline(always)]
    fn run(self) {
        let SideBySideKernel {
            lit,
            camera,
            n,
            pixel,
            samples,
            mut add,
            counts,
            scratch,
        } = self;
        let each = samples.len().min(LANES);
        if each == 0 {
            return;
        }
        let run = samples.start..samples.start + each as u32;
        let eye = camera.eye();
        let mut lanes = Run::default();
        // The run's lanes gathered from its pixels, then each stream's points in one eight-lane
        // computation (lanes past the run: some point, unread).
        let mut gathered = RunLanes::default();
        let mut film = [Vec2::ZERO; LANES];
        let mut len = 0;
        for (k, lane) in (0..n).zip((0..LANES).step_by(each)) {
            let ((x, y), sequences) = pixel(k);
            for (i, g) in (lane..lane + each).zip(run.clone()) {
                gathered.set(i, sequences, g);
                film[i] = Vec2::new(x as f32, y as f32);
            }
            len = lane + each;
        }
        let mut offsets = [Vec2::ZERO; LANES];
        gathered.points_2d(STREAM_SUBPIXEL, &mut offsets);
        gathered.points_2d(STREAM_LIGHTS, &mut lanes.u);
        let at: [Vec2; LANES] = std::array::from_fn(|i| film[i] + offsets[i]);
        let start = run.start;
        let add = |i: usize, l: Vec3| {
            let replicate = PixelSequences::replicate(start + (i % each) as u32);
            add(i / each, l, replicate);
        };
        lit.run(camera, eye, (&at, len), &mut lanes, add, counts, scratch);
    }
}

impl<'s, P, A> Kernel<Avx2> for SideBySideKernel<'_, '_, P, A>
where
    P: Fn(usize) -> ((u32, u32), &'s PixelSequences),
    A: FnMut(usize, Vec3, Option<usize>),
{
    type Output = ();

    #[inline(always)]
    fn call(self, _: Avx2) {
        self.run();
    }
}

impl RectLit<'_> {
    /// One run: the first `len` lanes' samples, seen through film points `at` with the light
    /// points already in `lanes.u`, each finite radiance handed to `add` with its lane, in
    /// order (as `Job::batch`: a non-finite sample is counted, not added).
    #[allow(clippy::too_many_arguments)] // reason: the run, its sink and the tile's state
    #[inline(always)]
    fn run(
        &self,
        camera: &PinholeCamera,
        eye: Vec3,
        (at, len): (&[Vec2; LANES], usize),
        lanes: &mut Run,
        add: impl FnMut(usize, Vec3),
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        let run = (at, len);
        match len {
            0..=2 => self.run_first::<2>(camera, eye, run, lanes, add, counts, scratch),
            3..=4 => self.run_first::<4>(camera, eye, run, lanes, add, counts, scratch),
            _ => self.run_first::<LANES>(camera, eye, run, lanes, add, counts, scratch),
        }
    }

    /// [`RectLit::run`] with its side-by-side loops over the first `N` lanes (`len <= N`).
    #[allow(clippy::too_many_arguments)] // reason: the run, its sink and the tile's state
    #[allow(clippy::needless_range_loop)] // reason: the vectorisable shape (`Run::rebuild`)
    #[inline(always)]
    fn run_first<const N: usize>(
        &self,
        camera: &PinholeCamera,
        eye: Vec3,
        (at, len): (&[Vec2; LANES], usize),
        lanes: &mut Run,
        mut add: impl FnMut(usize, Vec3),
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        debug_assert!(len <= N && N <= LANES);
        lanes.shaded = [false; LANES];
        lanes.flat = [false; LANES];
        for i in 0..N {
            lanes.dir.set(i, camera.ray(at[i]).dir);
        }
        for i in 0..len {
            self.camera_sample(eye, i, lanes, counts, scratch);
        }
        lanes.rebuild::<N>();
        let shadows = self.shadows::<N>(lanes);
        for i in 0..len {
            let l = self.radiance(i, lanes, &shadows, counts, scratch);
            if l.is_finite() {
                add(i, l);
            } else {
                counts.nonfinite += 1;
            }
        }
    }
}

impl Kernel<Avx2> for PixelKernel<'_, '_> {
    type Output = ();

    #[inline(always)]
    fn call(self, _: Avx2) {
        self.run();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::FsLoader;
    use crate::compile::compile_file;
    use crate::ir::SceneDesc;
    use crate::scene::{build, BuildOptions};

    fn example(name: &str, edit: impl Fn(&mut SceneDesc)) -> Scene {
        let loader = FsLoader::new();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("examples")
            .join(format!("{name}.scn"));
        let mut desc = compile_file(&path, &loader)
            .scene
            .expect("the example compiles");
        edit(&mut desc);
        build(&desc, &loader, &BuildOptions::default())
            .into_result()
            .map(|(scene, _)| scene)
            .unwrap_or_else(|_| panic!("{name} builds"))
    }

    fn cornell(edit: impl Fn(&mut SceneDesc)) -> Scene {
        example("cornell", edit)
    }

    /// cornell and soft_shadows take the path, fixed-count or adaptive; a specular lobe,
    /// several light samples or the general path asked for do not (the image comparisons are `tests/render_rect_lit.rs`).
    #[test]
    fn covers_cornell_and_no_scene_with_other_features() {
        assert!(RectLit::of(&cornell(|_| ())).is_some());
        assert!(RectLit::of(&cornell(|d| d.render.noise = Some(0.05))).is_some());
        // A sphere with vertex normals and a rotated box: covered, their hits rebuilt one by one.
        let soft = example("soft_shadows", |_| ());
        let lit = RectLit::of(&soft).expect("soft_shadows is covered");
        assert!(lit.flat.iter().any(|&f| f) && !lit.flat.iter().all(|&f| f));
        let specular =
            |d: &mut SceneDesc| d.materials[0].specular = ColorInput::Constant(Vec3::splat(0.2));
        let picks = |d: &mut SceneDesc| d.render.light_samples = 2;
        let samples = |d: &mut SceneDesc| {
            if let Some(crate::ir::Light::Area(a)) = d.lights.first_mut() {
                a.samples = 4;
            }
        };
        let edits: [fn(&mut SceneDesc); 3] = [specular, picks, samples];
        for edit in edits {
            assert!(RectLit::of(&cornell(edit)).is_none());
        }
        let mut general = cornell(|_| ());
        general.shading_path = ShadingPath::General;
        assert!(RectLit::of(&general).is_none());
    }

    /// An adaptive pixel's samples `samples` on the general path: `Job::progressive_batch`'s
    /// loop, one sample at a time.
    fn general_progressive(
        scene: &Scene,
        camera: &PinholeCamera,
        (x, y): (u32, u32),
        samples: std::ops::Range<u32>,
        counts: &mut RayCounts,
    ) -> Accumulator {
        let sequences = PixelSequences::new(scene.settings.seed, x, y);
        let mut acc = Accumulator::default();
        for g in samples {
            let mut o = [Vec2::ZERO];
            sequences.points_2d(STREAM_SUBPIXEL, g..g + 1, &mut o);
            let ray = camera.ray(Vec2::new(x as f32, y as f32) + o[0]);
            let mut sampler = sequences.sampler(g);
            let l =
                crate::render::integrator::radiance_scaled(scene, &ray, 1.0, &mut sampler, counts);
            if l.is_finite() {
                acc.add_replicate(l, PixelSequences::replicate(g));
            } else {
                counts.nonfinite += 1;
            }
        }
        acc
    }

    /// An adaptive pixel's runs of any length (1, 2, 3, 5, 9 samples, from the first sample, in
    /// the shared round, across its end and deep in the replicates' sequences) give the general
    /// path's sums bit for bit, and its ray counts: the sequences continue across batches.
    #[test]
    fn adaptive_runs_of_any_length_are_the_general_paths_samples() {
        for name in ["cornell", "soft_shadows"] {
            let scene = example(name, |d| {
                d.render.width = 24;
                d.render.height = 24;
                d.render.noise = Some(0.05);
            });
            let lit = RectLit::of(&scene).expect("covered");
            let camera = PinholeCamera::new(&scene.camera, 24, 24);
            let mut scratch = Scratch::new();
            let mut shadow_rays = 0;
            for (x, y) in [(3, 4), (12, 12), (20, 7), (11, 20)] {
                let sequences = PixelSequences::new(scene.settings.seed, x, y);
                for start in [0, 2, 3, 4, 17, 100] {
                    for len in [1, 2, 3, 5, 9] {
                        let samples = start..start + len;
                        let (mut fast_counts, mut general_counts) =
                            (RayCounts::default(), RayCounts::default());
                        let mut fast = Accumulator::default();
                        let from = Samples::Progressive {
                            sequences: &sequences,
                            samples: samples.clone(),
                        };
                        let sinks = (&mut fast, &mut fast_counts, &mut scratch);
                        lit.pixel(&camera, (x, y), from, sinks.0, sinks.1, sinks.2);
                        let general = general_progressive(
                            &scene,
                            &camera,
                            (x, y),
                            samples,
                            &mut general_counts,
                        );
                        let what = format!("{name} ({x}, {y}), samples {start}..{}", start + len);
                        assert_eq!(format!("{fast:?}"), format!("{general:?}"), "{what}");
                        assert_eq!(fast_counts, general_counts, "{what}");
                        assert_eq!(fast_counts.camera, u64::from(len), "{what}");
                        shadow_rays += fast_counts.shadow;
                    }
                }
            }
            assert!(shadow_rays > 0, "{name}: lit samples compared");
        }
    }
}
