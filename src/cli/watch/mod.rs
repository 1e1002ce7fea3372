//! `scnc watch FILE [-o out.png] [--threads N] [--camera NAME] [--no-clear] [--port N]
//! [--no-serve] [--events human|json]`: compile, render progressively, and do it again on
//! every change of the scene, its includes and its assets, until Ctrl-C.
//!
//! The loop: compile (through a recording loader: the paths read are the new watch set) and
//! build through the cache → start the passes on a render thread → wait for a batch of file
//! events ([`batch`]) that changes some watched file's content ([`watcher`]) → cancel the
//! render, hand its scene back to the cache, repeat. A broken edit prints its diagnostics and
//! leaves the last good image in place. Files: [`session`] (one compile), [`passes`]
//! (progressive render), [`status`] (terminal and JSON events), [`server`] (preview page).

mod batch;
mod passes;
mod server;
mod session;
mod settled;
mod status;
mod watcher;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::sync::Arc;
use std::time::Duration;

use clap::Args;

use self::batch::Msg;
use self::passes::RenderJob;
use self::server::Preview;
use self::session::Session;
use self::status::{EventsFormat, Status};
use self::watcher::FileWatcher;
use super::report::SceneArg;
use crate::scene::BuildCache;

/// How often files that do not exist yet are looked for.
const POLL: Duration = Duration::from_millis(250);

/// `scnc watch`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct WatchArgs {
    /// The scene file.
    #[command(flatten)]
    pub scene: SceneArg,
    /// `--frame F`, `--define NAME=VALUE`.
    #[command(flatten)]
    pub overrides: super::overrides::OverrideArgs,
    /// Output image (written after every pass); default: the scene's outputs, or the scene
    /// file's name with `.png` in the current directory.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Worker threads for rendering (default: every core).
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Render from this camera instead of the scene's active one.
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,
    /// Do not clear the terminal before each compile.
    #[arg(long)]
    pub no_clear: bool,
    /// Port of the preview server on 127.0.0.1 (default: any free port).
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub port: u16,
    /// Do not start the preview server.
    #[arg(long)]
    pub no_serve: bool,
    /// How to report: a human status on stderr, or one JSON object per line on stdout.
    #[arg(long, value_enum, default_value_t = EventsFormat::Human)]
    pub events: EventsFormat,
}

/// `scnc watch`: compile, build and render in a loop, on every change of what was read.
pub fn run(args: &WatchArgs) -> ExitCode {
    let (tx, rx) = channel();
    {
        let tx = tx.clone();
        // Without a handler Ctrl-C kills the process outright; outputs are still whole (they
        // are written atomically), so a failure to install one is not worth stopping for.
        let _ = ctrlc::set_handler(move || {
            let _ = tx.send(Msg::Quit);
        });
    }
    let preview = (!args.no_serve).then(|| Arc::new(Preview::default()));
    let status = Arc::new(Status::new(args.events, args.no_clear, preview.clone()));
    if let Some(p) = &preview {
        match server::serve(p.clone(), args.port) {
            Ok(url) => status.serving(&url),
            Err(e) => {
                eprintln!(
                    "error: cannot serve the preview on 127.0.0.1:{}: {e}",
                    args.port
                );
                return ExitCode::FAILURE;
            }
        }
    }
    let mut watcher = match FileWatcher::new(tx) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("error: cannot watch files: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut session = Session {
        file: args.scene.file.clone(),
        output: args.output.clone(),
        camera: args.camera.clone(),
        cache: BuildCache::new(),
        front: crate::compile::Incremental::new(args.overrides.overrides()),
    };
    let mut job: Option<RenderJob> = None;
    let mut changed = Vec::new();
    loop {
        if let Some(scene) = job.take().and_then(RenderJob::stop) {
            session.cache.recycle(scene);
        }
        session.cache.retain_current(|p| watcher.hash_of(p));
        status.begin(&changed);
        let outcome = session.compile(watcher.take_read(), &|figures, diagnostics, sources| {
            status.checked(figures, diagnostics, sources);
        });
        watcher.set(outcome.files);
        let diagnostics = outcome.built.diagnostics;
        match outcome.built.value {
            Some(ready) => {
                status.compiled(&outcome.figures, &diagnostics, &outcome.sources);
                job = Some(RenderJob::start(
                    ready,
                    Arc::new(outcome.sources),
                    args.threads,
                    status.clone(),
                    preview.clone(),
                ));
            }
            None => status.error(&diagnostics, &outcome.sources),
        }
        status.watching(watcher.len());
        match wait_for_change(&rx, &mut watcher) {
            Some(paths) => changed = paths,
            None => break,
        }
    }
    if let Some(job) = job.take() {
        job.stop();
    }
    status.stopped();
    ExitCode::SUCCESS
}

/// Blocks until a watched file's content changed (returns those files) or Ctrl-C (`None`).
fn wait_for_change(rx: &Receiver<Msg>, watcher: &mut FileWatcher) -> Option<Vec<PathBuf>> {
    loop {
        let (change, paths) = match rx.recv_timeout(POLL) {
            Ok(Msg::Quit) | Err(RecvTimeoutError::Disconnected) => return None,
            Ok(Msg::Paths(change, paths)) => (change, paths),
            Err(RecvTimeoutError::Timeout) => {
                let changed = watcher.poll();
                if !changed.is_empty() {
                    return Some(changed);
                }
                continue;
            }
        };
        let first: Vec<PathBuf> = paths
            .into_iter()
            .filter(|p| watcher.is_watched(p))
            .collect();
        if first.is_empty() {
            continue;
        }
        let batch = batch::gather(rx, (change, first), batch::Timing::WATCH, |p| {
            watcher.is_watched(p)
        });
        if batch.quit {
            return None;
        }
        let changed = watcher.confirm(&batch.paths);
        if !changed.is_empty() {
            return Some(changed);
        }
    }
}
