//! Image textures, mip levels and normal maps (issue 4), end to end from `.scn` text:
//! - the mip level from ray cones at a known distance and angle equals the closed form;
//! - a checkerboard plane to the horizon at 4 spp: trilinear's error against a 1024-spp
//!   reference is at most half of nearest's; the default (anisotropic) filter's is at most
//!   nearest's in every band of rows, at most half of it next to the horizon and at most 0.8×
//!   overall (issue 20; figures in `docs/textures.md`);
//! - the default filter's error keeps falling with samples (log-log slope of MSE against spp,
//!   as `tests/quality.rs` does for cornell): the footprint shrinks as max(1/8, 1/√spp);
//! - a flat image renders the same bits under every filter; `--stats`' anisotropic lookups
//!   and taps are counted for the default filter and are zero for the others;
//! - a flat normal map renders the image of no normal map; a uniformly tilted one gives the
//!   closed-form shading of the tilted normal;
//! - bad texture files are diagnostics at the path literal, never panics; a textured mesh
//!   without UVs is a warning at the object.

use std::io::Cursor;
use std::sync::atomic::AtomicBool;

use glam::Vec3;
use image::{DynamicImage, ImageFormat};
use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::diag::{Diagnostic, Severity};
use scnc::geom::Ray;
use scnc::render::{render, RenderOptions};
use scnc::scene::{build, BuildOptions, Scene};
use scnc::shade::surface::surface_hit;
use scnc::shade::texture::footprint::{pixel_spread_angle, uv_footprint};
use scnc::shade::Texture;

fn encode(img: DynamicImage, format: ImageFormat) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    img.write_to(&mut out, format).expect("encodes");
    out.into_inner()
}

/// A `size`-texel checkerboard PNG with `squares` squares per side (white and black).
fn checker_png(size: u32, squares: u32) -> Vec<u8> {
    let cell = size / squares;
    let img = image::RgbImage::from_fn(size, size, |x, y| {
        let v = if (x / cell + y / cell).is_multiple_of(2) {
            255
        } else {
            0
        };
        image::Rgb([v, v, v])
    });
    encode(DynamicImage::ImageRgb8(img), ImageFormat::Png)
}

/// A 4 × 4 float normal map holding `n · ½ + ½` everywhere.
fn normal_exr(n: Vec3) -> Vec<u8> {
    let c = n * 0.5 + Vec3::splat(0.5);
    let img = image::Rgb32FImage::from_pixel(4, 4, image::Rgb([c.x, c.y, c.z]));
    encode(DynamicImage::ImageRgb32F(img), ImageFormat::OpenExr)
}

/// The build's scene and warnings (or every diagnostic), and the compile's codes.
#[allow(clippy::type_complexity, reason = "a test helper's one-off shape")]
fn try_build(
    src: &str,
    loader: &MemLoader,
) -> (Result<(Scene, Vec<Diagnostic>), Vec<Diagnostic>>, String) {
    let compiled = compile_source("scene.scn", src, loader);
    assert!(!compiled.has_errors(), "{:#?}", compiled.diagnostics);
    let desc = compiled.scene.as_ref().expect("compiles");
    let built = build(desc, loader, &BuildOptions::default()).into_result();
    let warnings: Vec<String> = compiled
        .diagnostics
        .iter()
        .map(|d| d.code.to_string())
        .collect();
    (built, warnings.join(","))
}

fn build_ok(src: &str, loader: &MemLoader) -> Scene {
    try_build(src, loader)
        .0
        .unwrap_or_else(|d| panic!("{d:#?}"))
        .0
}

fn pixels(scene: &mut Scene, spp: u32) -> Vec<Vec3> {
    scene.settings.fix_samples(spp);
    let options = RenderOptions { threads: Some(2) };
    let (film, _) = render(scene, &options, &|_| {}, &AtomicBool::new(false)).expect("renders");
    film.pixels().to_vec()
}

