//! `scnc bench quality scene.scn [--out DIR] [--resolution WxH] [--reference-spp N]
//! [--max-spp N] [--threads N]`: the speed/accuracy curve of one scene, measured.
//!
//! Renders a high-sample reference (the progressive sampler run to `--reference-spp` samples in
//! every pixel, cached in DIR as `.reference-NAME-HASH.exr`, keyed by a
//! hash of the scene's source files, its validated IR and the reference settings; the seed
//! differs from the measured renders' so their noise is independent of the reference's), then
//! each quality preset, a sweep of fixed sample counts (1, 4, 16, … up to `--max-spp`) and
//! adaptive renders at noise targets 10%, 5%, 2% and 1%. For each: wall time, RMSE and relative
//! MSE against the reference on linear radiance (`film::compare`). Writes `NAME.csv` and a
//! log-log plot `NAME.svg` of relative RMS error against time (see `plot`), and prints the
//! table with the time to 1% relative RMS error with and without adaptive sampling.

mod plot;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;

use clap::{Args, Subcommand};

use super::render::parse_resolution;
use super::report::{report, strict, DiagArgs, JsonTo, SceneArg};
use crate::assets::FsLoader;
use crate::bvh::AccelKind;
use crate::compile::compile;
use crate::film::compare::{compare, FilmError};
use crate::film::{self, Film, WriteSettings};
use crate::ir::{Quality, SceneDesc, SettingFlags};
use crate::render::{self, RenderOptions};
use crate::scene::{self, BuildOptions, Scene};
use crate::source::SourceMap;

/// `scnc bench`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct BenchArgs {
    /// Which benchmark.
    #[command(subcommand)]
    pub what: BenchWhat,
}

/// The benchmarks.
#[derive(Debug, Clone, Subcommand)]
pub enum BenchWhat {
    /// Error against a high-sample reference, and time, for each preset, a sweep of sample
    /// counts and adaptive noise targets; CSV and a log-log SVG plot.
    Quality(QualityArgs),
}

/// `scnc bench quality`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct QualityArgs {
    /// The scene file.
    #[command(flatten)]
    pub scene: SceneArg,
    /// Directory for the CSV, the plot and the cached reference.
    #[arg(long, value_name = "DIR", default_value = "bench-quality")]
    pub out: PathBuf,
    /// Override the scene's resolution, e.g. `256x256`.
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Samples per pixel of the reference.
    #[arg(long, value_name = "N", default_value_t = 4096,
          value_parser = clap::value_parser!(u32).range(16..=65536))]
    pub reference_spp: u32,
    /// Largest sample count of the sweep.
    #[arg(long, value_name = "N", default_value_t = 1024,
          value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub max_spp: u32,
    /// Worker threads (default: every core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Diagnostic format and `--strict`.
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// One measured render.
#[derive(Debug, Clone)]
pub struct Row {
    /// `preset`, `fixed` or `adaptive`.
    pub kind: &'static str,
    /// What was rendered, for people (`preview`, `16 spp`, `noise 1%`).
    pub label: String,
    /// Samples per pixel (the mean, for adaptive renders).
    pub spp: u32,
    /// The scene's `light_samples` of the render.
    pub light_samples: u32,
    /// The noise target of an adaptive render.
    pub noise: Option<f32>,
    /// Wall time of the render.
    pub seconds: f64,
    /// Error against the reference.
    pub error: FilmError,
    /// Mean samples per pixel, unrounded.
    pub mean_spp: f64,
    /// Pixels of an adaptive render that stopped at `max_samples`.
    pub pixels_at_max: u64,
}

/// Runs the chosen benchmark.
pub fn run(args: &BenchArgs) -> ExitCode {
    match &args.what {
        BenchWhat::Quality(q) => match quality(q) {
            Ok(()) => ExitCode::SUCCESS,
            Err(message) => {
                eprintln!("error: {message}");
                ExitCode::FAILURE
            }
        },
    }
}

