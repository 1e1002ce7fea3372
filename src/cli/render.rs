//! `scnc render FILE [-o out.png] [--quality draft|preview|final] [--spp N] [--noise E
//! [--max-samples N]] [--variance-out FILE] [--threads N] [--camera NAME] [--accel bvh|none]
//! [--resolution WxH] [--stats]`: the whole pipeline once, from `.scn` to image file.
//!
//! Precedence of the sample count: a command-line flag beats the scene; at each level an
//! explicit count beats a preset. So `--spp` > `--quality` > `render { samples }` >
//! `render { quality }` > the default (and likewise for `light_samples`, which only presets set
//! from the command line). `--noise` (or the scene's `noise`) samples adaptively; `--spp` on the
//! command line turns the scene's adaptive sampling off.
//!
//! Compiles (printing every diagnostic as `scnc check` does), builds the scene, renders with a
//! progress bar when stderr is a terminal, and writes each output atomically. Ctrl-C cancels the
//! render at the next tile and writes nothing, so the previous image survives.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};

use super::report::{compile_and_report, print_diagnostic_list, DiagArgs, JsonTo, SceneArg};
use super::stats::PhaseStats;
use crate::assets::FsLoader;
use crate::bvh::AccelKind;
use crate::cli::targets::{camera_index, output_targets};
use crate::film::{self, WriteSettings};
use crate::ir::{self, Quality};
use crate::render::{self, RenderOptions};
use crate::scene::{self, BuildOptions};

/// Which acceleration structure traces the rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum AccelArg {
    /// Bounding volume hierarchy (binned SAH, two-level for instances).
    #[default]
    Bvh,
    /// No acceleration structure: every ray against every triangle (the reference).
    None,
}

#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub scene: SceneArg,
    /// Output image; the format follows the extension (.png, .exr, .hdr, .pfm). Default: the
    /// scene's `output`s, or the scene file's name with `.png` in the current directory.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Samples per pixel, 1..=65536 (rounded up to a square N×N pattern). Beats `--quality`
    /// and the scene's `samples`.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub spp: Option<u32>,
    /// A quality preset: draft (1 spp, 4 light samples), preview (16 spp), final (256 spp).
    /// Beats the scene's `quality` and `samples`.
    #[arg(long, value_enum, value_name = "PRESET")]
    pub quality: Option<QualityArg>,
    /// Adaptive sampling: sample each pixel until the relative standard error of its mean is
    /// below this (e.g. 0.01 for 1%), or `--max-samples` is reached.
    #[arg(long, value_name = "E", value_parser = parse_noise, conflicts_with = "spp")]
    pub noise: Option<f32>,
    /// The cap of adaptive sampling per pixel (16..=1048576; default 4096).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(16..=1_048_576))]
    pub max_samples: Option<u32>,
    /// Also write each pixel's standard error of the mean (linear RGB) to this file (.exr or
    /// .pfm), atomically like the image.
    #[arg(long, value_name = "FILE", value_parser = parse_variance_path)]
    pub variance_out: Option<PathBuf>,
    /// Worker threads (default: every core). The image is the same for any count.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Render from this camera instead of the scene's active one.
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// Acceleration structure.
    #[arg(long, value_enum, default_value_t = AccelArg::Bvh)]
    pub accel: AccelArg,
    /// Override the scene's resolution, e.g. `320x240`.
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Print phase times, ray counts, Mrays/s, BVH size and peak memory.
    #[arg(long)]
    pub stats: bool,
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// `--quality`: the presets of `render { quality … }`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum QualityArg {
    Draft,
    Preview,
    Final,
}

impl QualityArg {
    pub fn preset(self) -> Quality {
        match self {
            QualityArg::Draft => Quality::Draft,
            QualityArg::Preview => Quality::Preview,
            QualityArg::Final => Quality::Final,
        }
    }
}

/// `--noise`: a relative standard error in 0.0001..=1, as in the scene language.
pub fn parse_noise(s: &str) -> Result<f32, String> {
    let x: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("`{s}` is not a number (try 0.01 for 1%)"))?;
    if (1e-4..=1.0).contains(&x) {
        Ok(x as f32)
    } else {
        Err(format!(
            "the noise target is a relative error in 0.0001..=1 (0.01 is 1%), got {s}"
        ))
    }
}

fn parse_variance_path(s: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(s);
    match film::format_for_path(&path) {
        Some(ir::OutputFormat::Exr | ir::OutputFormat::Pfm) => Ok(path),
        _ => Err(format!(
            "the variance image is linear float: give a .exr or .pfm file, got `{s}`"
        )),
    }
}

/// Largest side accepted by `--resolution`, as in the scene language.
const MAX_SIDE: u32 = 16384;

pub(super) fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("expected WIDTHxHEIGHT such as 320x240, got `{s}`"))?;
    let side = |v: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("`{v}` is not a whole number"))?;
        if (1..=MAX_SIDE).contains(&n) {
            Ok(n)
        } else {
            Err(format!("each side must be 1..={MAX_SIDE}, got {n}"))
        }
    };
    Ok((side(w)?, side(h)?))
}

