//! Benchmark (a program, not a test): how texture filters converge on the scene of issue 20, a
//! checker image repeated over a large ground plane seen from eye height towards the horizon.
//!
//! Two harnesses, both against a `nearest` reference at 1,024 samples per pixel (the pixel-box
//! integral of the true checker):
//! - **filter-only**: camera rays → hit → footprint (scaled by `footprint_scale(spp)`) → one
//!   lookup per sample with each method: nearest, trilinear, anisotropic multi-tap, EWA. The
//!   ground is lit uniformly, so this is the texture's error alone, and the only place the two
//!   anisotropic methods can be compared in the same run. RMSE per sample count, and at 4 spp
//!   per band of distance along the ground;
//! - **renders**: the renderer itself (`render::render`, two threads) with `filter nearest`,
//!   `trilinear` and `anisotropic`, RMSE and wall time per sample count, and the time to reach
//!   the error `nearest` has at 64 spp (log-log interpolation).
//!
//! Run: `cargo bench --bench texture_quality`. Figures go in `docs/textures.md`.

use std::io::Cursor;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use glam::{Vec2, Vec3, Vec4};
use image::{DynamicImage, ImageFormat};
use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::ir::Filter;
use scnc::render::camera::PinholeCamera;
use scnc::render::rng::Sampler;
use scnc::render::{render, RenderOptions};
use scnc::scene::{build, BuildOptions, Scene};
use scnc::shade::surface::surface_hit;
use scnc::shade::texture::anisotropic::{ewa, multi_tap};
use scnc::shade::texture::footprint::{footprint_scale, uv_footprint};
use scnc::shade::texture::image::ImageData;
use scnc::shade::texture::FilterStats;
use scnc::shade::Texture;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 100;
/// Distance bands along the ground (metres from the eye's foot), for the per-band table.
/// The image's bottom row sees the ground about 3 m away.
const BANDS: [(f32, f32); 5] = [
    (0.0, 5.0),
    (5.0, 10.0),
    (10.0, 30.0),
    (30.0, 100.0),
    (100.0, f32::INFINITY),
];

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
    let mut out = Cursor::new(Vec::new());
    let _ = DynamicImage::ImageRgb8(img).write_to(&mut out, ImageFormat::Png);
    out.into_inner()
}

fn horizon(filter: &str) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, 1.6, 0)  target (0, 1.1, 10)  up (0, 1, 0)  fov 50deg }}
texture board = image(\"checker.png\") {{ filter {filter}  wrap repeat }}
material m = phong {{ diffuse board  specular 0 }}
mesh floor = inline {{
  positions [(-2000, 0, -1) (2000, 0, -1) (2000, 0, 4000) (-2000, 0, 4000)]
  uvs [(-2000, -1) (2000, -1) (2000, 4000) (-2000, 4000)]
  indices [0 2 1  0 3 2]
}}
object floor {{ material m }}
light sun = point {{ position (0, 100000, 0)  intensity 31415926535 }}
render {{ resolution {WIDTH} x {HEIGHT} }}
"
    )
}

fn scene(filter: &str, loader: &MemLoader) -> Option<Scene> {
    let compiled = compile_source("horizon.scn", &horizon(filter), loader);
    let desc = compiled.scene.as_ref()?;
    build(desc, loader, &BuildOptions::default())
        .into_result()
        .ok()
        .map(|(s, _)| s)
}

#[derive(Clone, Copy, Debug)]
enum Method {
    Nearest,
    Trilinear,
    MultiTap,
    Ewa,
}

/// One lookup-per-sample image (grey: the red channel) and each pixel's ground distance.
fn filter_only(scene: &Scene, method: Method, spp: u32, seed: u64) -> (Vec<f32>, Vec<f32>) {
    let Some(Texture::Image { data, wrap, .. }) = scene.textures.slots[0].as_ref() else {
        return (Vec::new(), Vec::new());
    };
    let camera = PinholeCamera::new(&scene.camera, WIDTH, HEIGHT);
    let side = (spp as f32).sqrt().round().max(1.0) as u32;
    let scale = footprint_scale(side * side);
    let mut stats = FilterStats::default();
    let mut image = Vec::new();
    let mut distance = Vec::new();
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let centre = camera.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let hit = scene.accel.as_ref().and_then(|a| a.closest_hit(&centre));
            distance.push(hit.map_or(f32::INFINITY, |h| {
                let p = centre.origin + centre.dir * h.t;
                Vec2::new(p.x, p.z).length()
            }));
            let mut sum = 0.0;
            for s in 0..side * side {
                let jitter = Sampler::new(seed, x, y, s).next_2d();
                let cell = Vec2::new((s % side) as f32, (s / side) as f32);
                let film = Vec2::new(x as f32, y as f32) + (cell + jitter) / side as f32;
                let ray = camera.ray(film);
                let Some(h) = scene.accel.as_ref().and_then(|a| a.closest_hit(&ray)) else {
                    continue;
                };
                let Some(hit) = surface_hit(scene, &h) else {
                    continue;
                };
                let dir = ray.dir.normalize();
                let fp = uv_footprint(scene, &hit, dir, scale);
                let v: Vec4 = match method {
                    Method::Nearest => data.at_lod(hit.uv, *wrap, Filter::Nearest, 0.0),
                    Method::Trilinear => data.trilinear(hit.uv, *wrap, data.lod(fp)),
                    Method::MultiTap => multi_tap(data, hit.uv, *wrap, fp, &mut stats),
                    Method::Ewa => ewa(data, hit.uv, *wrap, fp, &mut stats),
                };
                sum += v.x;
            }
            image.push(sum / (side * side) as f32);
        }
    }
    (image, distance)
}