#[test]
fn mip_level_at_a_known_distance_and_angle_matches_the_closed_form() {
    let mut loader = MemLoader::new();
    let img = image::RgbImage::from_pixel(256, 64, image::Rgb([200, 200, 200]));
    loader.insert(
        "t.png",
        encode(DynamicImage::ImageRgb8(img), ImageFormat::Png),
    );
    let (size, height_px, fov_deg) = (4.0f32, 100u32, 30.0f32);
    for (distance, angle_deg) in [(5.0f32, 0.0f32), (5.0, 60.0), (12.5, 35.0), (0.3, 10.0)] {
        let a = angle_deg.to_radians();
        // Tilt the view in the yz-plane, looking at the quad's centre from `distance`.
        let eye = Vec3::new(0.0, a.cos(), -a.sin()) * distance;
        let src = format!(
            "scnc 1
camera main {{ eye ({}, {}, {})  target (0, 0, 0)  up (0, 0, 1)  fov {fov_deg}deg }}
texture t = image(\"t.png\") {{ filter trilinear }}
material m = phong {{ diffuse t  specular 0 }}
mesh floor = quad {{ size ({size}, {size}) }}
object floor {{ material m }}
light l = point {{ position (0, 3, 0)  intensity 1 }}
render {{ resolution {height_px} x {height_px} }}
",
            eye.x, eye.y, eye.z
        );
        let scene = build_ok(&src, &loader);
        let dir = (-eye).normalize();
        let ray = Ray::new(eye, dir);
        let hit = scene.accel.as_ref().and_then(|a| a.closest_hit(&ray));
        let hit = surface_hit(&scene, &hit.expect("hits the quad")).expect("valid");
        let footprint = uv_footprint(&scene, &hit, dir, 1.0);
        let Some(Texture::Image { data, .. }) = &scene.textures.slots[0] else {
            panic!("an image texture");
        };
        // The longer (major) axis: along the view, stretched by 1/cos θ.
        let lod = footprint.width().log2() + 0.5 * (data.size().x * data.size().y).log2();
        // Closed form: one pixel's cone (α·d wide) stretched by 1/cos θ, in texels: the quad
        // maps `size` world units to 1 UV unit, i.e. to √(256·64) = 128 texels.
        let alpha = (2.0 * (fov_deg.to_radians() / 2.0).tan() / height_px as f32).atan();
        assert!((pixel_spread_angle(fov_deg.to_radians(), height_px) - alpha).abs() < 1e-9);
        let expected = (alpha * distance / a.cos() * 128.0 / size).log2();
        assert!(
            (lod - expected).abs() < 0.05,
            "d {distance} θ {angle_deg}: λ {lod}, closed form {expected}"
        );
        assert_eq!(data.levels.len(), 9, "256 × 64 down to 1 × 1");
        // The minor axis is the cone's width across the view, not stretched by the angle.
        let across = alpha * distance / size;
        let minor = footprint.minor.length();
        assert!(
            (minor / across - 1.0).abs() < 0.01,
            "d {distance} θ {angle_deg}: minor {minor}, closed form {across}"
        );
    }
}

fn horizon(filter: &str) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, 1, 0)  target (0, 0.55, 10)  up (0, 1, 0)  fov 50deg }}
texture board = image(\"checker.png\") {{ filter {filter}  wrap repeat }}
material m = phong {{ diffuse board  specular 0 }}
mesh floor = inline {{
  positions [(-400, 0, -1) (400, 0, -1) (400, 0, 800) (-400, 0, 800)]
  uvs [(-400, -1) (400, -1) (400, 800) (-400, 800)]
  indices [0 2 1  0 3 2]
}}
object floor {{ material m }}
light sun = point {{ position (0, 100000, 0)  intensity 31415926535 }}
render {{ resolution 48 x 32 }}
"
    )
}

fn rmse(a: &[Vec3], b: &[Vec3]) -> f32 {
    let sum: f32 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).length_squared() / 3.0)
        .sum();
    (sum / a.len() as f32).sqrt()
}

