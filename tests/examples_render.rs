//! Every example renders: each `examples/*.scn` is compiled, built and rendered small, and the
//! image is summarised for an insta snapshot (size, FNV-1a of the 8-bit output, mean linear
//! radiance, an 8×8 thumbnail). The snapshot catches any change bit for bit; a small golden PNG
//! per example (tests/golden/) measures how far a change moved the picture, so a reviewer can
//! tell a rounding ripple from a broken renderer.
//!
//! After an intended change: `INSTA_UPDATE=always SCNC_BLESS=1 cargo test --test examples_render`
//! rewrites the snapshots and goldens; review both before committing.

use std::fmt::Write;
use std::path::Path;
use std::sync::atomic::AtomicBool;

use scnc::assets::FsLoader;
use scnc::compile::compile_file;
use scnc::diag::render_plain_all;
use scnc::film::{tonemap, Film};
use scnc::render::{render, RenderOptions};
use scnc::scene::{build, BuildOptions};

/// Width of the test renders; height keeps the example's aspect ratio.
const WIDTH: u32 = 48;
const SPP: u32 = 4;
/// Largest mean absolute difference from the golden image, in 8-bit steps, that still passes.
const GOLDEN_MEAN_TOLERANCE: f64 = 1.0;

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn to_srgb8(film: &Film, exposure: f32, curve: scnc::ir::ToneMap) -> Vec<u8> {
    film.pixels()
        .iter()
        .flat_map(|&p| tonemap::to_srgb8(p, exposure, curve))
        .collect()
}

fn summary(film: &Film, rgb8: &[u8]) -> String {
    let (w, h) = (film.width() as usize, film.height() as usize);
    let mean = film.mean();
    let mut s = String::new();
    let _ = writeln!(s, "size: {w}x{h}, {SPP} spp");
    let _ = writeln!(s, "fnv1a(rgb8): {:016x}", fnv1a(rgb8));
    let _ = writeln!(
        s,
        "mean radiance: ({:.4}, {:.4}, {:.4})",
        mean.x, mean.y, mean.z
    );
    let _ = writeln!(s, "thumbnail 8x8 (mean sRGB8 luma per block):");
    for by in 0..8 {
        let mut row = String::new();
        for bx in 0..8 {
            let (x0, x1) = (bx * w / 8, ((bx + 1) * w / 8).max(bx * w / 8 + 1));
            let (y0, y1) = (by * h / 8, ((by + 1) * h / 8).max(by * h / 8 + 1));
            let (mut sum, mut n) = (0u32, 0u32);
            for y in y0..y1.min(h) {
                for x in x0..x1.min(w) {
                    let i = 3 * (y * w + x);
                    let luma = (2126 * u32::from(rgb8[i])
                        + 7152 * u32::from(rgb8[i + 1])
                        + 722 * u32::from(rgb8[i + 2]))
                        / 10000;
                    sum += luma;
                    n += 1;
                }
            }
            let _ = write!(row, " {:02x}", sum / n.max(1));
        }
        let _ = writeln!(s, "{}", row.trim_start());
    }
    s
}

/// Compares with tests/golden/NAME.png (written when SCNC_BLESS is set); returns the mean and
/// largest absolute difference in 8-bit steps.
fn compare_with_golden(name: &str, w: u32, h: u32, rgb8: &[u8]) -> (f64, u8) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.png"));
    if std::env::var_os("SCNC_BLESS").is_some() {
        image::save_buffer(&path, rgb8, w, h, image::ExtendedColorType::Rgb8)
            .expect("tests/golden is writable when blessing");
    }
    let golden = image::open(&path)
        .unwrap_or_else(|e| {
            panic!(
                "golden {} missing or unreadable ({e}); run with SCNC_BLESS=1",
                path.display()
            )
        })
        .to_rgb8();
    assert_eq!(
        (golden.width(), golden.height()),
        (w, h),
        "{name}: golden size differs"
    );
    let mut total = 0u64;
    let mut worst = 0u8;
    for (a, b) in golden.as_raw().iter().zip(rgb8) {
        let d = a.abs_diff(*b);
        total += u64::from(d);
        worst = worst.max(d);
    }
    (total as f64 / rgb8.len() as f64, worst)
}

#[test]
fn every_example_renders_and_matches_its_summary_and_golden() {
    insta::glob!("../examples", "*.scn", |path| {
        let rel = path
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap_or(path);
        let name = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("example");
        let loader = FsLoader::new();
        let compiled = compile_file(rel, &loader);
        let text = render_plain_all(&compiled.diagnostics, &compiled.sources, 100);
        let mut desc = compiled
            .scene
            .unwrap_or_else(|| panic!("{name} does not compile:\n{text}"));
        let aspect = desc.render.height as f32 / desc.render.width as f32;
        desc.render.width = WIDTH;
        desc.render.height = ((WIDTH as f32 * aspect).round() as u32).max(1);
        desc.render.fix_samples(SPP);
        let scene = build(&desc, &loader, &BuildOptions::default())
            .into_result()
            .map(|(scene, _)| scene)
            .unwrap_or_else(|d| {
                panic!(
                    "{name} does not build:\n{}",
                    render_plain_all(&d, &compiled.sources, 100)
                )
            });
        let options = RenderOptions { threads: Some(2) };
        let (film, _) =
            render(&scene, &options, &|_| {}, &AtomicBool::new(false)).expect("not cancelled");
        assert!(
            film.pixels().iter().all(|p| p.is_finite()),
            "{name}: non-finite radiance"
        );
        assert!(
            film.mean().max_element() > 0.0,
            "{name}: the image is black"
        );
        let rgb8 = to_srgb8(&film, scene.settings.exposure, scene.settings.tonemap);
        let (mean_diff, worst) = compare_with_golden(name, film.width(), film.height(), &rgb8);
        assert!(
            mean_diff <= GOLDEN_MEAN_TOLERANCE,
            "{name}: the image moved by {mean_diff:.3} 8-bit steps on average (worst pixel {worst}) from tests/golden/{name}.png"
        );
        insta::assert_snapshot!(summary(&film, &rgb8));
    });
}