fn rmse_where(a: &[f32], b: &[f32], keep: impl Fn(usize) -> bool) -> f64 {
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        if keep(i) {
            sum += f64::from(x - y).powi(2);
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

fn filter_only_tables(scene: &Scene) {
    let (reference, distance) = filter_only(scene, Method::Nearest, 1024, 2);
    let methods = [
        Method::Nearest,
        Method::Trilinear,
        Method::MultiTap,
        Method::Ewa,
    ];
    println!("filter-only RMSE vs nearest @1024 spp ({WIDTH}x{HEIGHT})");
    println!("method      4 spp    16 spp   64 spp   256 spp");
    for m in methods {
        let row: Vec<String> = [4, 16, 64, 256]
            .iter()
            .map(|&spp| {
                let (img, _) = filter_only(scene, m, spp, 1);
                format!("{:.4}", rmse_where(&img, &reference, |_| true))
            })
            .collect();
        println!("{:<11} {}", format!("{m:?}"), row.join("   "));
    }
    println!("filter-only RMSE at 4 spp by ground distance (m)");
    let at4: Vec<(Method, Vec<f32>)> = methods
        .iter()
        .map(|&m| (m, filter_only(scene, m, 4, 1).0))
        .collect();
    for (lo, hi) in BANDS {
        let keep = |i: usize| distance[i] >= lo && distance[i] < hi;
        let pixels = (0..distance.len()).filter(|&i| keep(i)).count();
        let cells: Vec<String> = at4
            .iter()
            .map(|(m, img)| format!("{m:?} {:.4}", rmse_where(img, &reference, keep)))
            .collect();
        println!("  [{lo}, {hi}) {pixels} px: {}", cells.join(", "));
    }
    let time = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        f();
        start.elapsed().as_secs_f64()
    };
    for m in methods {
        let t = time(&mut || {
            let _ = filter_only(scene, m, 16, 1);
        });
        let per = t * 1e9 / f64::from(WIDTH * HEIGHT * 16);
        println!("filter-only {m:?}: {per:.0} ns per sample (trace + footprint + lookup)");
    }
}

fn render_tables(loader: &MemLoader) {
    let Some(mut reference_scene) = scene("nearest", loader) else {
        println!("the scene did not build");
        return;
    };
    let options = RenderOptions { threads: Some(2) };
    let cancel = AtomicBool::new(false);
    let run = |scene: &mut Scene, spp: u32| {
        scene.settings.fix_samples(spp);
        let start = Instant::now();
        let (film, stats) = render(scene, &options, &|_| {}, &cancel).ok()?;
        let grey: Vec<f32> = film.pixels().iter().map(|p: &Vec3| p.x).collect();
        Some((grey, start.elapsed().as_secs_f64(), stats))
    };
    reference_scene.settings.seed = 7;
    let Some((reference, _, _)) = run(&mut reference_scene, 1024) else {
        return;
    };
    println!("renders: RMSE vs nearest @1024 spp, wall s (2 threads)");
    let mut target = 0.0;
    for filter in ["nearest", "trilinear", "anisotropic"] {
        let Some(mut s) = scene(filter, loader) else {
            continue;
        };
        let mut points = Vec::new();
        let mut line = format!("{filter:<12}");
        for spp in [4, 16, 64, 256] {
            if let Some((img, secs, stats)) = run(&mut s, spp) {
                let e = rmse_where(&img, &reference, |_| true);
                points.push((secs, e));
                let c = stats.counts;
                line += &format!(
                    "  {spp} spp {e:.4} {secs:.2}s ({} aniso, {:.1} taps)",
                    c.filter.anisotropic,
                    c.filter.mean_taps()
                );
            }
        }
        println!("{line}");
        if filter == "nearest" {
            target = points.get(2).map_or(0.0, |p| p.1);
        }
        println!("  time to RMSE {target:.4}: {}", time_to(&points, target));
    }
}

/// Log-log interpolation of the wall time at which the error reaches `target`.
fn time_to(points: &[(f64, f64)], target: f64) -> String {
    for w in points.windows(2) {
        let ((t0, e0), (t1, e1)) = (w[0], w[1]);
        if e0 >= target && e1 <= target {
            let f = (target.ln() - e0.ln()) / (e1.ln() - e0.ln());
            return format!("{:.2} s", (t0.ln() + f * (t1.ln() - t0.ln())).exp());
        }
    }
    match points.first() {
        Some(&(t, e)) if e <= target => format!("< {t:.2} s"),
        _ => "not reached by 256 spp".into(),
    }
}

fn main() {
    let mut loader = MemLoader::new();
    // 64 texels, 8 squares per UV unit (one UV unit per metre).
    loader.insert("checker.png", checker_png(64, 8));
    let Some(anisotropic) = scene("anisotropic", &loader) else {
        println!("the scene did not build");
        return;
    };
    let data: Option<&ImageData> = match anisotropic.textures.slots[0].as_ref() {
        Some(Texture::Image { data, .. }) => Some(data),
        _ => None,
    };
    println!("mip levels: {}", data.map_or(0, |d| d.levels.len()));
    filter_only_tables(&anisotropic);
    render_tables(&loader);
}