fn quality(args: &QualityArgs) -> Result<(), String> {
    let (sources, desc, mut scene) = compile_and_build(args)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let name = args
        .scene
        .file
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let mut key = Fnv::default();
    for (_, file) in sources.files() {
        key.write(file.text.as_bytes());
    }
    key.write(serde_json::to_string(&desc).unwrap_or_default().as_bytes());
    key.write(
        format!(
            "{} {} progressive",
            args.reference_spp,
            env!("CARGO_PKG_VERSION")
        )
        .as_bytes(),
    );
    let ref_path = args
        .out
        .join(format!(".reference-{name}-{:016x}.exr", key.0));
    let reference = reference(&mut scene, &ref_path, args)?;
    let rows = sweep(&mut scene, &reference, args)?;
    let csv_path = args.out.join(format!("{name}.csv"));
    write_file(&csv_path, csv(&name, &rows).as_bytes())?;
    let svg_path = args.out.join(format!("{name}.svg"));
    let svg = plot::svg(&name, &rows)?;
    write_file(&svg_path, svg.as_bytes())?;
    print!("{}", table(&rows));
    println!(
        "time to 1% relative RMS error: fixed {}, adaptive {}",
        fmt_time(time_to(&rows, "fixed", 0.01)),
        fmt_time(time_to(&rows, "adaptive", 0.01))
    );
    eprintln!("wrote {} and {}", csv_path.display(), svg_path.display());
    Ok(())
}

/// Compiles and builds the scene through one loader (`--resolution` resolved into its
/// settings first), reporting the diagnostics of both stages once.
fn compile_and_build(args: &QualityArgs) -> Result<(SourceMap, SceneDesc, Scene), String> {
    let loader = FsLoader::new();
    let mut sources = SourceMap::new();
    let options = BuildOptions {
        accel: AccelKind::Bvh,
        camera: None,
    };
    let flags = SettingFlags {
        resolution: args.resolution,
        ..SettingFlags::default()
    };
    let compiled = strict(compile(&args.scene.file, &loader, &mut sources), &args.diag);
    let compiled_ok = compiled.value.is_some();
    let built = compiled
        .map(|mut desc| {
            desc.render.resolve(&flags);
            desc
        })
        .and_then(|desc| scene::build(&desc, &loader, &options).map(|s| (desc, s)));
    report(&built, &sources, &args.diag, JsonTo::Stderr);
    match built.value {
        Some((desc, scene)) => Ok((sources, desc, scene)),
        None if compiled_ok => Err("the scene does not build".into()),
        None => Err("the scene does not compile".into()),
    }
}

/// Renders every point of the curve: each preset, fixed counts 1, 4, 16, … up to
/// `--max-spp`, and adaptive sampling at four noise targets.
fn sweep(scene: &mut Scene, reference: &Film, args: &QualityArgs) -> Result<Vec<Row>, String> {
    let base = scene.settings.clone();
    let mut rows = Vec::new();
    for q in Quality::ALL {
        scene.settings = base.clone();
        scene.settings.apply_quality(q);
        scene.settings.noise = None;
        rows.push(measure(scene, reference, "preset", q.name(), args)?);
    }
    let mut side = 1u32;
    while side * side <= args.max_spp {
        scene.settings = base.clone();
        scene.settings.fix_samples(side * side);
        scene.settings.light_samples = 1;
        let label = format!("{} spp", side * side);
        rows.push(measure(scene, reference, "fixed", &label, args)?);
        side *= 2;
    }
    for target in [0.1f32, 0.05, 0.02, 0.01] {
        scene.settings = base.clone();
        scene.settings.light_samples = 1;
        scene.settings.noise = Some(target);
        scene.settings.max_samples = Some(args.reference_spp);
        let label = format!("noise {}%", target * 100.0);
        rows.push(measure(scene, reference, "adaptive", &label, args)?);
    }
    scene.settings = base;
    Ok(rows)
}

/// The cached reference, or a new one (written atomically before it is used).
fn reference(scene: &mut Scene, path: &Path, args: &QualityArgs) -> Result<Film, String> {
    if let Some(film) = read_exr(path) {
        if (film.width(), film.height()) == (scene.settings.width, scene.settings.height) {
            eprintln!("reference: cached {}", path.display());
            return Ok(film);
        }
    }
    let base = scene.settings.clone();
    // The progressive sampler run to the cap in every pixel (a target no pixel reaches), not a
    // fixed count: a fixed-count render pairs each sub-pixel position with one light sample by
    // their common index, so its penumbra pixels converge to a seed-dependent value
    // (docs/quality.md); the progressive replicates converge to the independent-sample value.
    scene.settings.light_samples = 1;
    scene.settings.noise = Some(1e-7);
    scene.settings.max_samples = Some(args.reference_spp);
    // Independent of every measured render's samples.
    scene.settings.seed = base.seed ^ 0x005e_ed0f_4efe_4ece;
    let options = RenderOptions {
        threads: args.threads,
    };
    let rendered = render::render(scene, &options, &|_| {}, &AtomicBool::new(false));
    scene.settings = base;
    let (film, stats) = rendered.map_err(|_| "the reference render was cancelled".to_string())?;
    eprintln!(
        "reference: {} spp in {:.2} s, {}",
        stats.samples_per_pixel,
        stats.wall.as_secs_f64(),
        path.display()
    );
    film::write_image(
        &film,
        path,
        &WriteSettings::default(),
        film::Durability::Synced,
    )
    .map_err(|e| e.to_string())?;
    Ok(film)
}