pub fn run(args: &RenderArgs) -> ExitCode {
    let mut phases = PhaseStats::default();
    let t = Instant::now();
    let compiled = compile_and_report(&args.scene.file, &args.diag, JsonTo::Stdout);
    phases.compile = t.elapsed();
    let Some(mut desc) = compiled.scene else {
        return ExitCode::FAILURE;
    };
    let camera = match args.camera.as_deref().map(|name| camera_index(&desc, name)) {
        None => None,
        Some(Ok(i)) => Some(i),
        Some(Err(d)) => {
            print_diagnostic_list(
                &[*d],
                &compiled.sources,
                args.diag.diagnostic_format,
                JsonTo::Stdout,
            );
            return ExitCode::FAILURE;
        }
    };
    if let Some((w, h)) = args.resolution {
        desc.render.width = w;
        desc.render.height = h;
    }
    apply_sampling_flags(args, &mut desc.render);
    let accel = match args.accel {
        AccelArg::Bvh => AccelKind::Bvh,
        AccelArg::None => AccelKind::None,
    };
    let loader = FsLoader::new();
    let built = scene::build(
        &desc,
        &compiled.sources,
        &loader,
        &BuildOptions { accel, camera },
    );
    let scene = match built {
        Ok(mut scene) if args.diag.strict && !scene.warnings.is_empty() => {
            super::report::promote_warnings(&mut scene.warnings);
            print_diagnostic_list(
                &scene.warnings,
                &compiled.sources,
                args.diag.diagnostic_format,
                JsonTo::Stdout,
            );
            return ExitCode::FAILURE;
        }
        Ok(scene) => scene,
        Err(diags) => {
            print_diagnostic_list(
                &diags,
                &compiled.sources,
                args.diag.diagnostic_format,
                JsonTo::Stdout,
            );
            return ExitCode::FAILURE;
        }
    };
    print_diagnostic_list(
        &scene.warnings,
        &compiled.sources,
        args.diag.diagnostic_format,
        JsonTo::Stdout,
    );
    phases.asset_load = scene.timings.asset_load;
    phases.accel_build = scene.timings.accel_build;

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // Without a handler Ctrl-C still stops the process; the image on disk is safe either
        // way (writes are atomic), so a failure to install one is not worth reporting.
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let options = RenderOptions {
        spp: args.spp,
        threads: args.threads,
    };
    let bar = progress_bar();
    let progress = |f: f32| {
        if let Some(bar) = &bar {
            bar.set_position((f * 1000.0) as u64);
        }
    };
    let rendered = render::render_with_error(&scene, &options, &progress, &cancel);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let render::Rendered {
        film,
        std_error,
        stats: render_stats,
    } = match rendered {
        Ok(r) => r,
        Err(render::Cancelled) => {
            eprintln!("render cancelled; no image written");
            return ExitCode::from(130);
        }
    };
    phases.render = render_stats.wall;

    let t = Instant::now();
    let settings = WriteSettings::from_render(&scene.settings);
    let mut failed = false;
    for (path, span) in output_targets(args.output.as_deref(), &args.scene.file, &desc) {
        match film::write(&film, &path, &settings) {
            Ok(()) => eprintln!("wrote {}", path.display()),
            Err(e) => {
                failed = true;
                let d = e.to_diagnostic(span);
                print_diagnostic_list(
                    &[d],
                    &compiled.sources,
                    args.diag.diagnostic_format,
                    JsonTo::Stdout,
                );
            }
        }
    }
    if let Some(path) = &args.variance_out {
        // Float formats store the values as they are: the settings only matter for PNG.
        match film::write(&std_error, path, &WriteSettings::default()) {
            Ok(()) => eprintln!("wrote {} (standard error of each pixel)", path.display()),
            Err(e) => {
                failed = true;
                print_diagnostic_list(
                    &[e.to_diagnostic(None)],
                    &compiled.sources,
                    args.diag.diagnostic_format,
                    JsonTo::Stdout,
                );
            }
        }
    }
    phases.write = t.elapsed();
    if render_stats.noise.target.is_some() {
        eprintln!("{}", render_stats.noise.summary());
    }
    if args.stats {
        eprintln!("{}", phases.report(&scene, &render_stats));
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// `--quality`, `--noise`, `--max-samples` into the scene's settings (`--spp` stays a render
/// option: `scnc watch` overrides the count per pass the same way).
fn apply_sampling_flags(args: &RenderArgs, settings: &mut ir::RenderSettings) {
    if let Some(q) = args.quality {
        settings.apply_quality(q.preset());
    }
    if args.spp.is_some() {
        settings.noise = None;
    }
    if let Some(e) = args.noise {
        settings.noise = Some(e);
    }
    if let Some(n) = args.max_samples {
        settings.max_samples = Some(n);
    }
}

fn progress_bar() -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new(1000);
    let style = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:40}] {percent}% eta {eta}",
    )
    .map(|s| s.progress_chars("=> "));
    if let Ok(style) = style {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    Some(bar)
}
