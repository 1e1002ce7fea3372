//! `scnc render FILE [-o out.png] [--quality draft|preview|final] [--spp N] [--noise E
//! [--max-samples N]] [--variance-out FILE] [--threads N] [--camera NAME] [--accel bvh|none]
//! [--resolution WxH] [--tile K/N] [--frame F | --frames A..B[:STEP]] [--stats]`: the whole pipeline once, from `.scn` to image
//! file. `--tile K/N` renders one band of rows into an OpenEXR tile for `scnc merge` (see
//! [`super::tile`]).
//!
//! Precedence of the sample count: a command-line flag beats the scene; at each level an
//! explicit count beats a preset. So `--spp` > `--quality` > `render { samples }` >
//! `render { quality }` > the default (and likewise for `light_samples`, which only presets set
//! from the command line). `--noise` (or the scene's `noise`) samples adaptively; `--spp` on the
//! command line turns the scene's adaptive sampling off.
//!
//! The precedence is implemented once, in `ir::RenderSettings::resolve`, before the build.
//!
//! Compiles, builds the scene, renders with a progress bar when stderr is a terminal, and
//! writes each output atomically; then prints every diagnostic of the chain in one list (as
//! `scnc check` does). Ctrl-C cancels the
//! render at the next tile and writes nothing, so the previous image survives.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::{Args, ValueEnum};

use super::report::{exit_code, report, strict, DiagArgs, JsonTo, SceneArg};
use super::stats::PhaseStats;
use crate::assets::FsLoader;
use crate::bvh::AccelKind;
use crate::cli::frames::{self, FrameRange};
pub use crate::cli::parse::{
    parse_define, parse_frame, parse_noise, parse_resolution, parse_variance_path,
};
use crate::cli::targets::{camera_index, output_targets};
use crate::cli::tile::{self, TilePlan};
use crate::compile::{compile_with, Overrides};
use crate::diag::{Diagnostic, Staged};
use crate::film::{self, Durability, WriteSettings};
use crate::ir::{self, Quality, SettingFlags};
use crate::render::{self, RenderOptions, RenderStats};
use crate::scene::{self, BuildCache, BuildOptions, Scene};
use crate::source::SourceMap;

/// Which acceleration structure traces the rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum AccelArg {
    /// Bounding volume hierarchy (binned SAH, two-level for instances).
    #[default]
    Bvh,
    /// No acceleration structure: every ray against every triangle (the reference).
    None,
}

/// `scnc render`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    /// The scene file.
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
    /// below this (e.g. 0.01 for 1%), or `--max-samples` is reached. A pixel darker than 0.01
    /// (after exposure) stops at an absolute error of this times 0.01, the brightness below
    /// which relative error is not measured (docs/quality.md).
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
    /// Render only tile K of N (from 0) of the image, a band of rows, into an OpenEXR tile
    /// (`-o part_K.exr`) that `scnc merge` assembles with the others, bit for bit as one
    /// render would have made the image.
    #[arg(long, value_name = "K/N", value_parser = tile::parse_tile, conflicts_with = "variance_out")]
    pub tile: Option<(u32, u32)>,
    /// The value of the predefined constant `frame` in the scene's expressions (default 0),
    /// e.g. `rotate y (frame * 1.5deg)` for a turntable.
    #[arg(long, value_name = "F", value_parser = parse_frame, allow_hyphen_values = true)]
    pub frame: Option<f64>,
    /// Render frames A to B (inclusive) every STEP (default 1), each to `-o`'s name with its
    /// run of `#`s replaced by the zero-padded frame number (`-o out_####.png`); meshes, BVH
    /// and textures that do not depend on `frame` are built once.
    #[arg(long, value_name = "A..B[:STEP]", value_parser = frames::parse_frames,
          conflicts_with = "frame", allow_hyphen_values = true)]
    pub frames: Option<FrameRange>,
    /// Replace the value of the scene's `let NAME = …` with VALUE (an expression of the same
    /// type), e.g. `--define radius=2` or `--define tint='rgb(1, 0.5, 0)'`; repeatable.
    #[arg(long, value_name = "NAME=VALUE", value_parser = parse_define)]
    pub define: Vec<(String, String)>,
    /// Print phase times, ray counts, Mrays/s, BVH size and peak memory.
    #[arg(long)]
    pub stats: bool,
    /// Diagnostic format and `--strict`.
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// `--quality`: the presets of `render { quality … }`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[allow(
    missing_docs,
    reason = "clap would print variant docs in --help; the flag's doc describes the presets"
)]
pub enum QualityArg {
    Draft,
    Preview,
    Final,
}