#[test]
fn trilinear_halves_the_horizon_error_of_nearest_at_four_samples() {
    let mut loader = MemLoader::new();
    // 64 texels, 8 squares per UV unit (one UV unit per metre).
    loader.insert("checker.png", checker_png(64, 8));
    let mut nearest = build_ok(&horizon("nearest"), &loader);
    let mut trilinear = build_ok(&horizon("trilinear"), &loader);
    // Nearest lookups point-sample the texture itself: at many samples they converge to the
    // exact pixel average of the checkerboard.
    let reference = pixels(&mut nearest, 1024);
    let e_nearest = rmse(&pixels(&mut nearest, 4), &reference);
    let e_trilinear = rmse(&pixels(&mut trilinear, 4), &reference);
    println!("horizon RMSE at 4 spp: nearest {e_nearest:.4}, trilinear {e_trilinear:.4}");
    assert!(e_nearest > 0.01, "the test must alias: {e_nearest}");
    assert!(
        e_trilinear <= 0.5 * e_nearest,
        "trilinear {e_trilinear} vs nearest {e_nearest}"
    );
}

/// RMSE within rows `rows` of a `width`-wide image.
fn rmse_rows(a: &[Vec3], b: &[Vec3], width: usize, rows: std::ops::Range<usize>) -> f32 {
    let range = rows.start * width..rows.end * width;
    rmse(&a[range.clone()], &b[range])
}

#[test]
fn the_default_filter_beats_nearest_in_every_band_at_four_samples() {
    let mut loader = MemLoader::new();
    loader.insert("checker.png", checker_png(64, 8));
    let mut nearest = build_ok(&horizon("nearest"), &loader);
    let mut default = build_ok(&horizon("anisotropic"), &loader);
    nearest.settings.seed = 99;
    let reference = pixels(&mut nearest, 1024);
    nearest.settings.seed = 0;
    let (n4, d4) = (pixels(&mut nearest, 4), pixels(&mut default, 4));
    // 48 × 32, horizon at row 14: rows 14..32 are ground, nearest to farthest from the bottom.
    let bands = [(26, 32, 1.0), (20, 26, 1.0), (16, 20, 1.0), (14, 16, 0.5)];
    for (lo, hi, ratio) in bands {
        let (en, ed) = (
            rmse_rows(&n4, &reference, 48, lo..hi),
            rmse_rows(&d4, &reference, 48, lo..hi),
        );
        println!("rows {lo}..{hi}: nearest {en:.4}, default {ed:.4}");
        assert!(
            ed <= ratio * en,
            "rows {lo}..{hi}: default {ed} vs nearest {en}"
        );
    }
    let (en, ed) = (rmse(&n4, &reference), rmse(&d4, &reference));
    println!("all: nearest {en:.4}, default {ed:.4}");
    assert!(ed <= 0.8 * en, "default {ed} vs nearest {en}");
}

#[test]
fn the_default_filters_error_falls_with_samples() {
    let mut loader = MemLoader::new();
    loader.insert("checker.png", checker_png(64, 8));
    let mut nearest = build_ok(&horizon("nearest"), &loader);
    let mut default = build_ok(&horizon("anisotropic"), &loader);
    nearest.settings.seed = 1_000_003;
    let reference = pixels(&mut nearest, 4096);
    let counts = [4u32, 16, 64, 256];
    let mse: Vec<f64> = counts
        .iter()
        .map(|&spp| {
            let seeds = 2;
            (0..seeds)
                .map(|k| {
                    default.settings.seed = 17 + k;
                    f64::from(rmse(&pixels(&mut default, spp), &reference)).powi(2)
                })
                .sum::<f64>()
                / seeds as f64
        })
        .collect();
    // Least-squares slope of log MSE against log spp.
    let pts: Vec<(f64, f64)> = counts
        .iter()
        .zip(&mse)
        .map(|(&n, &e)| (f64::from(n).ln(), e.ln()))
        .collect();
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / 4.0, b + y / 4.0));
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    let slope = sxy / sxx;
    println!("default filter MSE {mse:?}, log-log slope {slope:.3}");
    assert!(
        slope <= -0.6,
        "the error must keep falling with samples: slope {slope}"
    );
    for w in mse.windows(2) {
        assert!(w[1] < w[0], "MSE must fall at every step: {mse:?}");
    }
}

