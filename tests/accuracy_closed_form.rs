//! Stage 4 against mathematics, the "correct" half of issue 8 (extends `render_closed_form.rs`,
//! which covers a square light over a horizontal plane and the point light over a plane seen
//! through the camera):
//!
//! - a rectangular area light over a Lambertian receiver at several positions and orientations,
//!   one point 2% of the light's size away from it and one at grazing incidence (79° from the normal): rendered
//!   radiance = `ρ/π · L_e · E`, `E` from Lambert's polygon formula, for both ways of sampling
//!   the light, within 4 standard errors estimated from the samples themselves;
//! - a point light: inverse square over nine decades of distance and the cosine law up to 89°;
//! - the normalised Phong lobe, by Monte Carlo with its own importance sampling: directional
//!   albedo ≤ 1 for every exponent and incidence, and exactly 1 at normal incidence;
//! - `examples/cornell.scn` as written: floor points that see the whole light (checked by
//!   tracing a grid of rays to it) have the closed-form radiance in every channel.
//!
//! Figures are printed (`--nocapture`) and quoted in docs/accuracy.md.

mod render_common;

use std::f32::consts::{FRAC_1_PI, PI};
use std::path::Path;

use glam::{Mat4, Quat, Vec2, Vec3};
use render_common::*;
use scnc::assets::FsLoader;
use scnc::bvh::AccelKind;
use scnc::compile::compile_file;
use scnc::geom::Ray;
use scnc::render::integrator::{radiance, RayCounts};
use scnc::render::rng::Sampler;
use scnc::scene::{build as build_scene, BuildOptions, LightSampling, Scene};
use scnc::shade::brdf::Phong;

/// Irradiance at `p` (unit normal `n`) from a uniform Lambertian polygon of radiance 1 that is
/// wholly above `p`'s horizon (Lambert 1760): `E = ½ Σ βᵢ n·γᵢ`.
fn polygon_irradiance(p: Vec3, n: Vec3, polygon: &[Vec3]) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..polygon.len() {
        let a = (polygon[i] - p).as_dvec3().normalize();
        let b = (polygon[(i + 1) % polygon.len()] - p)
            .as_dvec3()
            .normalize();
        let beta = a.dot(b).clamp(-1.0, 1.0).acos();
        sum += beta * n.as_dvec3().dot(a.cross(b).normalize());
    }
    (sum / 2.0).abs()
}

/// Per-channel mean and standard error of the radiance along `ray` over `n` independent samples.
fn estimate(scene: &Scene, ray: &Ray, n: u32) -> ([f64; 3], [f64; 3]) {
    let mut counts = RayCounts::default();
    let values: Vec<Vec3> = (0..n)
        .map(|i| radiance(scene, ray, &mut Sampler::new(1, 0, 0, i), &mut counts))
        .collect();
    let mut mean = [0.0; 3];
    let mut se = [0.0; 3];
    for c in 0..3 {
        let m = values.iter().map(|v| f64::from(v[c])).sum::<f64>() / f64::from(n);
        let var = values
            .iter()
            .map(|v| (f64::from(v[c]) - m).powi(2))
            .sum::<f64>()
            / f64::from(n - 1);
        mean[c] = m;
        se[c] = (var / f64::from(n)).sqrt();
    }
    (mean, se)
}

/// A 0.6 × 0.3 light of radiance `le` centred at (0, 1, 0), facing down, and a small receiver
/// quad centred at `p` with front normal `n`, seen along a ray from its front side.
fn receiver_scene(p: Vec3, n: Vec3, size: f32, le: f32) -> (Scene, Ray, Vec<Vec3>) {
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 3.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
        settings(4, 4, 1),
    );
    desc.meshes = vec![quad("receiver", size, size), quad("panel", 0.6, 0.3)];
    desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
    let to_n = Quat::from_rotation_arc(Vec3::Y, n);
    desc.objects = vec![object(
        0,
        0,
        Mat4::from_translation(p) * Mat4::from_quat(to_n),
    )];
    let facing_down = Mat4::from_translation(centre) * Mat4::from_rotation_x(PI);
    desc.lights = vec![area_light(1, facing_down, le, false, 4)];
    let corners = [(-0.3, -0.15), (0.3, -0.15), (0.3, 0.15), (-0.3, 0.15)]
        .iter()
        .map(|&(x, z)| centre + Vec3::new(x, 0.0, z))
        .collect();
    // The eye: in front of the receiver, nearer than the light, a little off the normal.
    let tangent = to_n * Vec3::X;
    let eye = p + 0.3 * size * (n + 0.5 * tangent);
    (
        build(&desc, AccelKind::Bvh),
        Ray::new(eye, (p - eye).normalize()),
        corners,
    )
}

