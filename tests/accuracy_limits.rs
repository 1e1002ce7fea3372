//! The whole pipeline (`.scn` text → check → build → render → 8-bit output) at the limits of
//! what the language accepts (issue 8): fields of view from 0.001° to 179.9°, images from 1×1 to
//! the checker's maximum side (16384), an `up` nearly parallel to the view, radiance and
//! intensity up to 1e30, zero-area and vanishingly small lights. Each ends in either a clear
//! diagnostic (code, label, message) or an image with no NaN or infinity in it — never a panic
//! or a poisoned film. And NaN never reaches the film: samples that would carry it are dropped
//! and counted in `RenderStats::counts.nonfinite` (shown by `--stats`).

mod render_common;

use std::sync::atomic::AtomicBool;

use glam::{Mat4, Vec3};
use render_common::*;
use scnc::assets::MemLoader;
use scnc::bvh::AccelKind;
use scnc::compile::compile_source;
use scnc::diag::{Diagnostic, Severity};
use scnc::film::{tonemap, Film};
use scnc::ir::ToneMap;
use scnc::render::{render, RenderOptions, RenderStats};
use scnc::scene::{build as build_scene, BuildOptions};

/// What the pipeline made of `src`: an image, or the errors it reported.
fn outcome(src: &str) -> Result<(Film, RenderStats), Vec<Diagnostic>> {
    let loader = MemLoader::new();
    let compiled = compile_source("limits.scn", src, &loader);
    if compiled.has_errors() {
        return Err(compiled.diagnostics);
    }
    let mut desc = compiled.scene.expect("no errors, so a scene");
    desc.render.fix_samples(1);
    let (scene, _) = build_scene(&desc, &loader, &BuildOptions::default()).into_result()?;
    let out = render(
        &scene,
        &RenderOptions { threads: Some(2) },
        &|_| {},
        &AtomicBool::new(false),
    )
    .expect("not cancelled");
    Ok(out)
}