#[test]
fn a_flat_image_renders_identically_under_every_filter() {
    let mut loader = MemLoader::new();
    let img = image::RgbImage::from_pixel(37, 21, image::Rgb([180, 90, 40]));
    loader.insert(
        "checker.png",
        encode(DynamicImage::ImageRgb8(img), ImageFormat::Png),
    );
    let mut images = ["nearest", "bilinear", "trilinear", "anisotropic"]
        .map(|filter| pixels(&mut build_ok(&horizon(filter), &loader), 4));
    let first = std::mem::take(&mut images[0]);
    for (k, other) in images.iter().enumerate().skip(1) {
        assert!(
            first == *other,
            "filter {k} differs from nearest on a flat image"
        );
    }
    assert!(first.iter().any(|p| p.x > 0.0), "the ground is lit");
}

#[test]
fn stats_count_anisotropic_lookups_only_for_mip_filtered_textures() {
    let mut loader = MemLoader::new();
    loader.insert("checker.png", checker_png(64, 8));
    let options = RenderOptions { threads: Some(2) };
    let counts = |filter: &str| {
        let mut scene = build_ok(&horizon(filter), &loader);
        scene.settings.fix_samples(4);
        let (_, stats) =
            render(&scene, &options, &|_| {}, &AtomicBool::new(false)).expect("renders");
        stats.counts
    };
    let aniso = counts("anisotropic");
    assert!(aniso.textured > 0);
    // The horizon view is grazing almost everywhere: most lookups take several taps.
    assert!(aniso.filter.anisotropic * 2 > aniso.textured, "{aniso:?}");
    let mean = aniso.filter.mean_taps();
    assert!((2.0..=16.0).contains(&mean), "mean taps {mean}");
    for filter in ["nearest", "bilinear", "trilinear"] {
        let c = counts(filter);
        assert_eq!(c.filter.anisotropic, 0, "{filter}");
        assert_eq!(c.filter.taps, 0, "{filter}");
    }
}

#[test]
fn adaptive_textured_renders_filter_per_batch_and_are_the_same_bits_on_any_thread_count() {
    let mut loader = MemLoader::new();
    loader.insert("checker.png", checker_png(64, 8));
    let mut scene = build_ok(&horizon("anisotropic"), &loader);
    // Each batch of 16 filters with the footprint of the samples taken by its end.
    scene.settings.noise = Some(0.02);
    scene.settings.max_samples = Some(64);
    let run = |threads| {
        let options = RenderOptions {
            threads: Some(threads),
        };
        let (film, stats) =
            render(&scene, &options, &|_| {}, &AtomicBool::new(false)).expect("renders");
        (film.pixels().to_vec(), stats.counts.filter)
    };
    let (one, filter_one) = run(1);
    let (three, filter_three) = run(3);
    assert!(
        one == three,
        "adaptive textured render differs across thread counts"
    );
    assert_eq!(filter_one, filter_three);
    assert!(filter_one.anisotropic > 0);
}

fn lit_plane(normal_map: &str) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, 3, 0)  target (0, 0, 0)  up (0, 0, 1)  fov 20deg }}
texture bumps = image(\"n.exr\") {{ encoding data  filter bilinear }}
material m = phong {{ diffuse 0.5  specular 0  {normal_map} }}
mesh floor = quad {{ size (4, 4) }}
object floor {{ material m }}
light bulb = point {{ position (1, 2, 0)  intensity 10 }}
render {{ resolution 1 x 1  samples 1 }}
"
    )
}

