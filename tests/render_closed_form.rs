//! Stage 4 against mathematics: analytic scenes render their closed-form radiance.
//!
//! - a diffuse plane under a point light: `ρ/π · I · cos θ / r²`, deterministic, so compared to
//!   float tolerance;
//! - a diffuse plane under a square area light: `ρ/π · E`, with `E` from Lambert's exact polygon
//!   formula, within 4 standard errors estimated from the sample variance;
//! - a constant environment over a diffuse plane: `ρ · L` with zero variance when sampled by the
//!   BRDF alone (cosine sampling is exact for a diffuse surface under a constant sky); the other
//!   strategies are checked on the same scene within 4 standard errors in
//!   `tests/render_environment.rs`.

mod render_common;

use std::f32::consts::{FRAC_1_PI, PI};

use glam::{Mat4, Vec2, Vec3};
use render_common::*;
use scnc::bvh::AccelKind;
use scnc::geom::Ray;
use scnc::ir::{EnvSource, EnvironmentLight, Light, SceneDesc};
use scnc::render::camera::PinholeCamera;
use scnc::render::integrator::{radiance, RayCounts};
use scnc::render::rng::Sampler;
use scnc::scene::{DirectStrategy, Scene};

fn plane_scene(albedo: f32, lights: Vec<Light>) -> SceneDesc {
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 4.0, 0.0), Vec3::ZERO, Vec3::Z, 60.0),
        settings(16, 12, 1),
    );
    desc.meshes = vec![quad("floor", 20.0, 20.0), quad("panel", 0.5, 0.5)];
    desc.materials = vec![phong("white", Vec3::splat(albedo), 0.0, 1.0)];
    desc.objects = vec![object(0, 0, Mat4::IDENTITY)];
    desc.lights = lights;
    desc
}

#[test]
fn point_light_on_a_diffuse_plane_is_rho_over_pi_i_cos_over_r2() {
    let light = Vec3::new(0.7, 2.0, -0.4);
    let intensity = 5.0;
    let desc = plane_scene(0.8, vec![point_light(light, intensity)]);
    let (film, stats) = render_with(&build(&desc, AccelKind::Bvh), 1);
    assert_eq!(stats.shadow_rays, 16 * 12);
    let cam = PinholeCamera::new(&desc.cameras[0], 16, 12);
    for (x, y) in [(0, 0), (8, 6), (15, 11), (3, 9), (12, 2)] {
        let ray = cam.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
        let p = ray.at(-ray.origin.y / ray.dir.y);
        let to_light = light - p;
        let r2 = to_light.length_squared();
        let cos = to_light.y / r2.sqrt();
        let expected = 0.8 * FRAC_1_PI * intensity * cos / r2;
        let got = film.get(x, y);
        assert!(
            (got - Vec3::splat(expected)).abs().max_element() <= 1e-5 * expected,
            "pixel ({x},{y}): {got} vs {expected}"
        );
    }
    // Falloff: the pixel straight below the light is brighter than one far from it.
    assert!(film.get(8, 6).x > film.get(0, 0).x);
}

#[test]
fn a_light_behind_the_surface_contributes_nothing() {
    let desc = plane_scene(0.8, vec![point_light(Vec3::new(0.0, -1.0, 0.0), 5.0)]);
    let (film, _) = render_with(&build(&desc, AccelKind::Bvh), 1);
    assert!(film.pixels().iter().all(|&p| p == Vec3::ZERO));
}

/// Irradiance at `p` (normal `n`) from a uniform Lambertian polygon of radiance 1 (Lambert).
fn polygon_irradiance(p: Vec3, n: Vec3, polygon: &[Vec3]) -> f32 {
    let mut sum = 0.0;
    for i in 0..polygon.len() {
        let a = (polygon[i] - p).normalize();
        let b = (polygon[(i + 1) % polygon.len()] - p).normalize();
        sum += a.dot(b).clamp(-1.0, 1.0).acos() * n.dot(a.cross(b).normalize());
    }
    (sum / 2.0).abs()
}

/// Mean and standard error of the radiance towards the camera at `p` over `n` samples.
fn estimate(scene: &Scene, p: Vec3, n: u32) -> (f64, f64) {
    let eye = p + Vec3::new(3.0, 2.0, 0.0);
    let ray = Ray::new(eye, (p - eye).normalize());
    let mut counts = RayCounts::default();
    let values: Vec<f64> = (0..n)
        .map(|i| radiance(scene, &ray, &mut Sampler::new(0, 0, 0, i), &mut counts).x as f64)
        .collect();
    let mean = values.iter().sum::<f64>() / n as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    (mean, (var / n as f64).sqrt())
}

