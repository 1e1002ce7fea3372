//! Benchmark (a program, not a test): full renders at one thread and at every core, for the
//! thread-scaling target of the renderer ("2 threads at least 1.9× one thread on a full
//! render") and the Mrays/s of whole renders (camera, shadow and BRDF rays with shading).
//!
//! ```text
//! cargo bench --bench render -- [SCENE.scn ...] [--reps N] [--spp N] [--threads a,b]
//! ```
//! Without scene arguments it renders `examples/cornell.scn`, `examples/env.scn` and
//! `examples/dense.scn` at their own settings. For each scene and thread count it reports the
//! median wall time of `--reps` renders (default 3) and the rays per second; then the speed-up
//! of the largest thread count over the first. Run it on an idle machine: with other work on
//! the cores the speed-up measures the other work. Figures go in `docs/renderer.md`.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use scnc::assets::FsLoader;
use scnc::compile::compile_file;
use scnc::render::{self, RenderOptions, RenderStats};
use scnc::scene::{self, BuildOptions, Scene};

struct Args {
    scenes: Vec<PathBuf>,
    reps: usize,
    spp: Option<u32>,
    threads: Vec<usize>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        scenes: Vec::new(),
        reps: 3,
        spp: None,
        threads: vec![1, 2],
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match a.as_str() {
            "--bench" => {}
            "--reps" => args.reps = value("--reps")?.parse().map_err(|e| format!("{e}"))?,
            "--spp" => args.spp = Some(value("--spp")?.parse().map_err(|e| format!("{e}"))?),
            "--threads" => {
                args.threads = value("--threads")?
                    .split(',')
                    .map(|t| t.parse::<usize>().map_err(|e| format!("{e}")))
                    .collect::<Result<_, _>>()?
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            path => args.scenes.push(PathBuf::from(path)),
        }
    }
    if args.scenes.is_empty() {
        let examples = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples");
        args.scenes = ["cornell.scn", "env.scn", "dense.scn"]
            .iter()
            .map(|f| examples.join(f))
            .collect();
    }
    args.reps = args.reps.max(1);
    Ok(args)
}

/// The scene at `path`, with `--spp` (if given) as its sample count.
fn load(path: &Path, spp: Option<u32>) -> Result<Scene, String> {
    let loader = FsLoader::new();
    let compiled = compile_file(path, &loader);
    let mut desc = compiled
        .scene
        .ok_or_else(|| format!("{}: does not compile", path.display()))?;
    if let Some(spp) = spp {
        desc.render.fix_samples(spp);
    }
    scene::build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .map(|(scene, _)| scene)
        .map_err(|e| format!("{}: does not build: {e:?}", path.display()))
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn main() {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("render bench: {e}");
            std::process::exit(2);
        }
    };
    println!("scene, threads, spp, median ms, Mrays/s, rays");
    for path in &args.scenes {
        let scene = match load(path, args.spp) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("skipped: {e}");
                continue;
            }
        };
        let name = path.file_stem().map_or_else(
            || path.display().to_string(),
            |s| s.to_string_lossy().into(),
        );
        let mut medians = Vec::new();
        for &threads in &args.threads {
            let options = RenderOptions {
                threads: Some(threads),
            };
            let mut walls = Vec::new();
            let mut last: Option<RenderStats> = None;
            for _ in 0..args.reps {
                match render::render(&scene, &options, &|_| {}, &AtomicBool::new(false)) {
                    Ok((_, stats)) => {
                        walls.push(stats.wall);
                        last = Some(stats);
                    }
                    Err(render::Cancelled) => continue,
                }
            }
            let wall = median(walls);
            let stats = last.unwrap_or_default();
            let mrays = stats.rays() as f64 / wall.as_secs_f64().max(1e-9) / 1e6;
            println!(
                "{name}, {threads}, {}, {:.1}, {mrays:.2}, {}",
                stats.samples_per_pixel,
                wall.as_secs_f64() * 1e3,
                stats.rays()
            );
            medians.push((threads, wall));
        }
        if let (Some(first), Some(last)) = (medians.first(), medians.last()) {
            if last.0 != first.0 {
                println!(
                    "{name}: {} threads are {:.2}x {} thread(s)",
                    last.0,
                    first.1.as_secs_f64() / last.1.as_secs_f64().max(1e-9),
                    first.0
                );
            }
        }
    }
}
