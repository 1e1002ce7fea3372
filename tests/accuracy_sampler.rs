//! Stage 4 against mathematics: the render's per-pixel stratified sample sets (`render::rng`,
//! scrambled Hammersley points shared by the pixel's samples) stay unbiased and converge faster
//! than independent sampling on a smooth integrand.
//!
//! A 0.6 × 0.3 area light of radiance 3 over a white Lambertian receiver, wholly visible: the
//! radiance at the receiver is `L_e · E / π` with `E` from Lambert's polygon formula. Each
//! "pixel" takes its `N` samples (`Sampler::for_pixel_sample`, sample `i` of `N`); 64 pixels
//! (independent scrambles) give the RMSE. Independent samples would lose a
//! factor 4 of RMSE from 16 to 256 samples (1/√N); the stratified sequence must lose more than
//! 8 (a slope steeper than −¾), and the mean over all pixels must match the closed form within
//! 4 standard errors.

mod render_common;

use std::f32::consts::PI;

use glam::{Mat4, Vec3};
use render_common::*;
use scnc::bvh::AccelKind;
use scnc::geom::Ray;
use scnc::render::integrator::{radiance, RayCounts};
use scnc::render::rng::Sampler;
use scnc::scene::Scene;

/// Irradiance at `p` (unit normal `n`) from a uniform Lambertian polygon of radiance 1 wholly
/// above `p`'s horizon (Lambert 1760): `E = ½ Σ βᵢ n·γᵢ`.
fn polygon_irradiance(p: Vec3, n: Vec3, polygon: &[Vec3]) -> f64 {
    let mut sum = 0.0f64;
    for i in 0..polygon.len() {
        let a = (polygon[i] - p).as_dvec3().normalize();
        let b = (polygon[(i + 1) % polygon.len()] - p)
            .as_dvec3()
            .normalize();
        sum += a.dot(b).clamp(-1.0, 1.0).acos() * n.as_dvec3().dot(a.cross(b).normalize());
    }
    (sum / 2.0).abs()
}

fn scene(le: f32) -> (Scene, Ray, f64) {
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 3.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
        settings(4, 4, 1),
    );
    desc.meshes = vec![quad("receiver", 0.1, 0.1), quad("panel", 0.6, 0.3)];
    desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
    let p = Vec3::new(0.35, 0.2, -0.1);
    desc.objects = vec![object(0, 0, Mat4::from_translation(p))];
    let facing_down = Mat4::from_translation(centre) * Mat4::from_rotation_x(PI);
    desc.lights = vec![area_light(1, facing_down, le, false, 1)];
    let corners: Vec<Vec3> = [(-0.3, -0.15), (0.3, -0.15), (0.3, 0.15), (-0.3, 0.15)]
        .iter()
        .map(|&(x, z)| centre + Vec3::new(x, 0.0, z))
        .collect();
    let expected = f64::from(le) * polygon_irradiance(p, Vec3::Y, &corners) / std::f64::consts::PI;
    let eye = p + Vec3::new(0.01, 0.03, 0.0);
    (
        build(&desc, AccelKind::Bvh),
        Ray::new(eye, (p - eye).normalize()),
        expected,
    )
}

/// Per-pixel means of `n` samples for `pixels` pixels.
fn pixel_means(scene: &Scene, ray: &Ray, n: u32, pixels: u32) -> Vec<f64> {
    let mut counts = RayCounts::default();
    (0..pixels)
        .map(|px| {
            (0..n)
                .map(|i| {
                    let mut sampler = Sampler::for_pixel_sample(11, px, 7, i, n);
                    f64::from(radiance(scene, ray, &mut sampler, &mut counts).x)
                })
                .sum::<f64>()
                / f64::from(n)
        })
        .collect()
}

#[test]
fn stratified_sequence_is_unbiased_and_converges_faster_than_one_over_root_n() {
    let (scene, ray, expected) = scene(3.0);
    let pixels = 64;
    let rmse = |n: u32| {
        let means = pixel_means(&scene, &ray, n, pixels);
        let mean = means.iter().sum::<f64>() / f64::from(pixels);
        let var = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / f64::from(pixels - 1);
        let se = (var / f64::from(pixels)).sqrt();
        // Unbiased: the mean of the pixel estimates matches the closed form.
        assert!(
            (mean - expected).abs() <= 4.0 * se + 1e-6 * expected,
            "{n} spp: mean {mean} vs {expected} (se {se})"
        );
        let e2 = means.iter().map(|m| (m - expected).powi(2)).sum::<f64>() / f64::from(pixels);
        e2.sqrt() / expected
    };
    let (e16, e256) = (rmse(16), rmse(256));
    println!(
        "relative RMSE: 16 spp {e16:.2e}, 256 spp {e256:.2e}, ratio {:.1}",
        e16 / e256
    );
    assert!(
        e16 / e256 > 8.0,
        "16 → 256 spp: RMSE {e16:.3e} → {e256:.3e}"
    );
}