#[test]
fn a_square_area_light_gives_the_closed_form_irradiance() {
    let centre = Vec3::new(0.2, 1.0, 0.1);
    let le = 4.0;
    let facing_down = Mat4::from_translation(centre) * Mat4::from_rotation_x(PI);
    let corners: Vec<Vec3> = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .iter()
        .map(|&(x, z)| centre + Vec3::new(x * 0.25, 0.0, z * 0.25))
        .collect();
    let desc = plane_scene(1.0, vec![area_light(1, facing_down, le, false, 4)]);
    let scene = build(&desc, AccelKind::Bvh);
    for p in [
        Vec3::ZERO,
        Vec3::new(0.2, 0.0, 0.1),
        Vec3::new(1.0, 0.0, -0.5),
    ] {
        let exact = (FRAC_1_PI * le * polygon_irradiance(p, Vec3::Y, &corners)) as f64;
        let (mean, se) = estimate(&scene, p, 2000);
        assert!(
            se < 0.03 * exact,
            "the test must be sharp: se {se} vs {exact}"
        );
        assert!(
            (mean - exact).abs() < 4.0 * se,
            "at {p}: {mean} ± {se} vs {exact}"
        );
    }
}

#[test]
fn one_sided_lights_emit_from_the_front_only_and_two_sided_from_both() {
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let facing_up = Mat4::from_translation(centre);
    let facing_down = facing_up * Mat4::from_rotation_x(PI);
    let p = Vec3::new(0.1, 0.0, 0.0);
    let lit = |light| {
        let scene = build(&plane_scene(1.0, vec![light]), AccelKind::Bvh);
        estimate(&scene, p, 256).0
    };
    assert_eq!(lit(area_light(1, facing_up, 4.0, false, 2)), 0.0);
    let down = lit(area_light(1, facing_down, 4.0, false, 2));
    let both = lit(area_light(1, facing_up, 4.0, true, 2));
    assert!(
        down > 0.0 && (down - both).abs() < 1e-6 * down,
        "{down} vs {both}"
    );

    // Seen directly, the front shows its radiance and the back is black.
    let scene = build(
        &plane_scene(1.0, vec![area_light(1, facing_down, 4.0, false, 1)]),
        AccelKind::Bvh,
    );
    let mut counts = RayCounts::default();
    let mut s = Sampler::new(0, 0, 0, 0);
    let from_below = Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Y);
    assert_eq!(
        radiance(&scene, &from_below, &mut s, &mut counts),
        Vec3::splat(4.0)
    );
    let from_above = Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y);
    assert_eq!(
        radiance(&scene, &from_above, &mut s, &mut counts),
        Vec3::ZERO
    );
}

#[test]
fn constant_environment_over_a_diffuse_plane_is_albedo_times_radiance() {
    let sky = Light::Environment(EnvironmentLight {
        name: "sky".into(),
        source: EnvSource::Constant(Vec3::splat(1.0)),
        intensity: 2.0,
        rotation_y_rad: 0.0,
        visible: true,
        span: span(),
    });
    let mut desc = plane_scene(0.5, vec![sky]);
    desc.render.samples_per_pixel = 4;
    let mut scene = build(&desc, AccelKind::Bvh);
    scene.strategy = DirectStrategy::BrdfOnly;
    let (film, _) = render_with(&scene, 2);
    for &p in film.pixels() {
        assert!((p - Vec3::splat(1.0)).abs().max_element() < 1e-5, "{p}");
    }
    // Escaped camera rays show the sky.
    let scene = build(&desc, AccelKind::Bvh);
    let up = Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::Y);
    let got = radiance(
        &scene,
        &up,
        &mut Sampler::new(0, 0, 0, 0),
        &mut RayCounts::default(),
    );
    assert_eq!(got, Vec3::splat(2.0));
}

#[test]
fn point_light_specular_highlight_matches_the_normalised_lobe() {
    let light = Vec3::new(0.3, 2.0, 0.2);
    let intensity = 3.0;
    let mut desc = plane_scene(0.5, vec![point_light(light, intensity)]);
    desc.materials = vec![phong("glossy", Vec3::splat(0.5), 0.3, 20.0)];
    let (film, _) = render_with(&build(&desc, AccelKind::Bvh), 1);
    let cam = PinholeCamera::new(&desc.cameras[0], 16, 12);
    let mut saw_highlight = false;
    for y in 0..12 {
        for x in 0..16 {
            let ray = cam.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let p = ray.at(-ray.origin.y / ray.dir.y);
            let wi = (light - p).normalize();
            let wo = -ray.dir;
            let r = 2.0 * wi.y * Vec3::Y - wi;
            let lobe = 0.3 * 22.0 / (2.0 * PI) * r.dot(wo).max(0.0).powf(20.0);
            let f = 0.5 * FRAC_1_PI + lobe;
            let expected = f * intensity * wi.y / (light - p).length_squared();
            saw_highlight |= lobe > 0.5 * FRAC_1_PI;
            let got = film.get(x, y).x;
            assert!(
                (got - expected).abs() <= 1e-4 * expected,
                "({x},{y}): {got} vs {expected}"
            );
        }
    }
    assert!(saw_highlight, "the view must include the highlight");
}