/// The image is finite everywhere, and so is its 8-bit output.
fn assert_finite(film: &Film, what: &str) {
    let bad = film.pixels().iter().filter(|p| !p.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite pixels");
    for curve in [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Filmic] {
        for p in film.pixels().iter().take(4096) {
            let rgb = tonemap::to_srgb8(*p, 0.0, curve);
            // A huge value is white, never black from an overflow inside the curve.
            if p.x > 1e20 {
                assert_eq!(rgb[0], 255, "{what}: {p} under {curve:?}");
            }
        }
    }
}

/// An error diagnostic with a stable code, a message and a label in the file.
fn assert_clear(diags: &[Diagnostic], code: &str, what: &str) {
    let d = diags
        .iter()
        .find(|d| d.severity == Severity::Error)
        .unwrap_or_else(|| panic!("{what}: no error in {diags:#?}"));
    assert_eq!(d.code, code, "{what}: {d:#?}");
    assert!(
        !d.message.is_empty() && d.primary.is_some(),
        "{what}: {d:#?}"
    );
}

/// A lit floor, a ball and a sky; `camera`, `lights` and `render` filled in by each test.
fn scene(camera: &str, lights: &str, render: &str) -> String {
    format!(
        "scnc 1\n{camera}\n\
         material white = phong {{ diffuse 0.8  specular 0.2  shininess 30 }}\n\
         mesh floor = quad {{ size (10, 10) }}\n\
         mesh ball = sphere {{ radius 0.5  segments 16 }}\n\
         object floor {{ material white }}\n\
         object ball {{ material white  transform {{ translate (0, 0.5, 0) }} }}\n\
         {lights}\n\
         render {{ {render} }}\n"
    )
}

const CAMERA: &str = "camera main { eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }";
const LIGHTS: &str = "light bulb = point { position (2, 3, -2)  intensity 20 }\n\
    light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 4 }";

#[test]
fn fields_of_view_from_a_thousandth_of_a_degree_to_nearly_180() {
    for fov in [
        "0.001deg", "0.01deg", "1deg", "90deg", "170deg", "179deg", "179.9deg",
    ] {
        let cam = format!("camera main {{ eye (0, 2, -5)  target (0, 0.5, 0)  fov {fov} }}");
        let (film, _) = outcome(&scene(&cam, LIGHTS, "resolution 24 x 16"))
            .unwrap_or_else(|d| panic!("fov {fov}: {d:#?}"));
        assert_finite(&film, &format!("fov {fov}"));
        // Past 90° the pixel centres look ever further sideways, past the floor.
        if fov
            .trim_end_matches("deg")
            .parse::<f32>()
            .is_ok_and(|f| f <= 90.0)
        {
            assert!(film.pixels().iter().any(|p| p.x > 0.0), "fov {fov}: black");
        }
    }
    for fov in ["0deg", "180deg", "-1deg"] {
        let cam = format!("camera main {{ eye (0, 2, -5)  target (0, 0.5, 0)  fov {fov} }}");
        let diags = outcome(&scene(&cam, LIGHTS, "resolution 4 x 4")).expect_err(fov);
        assert!(
            diags.iter().any(|d| d.severity == Severity::Error
                && d.primary.is_some()
                && d.message.contains("fov")),
            "fov {fov}: {diags:#?}"
        );
    }
}

#[test]
fn images_from_one_pixel_to_the_maximum_side() {
    for res in ["1 x 1", "1 x 16384", "16384 x 1", "3 x 7"] {
        let (film, stats) = outcome(&scene(CAMERA, LIGHTS, &format!("resolution {res}")))
            .unwrap_or_else(|d| panic!("{res}: {d:#?}"));
        assert_finite(&film, res);
        assert_eq!(stats.camera_rays, u64::from(film.width() * film.height()));
    }
    let diags = outcome(&scene(CAMERA, LIGHTS, "resolution 16385 x 1")).expect_err("too wide");
    assert!(
        diags
            .iter()
            .any(|d| d.severity == Severity::Error && d.message.contains("16384")),
        "{diags:#?}"
    );
    let diags = outcome(&scene(CAMERA, LIGHTS, "resolution 0 x 4")).expect_err("empty");
    assert!(diags.iter().any(|d| d.severity == Severity::Error));
}

#[test]
fn up_nearly_parallel_to_the_view_direction() {
    // View direction (0, -1.5, 5) normalised; `up` along it, then slightly off it.
    for (up, exact) in [
        ("(0, -1.5, 5)", true),
        ("(0, 1.5, -5)", true),
        ("(0.000001, -1.5, 5)", false),
        ("(0.001, -1.5, 5)", false),
        ("(0, -1.5, 5.0001)", false),
    ] {
        let cam =
            format!("camera main {{ eye (0, 2, -5)  target (0, 0.5, 0)  up {up}  fov 40deg }}");
        match outcome(&scene(&cam, LIGHTS, "resolution 8 x 8")) {
            Ok((film, _)) => {
                assert!(!exact, "up {up} exactly parallel must be reported");
                assert_finite(&film, &format!("up {up}"));
            }
            Err(diags) => {
                let d = diags
                    .iter()
                    .find(|d| d.severity == Severity::Error)
                    .unwrap_or_else(|| panic!("up {up}: {diags:#?}"));
                assert!(d.primary.is_some(), "up {up}: unlabelled {d:#?}");
                eprintln!("up {up}: {} — {}", d.code, d.message);
            }
        }
    }
}

#[test]
fn radiance_and_intensity_up_to_1e30_stay_finite() {
    for (what, lights) in [
        (
            "area 1e30",
            "light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 1e30 }",
        ),
        (
            "point 1e30",
            "light bulb = point { position (2, 3, -2)  intensity 1e30 }",
        ),
        (
            "point 1e30 touching the floor",
            "light bulb = point { position (0, 0.0001, -2)  intensity 1e30 }",
        ),
        (
            "sky 1e30",
            "light sky = environment { rgb(1e30, 1e30, 1e30) }",
        ),
        ("all of them", concat!(
            "light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 1e30 }\n",
            "light bulb = point { position (2, 3, -2)  intensity 1e30 }\n",
            "light sky = environment { rgb(1e30, 1e30, 1e30) }"
        )),
    ] {
        match outcome(&scene(CAMERA, lights, "resolution 16 x 12")) {
            Ok((film, stats)) => {
                assert_finite(&film, what);
                assert!(film.pixels().iter().any(|p| p.x > 1e20), "{what}: too dark");
                eprintln!("{what}: {} NaN/inf samples dropped", stats.counts.nonfinite);
            }
            Err(diags) => assert!(
                diags.iter().all(|d| d.primary.is_some()),
                "{what}: {diags:#?}"
            ),
        }
    }
}

#[test]
fn zero_area_lights_are_reported_and_tiny_ones_render() {
    let flat = "light panel = area { quad (0, 3, 0) (1, 3, 0) (2, 3, 0) (3, 3, 0)  radiance 4 }";
    let diags = outcome(&scene(CAMERA, flat, "resolution 4 x 4")).expect_err("zero area");
    assert_clear(&diags, "scnc::check::degenerate_quad", "collinear quad");

    let squashed = "mesh panel_mesh = quad { size (1, 1) }\n\
        light panel = area { mesh panel_mesh  transform { scale (1, 1, 0) translate (0, 3, 0) }  radiance 4 }";
    let diags = outcome(&scene(CAMERA, squashed, "resolution 4 x 4")).expect_err("scale 0");
    assert_clear(
        &diags,
        "scnc::check::degenerate_transform",
        "light scaled flat",
    );

    for size in ["1e-6", "1e-12", "1e-18"] {
        let tiny = format!(
            "light panel = area {{ quad (0, 3, 0) ({size}, 3, 0) ({size}, 3, {size}) (0, 3, {size})  radiance 1e30 }}"
        );
        match outcome(&scene(CAMERA, &tiny, "resolution 8 x 8")) {
            Ok((film, _)) => assert_finite(&film, &format!("light of side {size}")),
            Err(diags) => assert!(
                diags.iter().all(|d| d.primary.is_some()),
                "side {size}: {diags:#?}"
            ),
        }
    }
}

#[test]
fn nan_never_reaches_the_film_and_is_counted() {
    // Only the IR can carry a NaN (the checker rejects it in text), so write it directly: a
    // material whose ambient term is NaN on the ball and infinite on the floor.
    let mut desc = empty_desc(
        camera(
            Vec3::new(0.0, 2.0, -5.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::Y,
            40.0,
        ),
        settings(16, 16, 4),
    );
    desc.meshes = vec![
        quad("floor", 3.0, 3.0),
        builtin(
            "ball",
            scnc::ir::BuiltinShape::Sphere {
                radius: 0.5,
                segments: 12,
            },
        ),
    ];
    let mut nan = phong("nan", Vec3::ONE, 0.0, 1.0);
    nan.ambient = Vec3::new(f32::NAN, 0.0, 0.0);
    let mut inf = phong("inf", Vec3::ONE, 0.0, 1.0);
    inf.ambient = Vec3::splat(f32::INFINITY);
    desc.materials = vec![inf, nan];
    desc.objects = vec![
        object(0, 0, Mat4::IDENTITY),
        object(1, 1, Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0))),
    ];
    desc.lights = vec![point_light(Vec3::new(1.0, 3.0, -1.0), 10.0)];
    let scene = build(&desc, AccelKind::Bvh);
    let (film, stats) = render_with(&scene, 2);
    assert_finite(&film, "NaN material");
    // Every camera sample that hit either object was dropped and counted; the rest (sky) not.
    let misses = film.pixels().iter().filter(|p| **p == Vec3::ZERO).count() as u64;
    assert!(stats.counts.nonfinite > 0);
    assert!(stats.counts.nonfinite <= stats.camera_rays - misses);
    assert!(
        stats.counts.nonfinite >= (16 * 16 - misses) * 4 / 2,
        "{} dropped, {misses} empty pixels",
        stats.counts.nonfinite
    );
}