impl QualityArg {
    /// The preset it names.
    pub fn preset(self) -> Quality {
        match self {
            QualityArg::Draft => Quality::Draft,
            QualityArg::Preview => Quality::Preview,
            QualityArg::Final => Quality::Final,
        }
    }
}

/// `scnc render`: resolve the settings, compile, build, render, write; then report every
/// diagnostic of the chain once.
pub fn run(args: &RenderArgs) -> ExitCode {
    match args.frames {
        Some(range) => frames::run(args, range),
        None => run_frame(args, None),
    }
}

/// One render of `args` (its `frame`), building through `cache` when given (`--frames`); the
/// scene goes back into the cache afterwards.
pub(super) fn run_frame(args: &RenderArgs, mut cache: Option<&mut BuildCache>) -> ExitCode {
    let loader = FsLoader::new();
    let mut sources = SourceMap::new();
    let mut phases = PhaseStats::default();
    let t = Instant::now();
    let overrides = Overrides {
        frame: args.frame.unwrap_or(0.0),
        defines: args.define.clone(),
    };
    let compiled = strict(
        compile_with(&args.scene.file, &loader, &mut sources, &overrides),
        &args.diag,
    );
    phases.compile = t.elapsed();
    let built = compiled
        .and_then(|desc| resolve(args, desc))
        .and_then(|(desc, options, plan)| {
            match cache.as_deref_mut() {
                Some(c) => scene::build_cached(&desc, &loader, &options, c),
                None => scene::build(&desc, &loader, &options),
            }
            .map(|s| (desc, s, plan))
        });
    // What compile and build found is printed before a render that may take minutes, as a
    // compiler prints its warnings before it links; what writing finds, after it.
    let built = strict(built, &args.diag);
    report(&built, &sources, &args.diag, JsonTo::Stdout);
    let built_failed = built.has_errors();
    let finished = Staged::new(built.value, Vec::new())
        .and_then(|(desc, scene, plan)| render_and_write(args, &desc, scene, plan, &mut phases));
    report(&finished, &sources, &args.diag, JsonTo::Stdout);
    let code = finish(args, &phases, built_failed, &finished);
    if let (Some(c), Some(Finished::Rendered(scene, ..))) = (cache, finished.value) {
        c.recycle(*scene);
    }
    code
}

/// Prints what the render wrote (and `--stats`); the exit code.
fn finish(
    args: &RenderArgs,
    phases: &PhaseStats,
    built_failed: bool,
    finished: &Staged<Finished>,
) -> ExitCode {
    match &finished.value {
        Some(Finished::Cancelled) => {
            eprintln!("render cancelled; no image written");
            ExitCode::from(130)
        }
        Some(Finished::Rendered(scene, stats, written)) => {
            for line in written {
                eprintln!("{line}");
            }
            if stats.noise.target.is_some() {
                eprintln!("{}", stats.noise.summary());
            }
            if args.stats {
                eprintln!("{}", phases.report(scene, stats));
            }
            if built_failed {
                ExitCode::FAILURE
            } else {
                exit_code(finished)
            }
        }
        None => ExitCode::FAILURE,
    }
}

/// How a render that got as far as the renderer ended.
#[allow(
    clippy::large_enum_variant,
    reason = "one value per render, moved once; boxing the stats buys nothing"
)]
enum Finished {
    /// Rendered, with a line per file written (the write's diagnostics say why any other
    /// was not).
    Rendered(Box<Scene>, RenderStats, Vec<String>),
    /// Ctrl-C: nothing written.
    Cancelled,
}

/// The command line's settings into the scene, before anything is built: `--camera` (a
/// diagnostic if the scene has no such camera), `--accel`, the render settings, and the
/// `--tile` plan (diagnostics for a non-EXR output or too many tiles).
fn resolve(args: &RenderArgs, mut desc: ir::SceneDesc) -> Staged<Resolved> {
    let camera = match args.camera.as_deref().map(|name| camera_index(&desc, name)) {
        None => None,
        Some(Ok(i)) => Some(i),
        Some(Err(d)) => return Staged::failed(vec![*d]),
    };
    desc.render.resolve(&setting_flags(args));
    let accel = match args.accel {
        AccelArg::Bvh => AccelKind::Bvh,
        AccelArg::None => AccelKind::None,
    };
    let plan = match args.tile {
        None => None,
        Some(k_n) => {
            let targets = output_targets(args.output.as_deref(), &args.scene.file, &desc);
            let chosen = camera.unwrap_or(desc.active_camera);
            let accel_name = format!("{:?}", args.accel).to_ascii_lowercase();
            match tile::plan(k_n, &desc, chosen, &accel_name, &targets) {
                Ok(plan) => Some(plan),
                Err(problems) => return Staged::failed(problems),
            }
        }
    };
    Staged::ok((desc, BuildOptions { accel, camera }, plan))
}

