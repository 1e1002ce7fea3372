//! Stage 4 robustness: shadow rays neither self-intersect (acne) nor start beyond a nearby
//! occluder (leaks), at scene scales from 1e-4 to 1e5 and on transformed, tilted surfaces.

mod render_common;

use std::f32::consts::FRAC_1_PI;

use glam::{Mat4, Quat, Vec2, Vec3};
use render_common::*;
use scnc::bvh::AccelKind;
use scnc::render::camera::PinholeCamera;

/// A floor at y = 0 seen from above over x ∈ [0, s]; a thin occluder at height 1e-3·s covers
/// x < 0; a point light far to the left and low (grazing, the hard case for acne) so the
/// occluder's shadow falls on x ∈ (0, 0.1·s).
#[test]
fn grazing_light_and_thin_contact_shadow_at_every_scale() {
    for s in [1e-4f32, 1.0, 1e5] {
        let mut desc = empty_desc(
            camera(
                Vec3::new(0.5 * s, 2.0 * s, 0.0),
                Vec3::new(0.5 * s, 0.0, 0.0),
                Vec3::Z,
                28.0,
            ),
            settings(32, 32, 1),
        );
        desc.meshes = vec![
            quad("floor", 4.0 * s, 4.0 * s),
            quad("lid", 2.0 * s, 4.0 * s),
        ];
        desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
        desc.objects = vec![
            object(0, 0, Mat4::IDENTITY),
            object(1, 0, Mat4::from_translation(Vec3::new(-s, 1e-3 * s, 0.0))),
        ];
        let light = Vec3::new(-100.0 * s, s, 0.0);
        let intensity = 1e4 * s * s;
        desc.lights = vec![point_light(light, intensity)];
        let (film, _) = render_with(&build(&desc, AccelKind::Bvh), 2);
        let cam = PinholeCamera::new(&desc.cameras[0], 32, 32);
        let (mut lit, mut shadowed) = (0, 0);
        for y in 0..32 {
            for x in 0..32 {
                let ray = cam.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                let p = ray.at(-ray.origin.y / ray.dir.y);
                let got = film.get(x, y).x;
                if p.x < 0.0 {
                    continue; // the camera sees the lid there
                }
                if p.x < 0.08 * s {
                    assert_eq!(
                        got,
                        0.0,
                        "scale {s}: light leaks under the lid at x = {}",
                        p.x / s
                    );
                    shadowed += 1;
                } else if p.x > 0.12 * s {
                    let to_light = light - p;
                    let r2 = to_light.length_squared();
                    let expected = FRAC_1_PI * intensity * (to_light.y / r2.sqrt()) / r2;
                    assert!(
                        (got - expected).abs() < 1e-3 * expected,
                        "scale {s}: acne at x = {}: {got} vs {expected}",
                        p.x / s
                    );
                    lit += 1;
                }
            }
        }
        assert!(
            lit > 300 && shadowed > 20,
            "scale {s}: {lit} lit, {shadowed} shadowed"
        );
    }
}

/// A plane rotated and translated far from the origin (so its hit points carry rounding
/// error in every axis), lit at a grazing angle: every visible pixel gets the full value.
#[test]
fn tilted_far_plane_has_no_acne() {
    for (offset, s) in [
        (Vec3::new(3e4, -2e4, 5e4), 100.0f32),
        (Vec3::new(1e-3, 2e-3, -1e-3), 1e-3),
    ] {
        let rotation = Quat::from_euler(glam::EulerRot::XYZ, 0.3, 0.7, -0.4);
        let normal = rotation * Vec3::Y;
        let tangent = rotation * Vec3::X;
        let mut desc = empty_desc(
            camera(
                offset + 3.0 * s * normal + 0.5 * s * tangent,
                offset,
                tangent,
                40.0,
            ),
            settings(24, 24, 1),
        );
        desc.meshes = vec![quad("floor", 20.0 * s, 20.0 * s)];
        desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
        desc.objects = vec![object(
            0,
            0,
            Mat4::from_translation(offset) * Mat4::from_quat(rotation),
        )];
        // 3° above the plane.
        let light = offset + 5.0 * s * (tangent + 0.0524 * normal);
        desc.lights = vec![point_light(light, s * s)];
        let (film, _) = render_with(&build(&desc, AccelKind::Bvh), 2);
        let dark = film.pixels().iter().filter(|p| p.x <= 0.0).count();
        assert_eq!(dark, 0, "offset {offset}: {dark} pixels in self-shadow");
    }
}

/// Irradiance is scale-invariant: an area light over a plane gives the same pixel values at
/// 1e-4, 1 and 1e5 (same seeds, both sampling strategies), so neither the shadow ray's start
/// nor its end point self-intersects at any scale.
#[test]
fn area_light_shading_is_scale_invariant() {
    use scnc::geom::Ray;
    use scnc::render::integrator::{radiance, RayCounts};
    use scnc::render::rng::Sampler;
    use scnc::scene::LightSampling;

    for sampling in [LightSampling::Area, LightSampling::SolidAngle] {
        let mut results = Vec::new();
        for s in [1e-4f32, 1.0, 1e5] {
            let mut desc = empty_desc(
                camera(Vec3::new(0.0, 4.0 * s, 0.0), Vec3::ZERO, Vec3::Z, 60.0),
                settings(4, 4, 1),
            );
            desc.meshes = vec![
                quad("floor", 20.0 * s, 20.0 * s),
                quad("panel", 0.5 * s, 0.5 * s),
            ];
            desc.materials = vec![phong("white", Vec3::ONE, 0.0, 1.0)];
            desc.objects = vec![object(0, 0, Mat4::IDENTITY)];
            let placement = Mat4::from_translation(Vec3::new(0.2 * s, s, 0.1 * s))
                * Mat4::from_rotation_x(std::f32::consts::PI);
            desc.lights = vec![area_light(1, placement, 3.0, false, 4)];
            let mut scene = build(&desc, AccelKind::Bvh);
            scene.light_sampling = sampling;
            let mut sum = 0.0f64;
            let mut counts = RayCounts::default();
            for (k, p) in [(0.0, 0.0), (0.3, -0.2), (1.5, 0.7)].iter().enumerate() {
                let p = Vec3::new(p.0 * s, 0.0, p.1 * s);
                let eye = p + Vec3::new(s, s, 0.0);
                let ray = Ray::new(eye, (p - eye).normalize());
                for i in 0..64 {
                    let mut sampler = Sampler::new(k as u64, 0, 0, i);
                    let l = radiance(&scene, &ray, &mut sampler, &mut counts).x;
                    assert!(
                        l > 0.0,
                        "{sampling:?}, scale {s}: sample {i} at {p} occluded"
                    );
                    sum += l as f64;
                }
            }
            results.push(sum);
        }
        for r in &results {
            assert!(
                (r - results[1]).abs() < 1e-3 * results[1],
                "{sampling:?}: {results:?}"
            );
        }
    }
}
