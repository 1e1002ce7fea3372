//! `scnc render FILE [-o out.png] [--spp N] [--threads N] [--camera NAME] [--accel bvh|none]
//! [--resolution WxH] [--stats]`: the whole pipeline once, from `.scn` to image file.
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
    /// Samples per pixel (rounded up to a square N×N pattern).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
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

/// Largest side accepted by `--resolution`, as in the scene language.
const MAX_SIDE: u32 = 16384;

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
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
    let rendered = render::render(&scene, &options, &progress, &cancel);
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let (film, render_stats) = match rendered {
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
    phases.write = t.elapsed();
    if args.stats {
        eprintln!("{}", phases.report(&scene, &render_stats));
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
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