#[test]
fn rectangular_area_light_matches_lamberts_polygon_formula() {
    let tilt = |deg: f32, axis: Vec3| Quat::from_axis_angle(axis, deg.to_radians()) * Vec3::Y;
    // (name, point, normal, receiver size)
    let cases = [
        ("below, facing up", Vec3::new(0.0, 0.0, 0.0), Vec3::Y, 0.1),
        ("off-centre", Vec3::new(0.7, 0.2, -0.4), Vec3::Y, 0.1),
        (
            "tilted 40°",
            Vec3::new(-0.3, 0.3, 0.2),
            tilt(40.0, Vec3::Z),
            0.1,
        ),
        (
            "tilted 65° about two axes",
            Vec3::new(0.5, 0.1, 0.5),
            tilt(-65.0, Vec3::new(1.0, 0.0, -1.0).normalize()),
            0.1,
        ),
        // 0.012 below a light 0.6 wide: the light fills most of the hemisphere.
        (
            "close to the light",
            Vec3::new(0.05, 0.988, 0.02),
            Vec3::Y,
            0.004,
        ),
        // Far to the side and low: the light is 78–79.5° from the normal.
        ("grazing", Vec3::new(5.0, 0.0, 0.0), Vec3::Y, 0.1),
    ];
    let le = 3.0;
    for sampling in [LightSampling::SolidAngle, LightSampling::Area] {
        for (name, p, n, size) in cases {
            let (mut scene, ray, corners) = receiver_scene(p, n, size, le);
            scene.light_sampling = sampling;
            // Lambert's formula needs the whole polygon above the horizon.
            let cos_max = corners
                .iter()
                .map(|c| n.dot((*c - p).normalize()))
                .fold(f32::INFINITY, f32::min);
            assert!(cos_max > 0.0, "{name}: the light must be above the horizon");
            let e = polygon_irradiance(p, n, &corners);
            let exact = f64::from(FRAC_1_PI * le) * e;
            let (mean, se) = estimate(&scene, &ray, 3000);
            let z = (mean[0] - exact) / se[0];
            eprintln!(
                "{sampling:?} {name}: exact {exact:.6}, rendered {:.6} ± {:.6} ({:.2}%), z = {z:.2}",
                mean[0],
                se[0],
                100.0 * se[0] / exact
            );
            assert!(
                se[0] < 0.03 * exact,
                "{name}: the test must be sharp (se {} of {exact})",
                se[0]
            );
            assert!(
                z.abs() < 4.0,
                "{sampling:?} {name}: {mean:?} ± {se:?} vs {exact}"
            );
        }
    }
}