/// The scene with the command line applied, what to build it with, and the tile to render.
type Resolved = (ir::SceneDesc, BuildOptions, Option<TilePlan>);

/// The render settings the flags give (see `ir::RenderSettings::resolve` for the precedence).
fn setting_flags(args: &RenderArgs) -> SettingFlags {
    SettingFlags {
        resolution: args.resolution,
        quality: args.quality.map(QualityArg::preset),
        spp: args.spp,
        noise: args.noise,
        max_samples: args.max_samples,
    }
}

/// Renders (Ctrl-C cancels at the next tile) and writes every output and the variance image.
fn render_and_write(
    args: &RenderArgs,
    desc: &ir::SceneDesc,
    scene: Scene,
    plan: Option<TilePlan>,
    phases: &mut PhaseStats,
) -> Staged<Finished> {
    phases.asset_load = scene.timings.asset_load;
    phases.accel_build = scene.timings.accel_build;
    // The bands are cut where the built scene's rows cost the same (`render::balance`).
    let split_start = Instant::now();
    let plan = plan.map(|p| p.balanced(&scene));
    phases.tile = plan.map(|p| {
        let h = p.header;
        (h.index, h.count, p.window, split_start.elapsed())
    });
    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // Without a handler Ctrl-C still stops the process; the image on disk is safe either
        // way (writes are atomic), so a failure to install one is not worth reporting.
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let options = RenderOptions {
        threads: args.threads,
    };
    let bar = progress_bar();
    let progress = |f: f32| {
        if let Some(bar) = &bar {
            bar.set_position((f * 1000.0) as u64);
        }
    };
    let window = plan.map_or(
        render::PixelWindow::full(scene.settings.width, scene.settings.height),
        |p| p.window,
    );
    let rendered = render::render_window(&scene, &options, window, &progress, &cancel);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let Ok(rendered) = rendered else {
        return Staged::ok(Finished::Cancelled);
    };
    phases.render = rendered.stats.wall;
    let t = Instant::now();
    let (written, diagnostics) = write_outputs(args, desc, &scene, plan.as_ref(), &rendered);
    phases.write = t.elapsed();
    Staged::new(
        Some(Finished::Rendered(Box::new(scene), rendered.stats, written)),
        diagnostics,
    )
}

/// Writes the image to every output target and the standard error to `--variance-out`;
/// returns a line per file written and the diagnostics of the writes that failed (the others
/// still happen).
fn write_outputs(
    args: &RenderArgs,
    desc: &ir::SceneDesc,
    scene: &Scene,
    plan: Option<&TilePlan>,
    rendered: &render::Rendered,
) -> (Vec<String>, Vec<Diagnostic>) {
    let settings = WriteSettings::from_render(&scene.settings);
    let (mut lines, mut diagnostics) = (Vec::new(), Vec::new());
    for (path, span) in output_targets(args.output.as_deref(), &args.scene.file, desc) {
        let written = match plan {
            Some(p) => Staged::from_result(
                film::tile::write_tile(&rendered.film, p.window, &p.header, &path)
                    .map_err(|e| e.to_diagnostic(span)),
            ),
            None => film::write(&rendered.film, &path, &settings, Durability::Synced, span),
        };
        if written.value.is_some() {
            lines.push(format!("wrote {}", path.display()));
        }
        diagnostics.extend(written.diagnostics);
    }
    if let Some(path) = &args.variance_out {
        // Float formats store the values as they are: the settings only matter for PNG.
        let written = film::write(
            &rendered.std_error,
            path,
            &WriteSettings::default(),
            Durability::Synced,
            None,
        );
        if written.value.is_some() {
            lines.push(format!(
                "wrote {} (standard error of each pixel)",
                path.display()
            ));
        }
        diagnostics.extend(written.diagnostics);
    }
    (lines, diagnostics)
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
