//! `scnc watch`: progressive rendering on a thread of its own. Pass 1 at preview quality
//! (1 sample per pixel), then passes refining to the scene's samples (1, 4, then the scene's
//! N², each skipped when it would not add samples); a scene with a noise target
//! (`render { noise 0.01 }`) ends with an adaptive pass instead of the fixed N². Each finished pass is written atomically
//! to every output and handed to the preview. Stopping sets the cancel flag (the renderer checks
//! it before every tile) and gives the scene back for the build cache.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

use super::server::Preview;
use super::session::Ready;
use super::status::Status;
use crate::film::{self, Durability};
use crate::render::{self, RenderOptions};
use crate::scene::Scene;
use crate::source::SourceMap;

/// The samples per pixel of each pass, for a scene rendering `full` in the end; `None` is the
/// scene's own adaptive sampling (when it sets a noise target), after the 1- and 4-sample
/// previews.
pub fn plan(full: u32, adaptive: bool) -> Vec<Option<u32>> {
    if adaptive {
        return vec![Some(1), Some(4), None];
    }
    let mut passes: Vec<Option<u32>> = [1, 4].into_iter().filter(|&s| s < full).map(Some).collect();
    passes.push(Some(full.max(1)));
    passes
}

/// A render in flight.
pub struct RenderJob {
    cancel: Arc<AtomicBool>,
    handle: JoinHandle<Scene>,
}

impl RenderJob {
    /// Starts rendering the passes of `ready` on a thread of its own.
    pub fn start(
        ready: Ready,
        sources: Arc<SourceMap>,
        threads: Option<usize>,
        status: Arc<Status>,
        preview: Option<Arc<Preview>>,
    ) -> RenderJob {
        let cancel = Arc::new(AtomicBool::new(false));
        let flag = cancel.clone();
        let handle = std::thread::spawn(move || {
            let mut ready = ready;
            run(
                &mut ready,
                &sources,
                threads,
                &status,
                preview.as_deref(),
                &flag,
            );
            ready.scene
        });
        RenderJob { cancel, handle }
    }

    /// Cancels the render (at the next tile) and waits for it; a pass being written finishes
    /// its atomic write first. Returns the scene for the cache (`None` if the thread panicked).
    pub fn stop(self) -> Option<Scene> {
        self.cancel.store(true, Ordering::Relaxed);
        self.handle.join().ok()
    }
}

/// Renders each pass of the plan with its own sample count (set in the scene's settings, then
/// put back so the cache gets the scene as built), writing and previewing each.
fn run(
    ready: &mut Ready,
    sources: &SourceMap,
    threads: Option<usize>,
    status: &Status,
    preview: Option<&Preview>,
    cancel: &AtomicBool,
) {
    let built = ready.scene.settings.clone();
    let passes = plan(built.samples_per_pixel, built.noise.is_some());
    let options = RenderOptions { threads };
    for (i, &spp) in passes.iter().enumerate() {
        ready.scene.settings = built.clone();
        if let Some(spp) = spp {
            ready.scene.settings.fix_samples(spp);
        }
        let rendered = render::render(&ready.scene, &options, &|_| {}, cancel);
        ready.scene.settings = built.clone();
        let Ok((film, stats)) = rendered else {
            return;
        };
        // The browser's preview first: it waits on nothing but the encoding.
        if let Some(p) = preview {
            if let Ok(png) = film::encode_png(&film, &ready.write) {
                p.set_image(png);
            }
        }
        for (path, span) in &ready.outputs {
            let written = film::write(&film, path, &ready.write, Durability::Replaced, *span);
            for d in &written.diagnostics {
                status.write_failed(d, sources);
            }
        }
        status.pass(
            i + 1,
            stats.samples_per_pixel,
            stats.wall.as_secs_f64() * 1e3,
            (film.width(), film.height()),
            i + 1 == passes.len(),
        );
        if cancel.load(Ordering::Relaxed) {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::plan;

    #[test]
    fn passes_refine_up_to_the_scene() {
        assert_eq!(plan(1, false), vec![Some(1)]);
        assert_eq!(plan(4, false), vec![Some(1), Some(4)]);
        assert_eq!(plan(16, false), vec![Some(1), Some(4), Some(16)]);
        assert_eq!(plan(0, false), vec![Some(1)]);
    }

    #[test]
    fn a_noise_target_ends_with_the_adaptive_pass() {
        assert_eq!(plan(16, true), vec![Some(1), Some(4), None]);
        assert_eq!(plan(1, true), vec![Some(1), Some(4), None]);
    }
}