fn read_exr(path: &Path) -> Option<Film> {
    let img = image::open(path).ok()?.into_rgb32f();
    let mut film = Film::new(img.width(), img.height());
    for (x, y, p) in img.enumerate_pixels() {
        film.set(x, y, glam::Vec3::new(p[0], p[1], p[2]));
    }
    Some(film)
}

fn measure(
    scene: &Scene,
    reference: &Film,
    kind: &'static str,
    label: &str,
    args: &QualityArgs,
) -> Result<Row, String> {
    let options = RenderOptions {
        threads: args.threads,
    };
    let r = render::render_with_error(scene, &options, &|_| {}, &AtomicBool::new(false))
        .map_err(|_| "render cancelled".to_string())?;
    let error = compare(&r.film, reference).ok_or("the reference has another size")?;
    let row = Row {
        kind,
        label: label.to_string(),
        spp: r.stats.samples_per_pixel,
        light_samples: scene.settings.light_samples,
        noise: scene.settings.noise,
        seconds: r.stats.wall.as_secs_f64(),
        error,
        mean_spp: r.stats.noise.mean_samples(),
        pixels_at_max: r.stats.noise.pixels_at_max,
    };
    eprintln!(
        "{kind:<8} {label:<12} {:>9.3} s  rel. RMS {:.4}",
        row.seconds,
        row.error.rel_rms()
    );
    Ok(row)
}

/// Time at which the `kind` rows reach relative RMS error `target`: a power law
/// `err = a · t^b` fitted by least squares in log-log to the rows (fixed counts above 1 spp,
/// where the 1/N regime holds), evaluated at the target. `None` with fewer than two rows.
pub fn time_to(rows: &[Row], kind: &str, target: f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.kind == kind && r.spp > 1 && r.seconds > 0.0 && r.error.rel_mse > 0.0)
        .map(|r| (r.seconds.ln(), r.error.rel_rms().ln()))
        .collect();
    let (slope, intercept) = fit(&pts)?;
    // A flat line (a bias floor) never reaches the target.
    (slope < -0.05).then(|| ((target.ln() - intercept) / slope).exp())
}

/// Least-squares line `y = slope · x + intercept`.
pub fn fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    (sxx > 0.0).then(|| (sxy / sxx, my - sxy / sxx * mx))
}

fn csv(name: &str, rows: &[Row]) -> String {
    let mut s = String::from(
        "scene,kind,label,spp,light_samples,noise,seconds,rmse,rel_mse,rel_rms,mean_spp,pixels_at_max\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{name},{},{},{},{},{},{:.6},{:.6e},{:.6e},{:.6e},{:.2},{}",
            r.kind,
            r.label,
            r.spp,
            r.light_samples,
            r.noise.map_or(String::new(), |n| n.to_string()),
            r.seconds,
            r.error.rmse,
            r.error.rel_mse,
            r.error.rel_rms(),
            r.mean_spp,
            r.pixels_at_max
        );
    }
    s
}

fn table(rows: &[Row]) -> String {
    let mut s = format!(
        "{:<9} {:<12} {:>9} {:>10} {:>11} {:>10} {:>10}\n",
        "kind", "label", "spp", "time s", "RMSE", "relMSE", "rel. RMS"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:<9} {:<12} {:>9.1} {:>10.3} {:>11.3e} {:>10.3e} {:>9.2}%",
            r.kind,
            r.label,
            r.mean_spp,
            r.seconds,
            r.error.rmse,
            r.error.rel_mse,
            r.error.rel_rms() * 100.0
        );
    }
    s
}

fn fmt_time(t: Option<f64>) -> String {
    t.map_or("n/a".into(), |t| format!("{t:.2} s"))
}

/// Writes atomically, like the images.
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), String> {
    film::write_atomic_with(path, film::Durability::Synced, |f| {
        std::io::Write::write_all(f, bytes)
    })
    .map_err(|e| e.to_string())
}

/// FNV-1a, 64-bit: a hash that is the same on every run and platform (the cache key).
#[derive(Debug)]
struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        // Separate consecutive inputs.
        self.0 = (self.0 ^ 0xff).wrapping_mul(0x0100_0000_01b3);
    }
}