#[test]
fn point_light_follows_inverse_square_and_cosine() {
    // A white plane through the origin, normal +y; the light at distance r, angle θ from
    // the normal. Deterministic (one shadow ray), so compared at float precision.
    for r in [1e-3f32, 1e-2, 1.0, 1e2, 1e4, 1e6] {
        for theta_deg in [0.0f32, 30.0, 60.0, 80.0, 89.0] {
            let t = theta_deg.to_radians();
            let light = r * Vec3::new(t.sin(), t.cos(), 0.0);
            let mut desc = empty_desc(
                camera(Vec3::new(0.0, 3.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
                settings(4, 4, 1),
            );
            desc.meshes = vec![quad("floor", 1e-2 * r, 1e-2 * r)];
            desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
            desc.objects = vec![object(0, 0, Mat4::IDENTITY)];
            desc.lights = vec![point_light(light, 7.0)];
            let scene = build(&desc, AccelKind::Bvh);
            let eye = Vec3::new(-0.3 * r, 0.5 * r, 0.1 * r);
            let ray = Ray::new(eye, -eye.normalize());
            let got = radiance(
                &scene,
                &ray,
                &mut Sampler::new(0, 0, 0, 0),
                &mut RayCounts::default(),
            )
            .x;
            let expected = FRAC_1_PI * 7.0 * t.cos() / (r * r);
            assert!(
                (got - expected).abs() <= 1e-4 * expected,
                "r = {r}, θ = {theta_deg}°: {got} vs {expected}"
            );
        }
    }
}

/// `∫ f cos θᵢ dωᵢ` of the pure specular lobe by importance sampling its own lobe.
fn lobe_albedo(shininess: f32, wo: Vec3, n: u32) -> (f64, f64) {
    let lobe = Phong {
        diffuse: Vec3::ZERO,
        specular: Vec3::ONE,
        shininess,
    };
    let ns = Vec3::Z;
    let mut sampler = Sampler::new(9, 0, 0, 0);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let u: Vec2 = sampler.next_2d();
        let value = lobe
            .sample(ns, wo, u)
            .filter(|wi| wi.z > 0.0)
            .map_or(0.0, |wi| {
                let pdf = lobe.pdf(ns, wo, wi);
                if pdf > 0.0 {
                    f64::from(lobe.eval(ns, wi, wo).x * wi.z / pdf)
                } else {
                    0.0
                }
            });
        sum += value;
        sum2 += value * value;
    }
    let mean = sum / f64::from(n);
    let var = (sum2 / f64::from(n) - mean * mean).max(0.0) * f64::from(n) / f64::from(n - 1);
    (mean, (var / f64::from(n)).sqrt())
}

#[test]
fn normalised_phong_lobe_conserves_energy_for_every_exponent() {
    for shininess in [0.0f32, 0.5, 1.0, 2.0, 7.5, 32.0, 200.0, 1e3, 1e4, 1e5] {
        let (head_on, se) = lobe_albedo(shininess, Vec3::Z, 20_000);
        // Closed form at normal incidence: (n+2)/(2π) · 2π ∫ cos^(n+1) sin = 1.
        assert!(
            (head_on - 1.0).abs() < 4.0 * se + 1e-6,
            "n = {shininess}: albedo {head_on} ± {se} at normal incidence"
        );
        for theta_deg in [10.0f32, 30.0, 60.0, 80.0, 89.0] {
            let t = theta_deg.to_radians();
            let (a, se) = lobe_albedo(shininess, Vec3::new(t.sin(), 0.0, t.cos()), 4000);
            assert!(
                a - 4.0 * se <= 1.0,
                "n = {shininess}, θ = {theta_deg}°: albedo {a} ± {se} exceeds 1"
            );
        }
    }
}

#[test]
fn cornell_floor_points_that_see_the_whole_light_have_the_closed_form_radiance() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let loader = FsLoader::new();
    let compiled = compile_file(&root.join("examples/cornell.scn"), &loader);
    let desc = compiled.scene.expect("examples/cornell.scn compiles");
    let scene = build_scene(&desc, &loader, &BuildOptions::default())
        .value
        .expect("examples/cornell.scn builds");
    let corners = [
        Vec3::new(343.0, 548.7, 227.0),
        Vec3::new(343.0, 548.7, 332.0),
        Vec3::new(213.0, 548.7, 332.0),
        Vec3::new(213.0, 548.7, 227.0),
    ];
    let le = Vec3::new(17.0, 12.0, 4.0);
    let albedo = Vec3::new(0.725, 0.71, 0.68);
    let accel = scene.accel.as_ref().expect("the box has triangles");
    let sees_whole_light = |p: Vec3| {
        (0..=16).all(|i| {
            (0..=16).all(|j| {
                let (a, b) = (i as f32 / 16.0, j as f32 / 16.0);
                let q = corners[0]
                    + a * (corners[1] - corners[0])
                    + b * (corners[3] - corners[0])
                    + Vec3::new(0.0, -0.05, 0.0);
                let o = p + Vec3::new(0.0, 0.01, 0.0);
                !accel.any_hit(&Ray::segment(o, q - o, 1.0))
            })
        })
    };
    let mut checked = 0;
    for p in [
        Vec3::new(278.0, 0.0, 20.0),
        Vec3::new(480.0, 0.0, 100.0),
        Vec3::new(60.0, 0.0, 480.0),
        Vec3::new(180.0, 0.0, 330.0),
        Vec3::new(500.0, 0.0, 520.0),
        Vec3::new(420.0, 0.0, 150.0),
    ] {
        if !sees_whole_light(p) {
            eprintln!("cornell: {p} is partly shadowed, skipped");
            continue;
        }
        let eye = p + Vec3::new(20.0, 60.0, -40.0);
        let ray = Ray::new(eye, (p - eye).normalize());
        let e = polygon_irradiance(p, Vec3::Y, &corners);
        let (mean, se) = estimate(&scene, &ray, 4000);
        for c in 0..3 {
            let exact = f64::from(albedo[c] * le[c] * FRAC_1_PI) * e;
            eprintln!(
                "cornell {p} channel {c}: exact {exact:.5}, rendered {:.5} ± {:.5}",
                mean[c], se[c]
            );
            assert!(se[c] < 0.02 * exact, "sharp: {} of {exact}", se[c]);
            assert!(
                (mean[c] - exact).abs() < 4.0 * se[c],
                "{p} channel {c}: {} ± {} vs {exact}",
                mean[c],
                se[c]
            );
        }
        checked += 1;
    }
    assert!(
        checked >= 3,
        "only {checked} floor points see the whole light"
    );
}