#[test]
fn a_flat_normal_map_changes_nothing_and_a_tilted_one_shades_in_closed_form() {
    let mut loader = MemLoader::new();
    loader.insert("n.exr", normal_exr(Vec3::Z));
    let mut plain = lit_plane("").replace("1 x 1  samples 1", "8 x 8  samples 4");
    plain = plain.replace("texture bumps", "texture unused");
    let flat = lit_plane("normal_map bumps").replace("1 x 1  samples 1", "8 x 8  samples 4");
    let (a, b) = (
        pixels(&mut build_ok(&plain, &loader), 4),
        pixels(&mut build_ok(&flat, &loader), 4),
    );
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (*x - *y).abs().max_element() <= 1e-5 * x.max_element(),
            "{x} vs {y}"
        );
    }

    // The quad's tangent is +x (u), its bitangent −z (v) and its normal +y: a map normal
    // (sin θ, 0, cos θ) is the world normal (sin θ, cos θ, 0).
    for (theta_deg, green) in [(30.0f32, "opengl"), (-40.0, "opengl"), (20.0, "directx")] {
        let th = theta_deg.to_radians();
        let mut loader = MemLoader::new();
        loader.insert("n.exr", normal_exr(Vec3::new(th.sin(), 0.0, th.cos())));
        let src = lit_plane(&format!("normal_map bumps  normal_green {green}"));
        let l = pixels(&mut build_ok(&src, &loader), 1)[0];
        let wi = Vec3::new(1.0, 2.0, 0.0).normalize();
        let n = Vec3::new(th.sin(), th.cos(), 0.0);
        let expected = 0.5 / std::f32::consts::PI * 10.0 * n.dot(wi).max(0.0) / 5.0;
        assert!(
            (l.x - expected).abs() < 1e-4 * expected.max(1e-3),
            "θ {theta_deg}: {l} vs {expected}"
        );
    }
    // A map tilted along v: DirectX flips its green, so the tilt points the other way.
    let mut loader = MemLoader::new();
    let th = 40f32.to_radians();
    loader.insert("n.exr", normal_exr(Vec3::new(0.0, th.sin(), th.cos())));
    let light_along_v = |green: &str| {
        let src = lit_plane(&format!("normal_map bumps  normal_green {green}"))
            .replace("position (1, 2, 0)", "position (0, 2, -1)");
        pixels(&mut build_ok(&src, &loader), 1)[0].x
    };
    let (gl, dx) = (light_along_v("opengl"), light_along_v("directx"));
    let wi = Vec3::new(0.0, 2.0, -1.0).normalize();
    let toward = Vec3::new(0.0, th.cos(), -th.sin()).dot(wi);
    let away = Vec3::new(0.0, th.cos(), th.sin()).dot(wi);
    let k = 0.5 / std::f32::consts::PI * 10.0 / 5.0;
    assert!(
        (gl - k * toward).abs() < 1e-4 && (dx - k * away).abs() < 1e-4,
        "{gl} {dx}"
    );
}

#[test]
fn a_normal_map_facing_away_never_gives_black_or_non_finite_pixels() {
    // Grazing camera, normals tilted hard away from it: the mapped normal would face away from
    // the viewer without the reflection fix, and a light at the eye would leave it black.
    let mut loader = MemLoader::new();
    let th = 80f32.to_radians();
    loader.insert("n.exr", normal_exr(Vec3::new(0.0, -th.sin(), th.cos())));
    let src = "scnc 1
camera main { eye (0, 0.3, -6)  target (0, 0, 0)  up (0, 1, 0)  fov 30deg }
texture bumps = image(\"n.exr\") { encoding data }
material m = phong { diffuse 0.5  specular 0.3  shininess 20  normal_map bumps }
mesh floor = quad { size (40, 40) }
object floor { material m }
light bulb = point { position (0, 0.3, -6)  intensity 30 }
render { resolution 16 x 8 }
";
    let mut scene = build_ok(src, &loader);
    let px = pixels(&mut scene, 4);
    // The rows below the horizon see the floor; every one of their pixels is lit.
    for (i, p) in px.iter().enumerate().skip(16 * 5) {
        assert!(p.is_finite() && p.max_element() > 0.0, "pixel {i}: {p}");
    }
}

fn error_at(src: &str, loader: &MemLoader) -> Vec<(String, &'static str)> {
    let compiled = compile_source("scene.scn", src, loader);
    let desc = compiled.scene.as_ref().expect("compiles");
    let diags = build(desc, loader, &BuildOptions::default())
        .into_result()
        .expect_err("the texture is bad");
    diags
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .map(|d| {
            let at = compiled
                .sources
                .snippet(d.primary.as_ref().expect("labelled").span);
            (at.to_string(), d.code.as_str())
        })
        .collect()
}

#[test]
fn bad_texture_files_are_diagnostics_at_the_path() {
    let good = checker_png(8, 2);
    let mut loader = MemLoader::new();
    loader.insert("garbage.png", b"not an image at all".to_vec());
    loader.insert("cut.png", good[..good.len() / 2].to_vec());
    loader.insert("empty.png", Vec::new());
    loader.insert("zero.png", png_header(0, 16));
    loader.insert("huge.png", png_header(100_000, 8));
    for (file, code) in [
        ("missing.png", "scnc::build::missing_file"),
        ("garbage.png", "scnc::build::corrupt_image"),
        ("cut.png", "scnc::build::corrupt_image"),
        ("empty.png", "scnc::build::corrupt_image"),
        ("zero.png", "scnc::build::corrupt_image"),
        ("huge.png", "scnc::build::image_too_large"),
    ] {
        let src = format!(
            "scnc 1
camera main {{ eye (0, 2, -3)  target (0, 0, 0) }}
texture t = image(\"{file}\")
material m = phong {{ diffuse t }}
mesh floor = quad {{ size 2 }}
object floor {{ material m }}
light l = point {{ position (0, 3, 0)  intensity 1 }}
"
        );
        assert_eq!(
            error_at(&src, &loader),
            [(format!("\"{file}\""), code)],
            "{file}"
        );
    }
}

#[test]
fn warnings_for_a_colour_normal_map_and_a_textured_mesh_without_uvs() {
    let mut loader = MemLoader::new();
    loader.insert("n.png", checker_png(8, 2));
    let src = "scnc 1
camera main { eye (0, 2, -3)  target (0, 0, 0) }
texture bumps = image(\"n.png\")
material m = phong { diffuse bumps  normal_map bumps }
mesh tri = inline { positions [(0, 0, 0) (1, 0, 0) (0, 0, 1)]  indices [0 2 1] }
object tri { material m }
light l = point { position (0, 3, 0)  intensity 1 }
render { resolution 4 x 4 }
";
    let (built, front) = try_build(src, &loader);
    assert!(front.contains("scnc::check::srgb_normal_map"), "{front}");
    let (mut scene, warnings) = built.expect("warnings only");
    let codes: Vec<&str> = warnings.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["scnc::build::no_uvs"]);
    assert!(scene.tangents.iter().all(Vec::is_empty));
    assert!(pixels(&mut scene, 1).iter().all(|p| p.is_finite()));
}

/// A PNG signature, an IHDR chunk claiming `w × h`, an empty IDAT and IEND.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend(w.to_be_bytes());
    ihdr.extend(h.to_be_bytes());
    ihdr.extend([8, 2, 0, 0, 0]);
    for (kind, data) in [(&b"IHDR"[..], &ihdr[..]), (b"IDAT", &[]), (b"IEND", &[])] {
        out.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        let crc = crc32(&body);
        out.extend(body);
        out.extend(crc.to_be_bytes());
    }
    out
}
