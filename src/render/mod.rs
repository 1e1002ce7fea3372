//! Stage 4, render: [`Scene`] → [`Film`] (linear RGB radiance per pixel).
//!
//! Syntax it executes: `render { resolution 512 x 512  samples rgss 4  light_samples 1
//! seed 0 }`. The image is cut into 16×16 tiles rendered in parallel on a local rayon pool;
//! each pixel's value depends only on its own samples (sub-pixel positions from
//! [`pattern`], random numbers hashed from pixel, sample and seed in [`rng`]), so the image is
//! bit-identical for any thread count. Cancellation is checked before every tile.
//!
//! `render { noise 0.01  max_samples 4096 }` samples each pixel adaptively, in batches, until
//! the relative standard error of its mean is below the target (see [`estimate`]); every render
//! also estimates each pixel's standard error ([`render_with_error`]) for `--variance-out`. An
//! adaptive render runs in three passes per band of rows: every pixel's first batch; every
//! pixel to its first whole batch (20 samples), unless it stops before on what its neighbours'
//! first batches say ([`early_stop`]); then each pixel on to its stop, the first of which pools
//! its neighbours' replicate spreads ([`pooled_stop`]). A band's third pass runs beside the next
//! band's first two, which do not read it.
//!
//! [`render_window`] renders only a rectangle of the image ([`window`]; `--tile K/N`), each of
//! its pixels with exactly the bits of the full render.

pub mod balance;
pub mod camera;
pub mod early_stop;
pub mod emitter_coverage;
pub mod emitter_pixels;
pub mod estimate;
mod first_pass;
pub mod integrator;
mod mis;
mod owen_sobol;
pub mod pattern;
pub mod pooled_stop;
mod rect_lit;
pub mod rng;
mod second_pass;
mod tile_rows;
pub mod window;

use std::cell::OnceCell;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use glam::Vec2;
use rayon::prelude::*;

use self::camera::PinholeCamera;
use self::early_stop::{FirstBatchSpread, NeighbourPrior};
use self::emitter_coverage::{EmitterCoverage, SliverRule};
use self::emitter_pixels::EmitterPixels;
use self::estimate::{Accumulator, NoiseStats, PixelEstimate};
use self::first_pass::FirstBatches;
use self::integrator::{radiance_scaled, RayCounts};
use self::pooled_stop::{ReplicatePool, POOL_BATCH};
use self::rect_lit::{RectLit, Samples};
use self::second_pass::{PixelState, SecondPass};
use self::tile_rows::TileRows;
pub use self::window::PixelWindow;
use crate::bvh::Scratch;
use crate::film::Film;
use crate::scene::Scene;
use crate::shade::texture::footprint::footprint_scale;

/// Side of the square tiles the image is cut into (one unit of parallel work).
pub const TILE_SIZE: u32 = 16;

/// How to run a render that is not a scene setting (those are in `Scene::settings`, resolved
/// before the render starts: see `ir::RenderSettings::resolve`).
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions {
    /// `--threads N`; `None` or `Some(0)` uses every core.
    pub threads: Option<usize>,
}

/// The render was cancelled (Ctrl-C, or `scnc watch` saw a newer edit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("render cancelled")]
pub struct Cancelled;

/// Figures for `--stats`.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderStats {
    /// Primary rays, one per sample.
    pub camera_rays: u64,
    /// Rays towards sampled lights.
    pub shadow_rays: u64,
    /// BRDF-sampled rays (multiple importance sampling of area lights and the environment).
    pub brdf_rays: u64,
    /// Wall time of the render: from the pre-pass that finds the pixels seeing a light, through
    /// the pixel loop, to the assembled films (not the scene's build nor the image's writing).
    pub wall: Duration,
    /// CPU time of the process over the same span (every thread's), if the platform tells:
    /// on a loaded machine the wall time counts other processes' turns, this does not.
    pub cpu: Option<Duration>,
    /// Worker threads used.
    pub threads: usize,
    /// Samples per pixel: the fixed count, or the mean of an adaptive render.
    pub samples_per_pixel: u32,
    /// Pixels of a fixed-count render that may see an area light, and the samples each of
    /// them took ([`emitter_pixels`]); (0, 0) when none was boosted.
    pub emitter_pixels: (u64, u32),
    /// Rays by kind, optional feature paths taken, and samples dropped as NaN or infinite.
    pub counts: RayCounts,
    /// Estimated error of the image, and how adaptive sampling went.
    pub noise: NoiseStats,
}

/// A render with its per-pixel error estimate.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// Linear radiance.
    pub film: Film,
    /// Standard error of each pixel's mean, per channel (linear RGB).
    pub std_error: Film,
    /// What the render did, for `--stats`.
    pub stats: RenderStats,
}

impl RenderStats {
    /// Every ray traced.
    pub fn rays(&self) -> u64 {
        self.camera_rays + self.shadow_rays + self.brdf_rays
    }

    /// Millions of rays (camera + shadow + BRDF) per second of wall time.
    pub fn mrays_per_sec(&self) -> f64 {
        mrays_per(self.rays(), self.wall)
    }

    /// Millions of rays per CPU-second of the render (comparable with `benches/rays.rs`'s
    /// Mrays/CPU-s, the traversal alone), if the CPU time is known.
    pub fn mrays_per_cpu_sec(&self) -> Option<f64> {
        self.cpu.map(|cpu| mrays_per(self.rays(), cpu))
    }
}

/// Millions of `rays` per second of `time` (0 for no time).
fn mrays_per(rays: u64, time: Duration) -> f64 {
    let secs = time.as_secs_f64();
    if secs > 0.0 {
        rays as f64 / secs / 1e6
    } else {
        0.0
    }
}

#[derive(Debug, Clone, Copy)]
struct Tile {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
}

/// Renders the scene. `progress` receives the fraction of tiles done (from worker threads);
/// setting `cancel` stops the render at the next tile boundary.
pub fn render(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(f32) + Sync),
    cancel: &AtomicBool,
) -> Result<(Film, RenderStats), Cancelled> {
    render_with_error(scene, options, progress, cancel).map(|r| (r.film, r.stats))
}

/// [`render`], also returning each pixel's standard error. Adaptive when the scene's
/// `noise` is set (else a fixed count of `samples_per_pixel`, rounded up to a square).
pub fn render_with_error(
    scene: &Scene,
    options: &RenderOptions,
    progress: &(dyn Fn(f32) + Sync),
    cancel: &AtomicBool,
) -> Result<Rendered, Cancelled> {
    let full = PixelWindow::full(scene.settings.width, scene.settings.height);
    render_window(scene, options, full, progress, cancel)
}

/// [`render_with_error`] of the pixels in `window` only (clipped to the image): the films
/// are the window's size, and each pixel has exactly the bits of the full render's
/// (`scnc render --tile K/N`).
pub fn render_window(
    scene: &Scene,
    options: &RenderOptions,
    window: PixelWindow,
    progress: &(dyn Fn(f32) + Sync),
    cancel: &AtomicBool,
) -> Result<Rendered, Cancelled> {
    let start = Instant::now();
    let cpu_start = cpu_time::ProcessTime::try_now().ok();
    let settings = &scene.settings;
    let side = pattern::side_for(settings.samples_per_pixel);
    let offsets = pattern::offsets(side, settings.pattern);
    let max_samples = settings
        .max_samples
        .unwrap_or(crate::ir::DEFAULT_MAX_SAMPLES);
    let camera = PinholeCamera::new(&scene.camera, settings.width, settings.height);
    // Pixels that may see an area light: a fixed-count render takes more samples there, an
    // adaptive one measures how much of each the light covers (both from geometry alone).
    let emitter_pixels = match settings.noise {
        None => EmitterPixels::find(scene, &camera, side),
        Some(_) => EmitterPixels::find(scene, &camera, estimate::BATCH),
    };
    let adaptive = settings.noise.map(|target| Adaptive {
        target: target as f64,
        coverage: EmitterCoverage::find(scene, &camera, &emitter_pixels),
        batch_sizes: estimate::batch_sizes(max_samples),
        emitter_min: estimate::emitter_min_samples(target as f64),
        min: estimate::min_samples(target as f64),
        black_min: estimate::black_min_samples(target as f64),
        dim_floor: estimate::dim_floor(settings.exposure),
    });
    let boosted_offsets = match emitter_pixels.factor() {
        _ if adaptive.is_some() => Vec::new(),
        1 => Vec::new(),
        f => pattern::offsets(side * f, settings.pattern),
    };
    let job = Job {
        scene,
        camera,
        offsets: &offsets,
        emitter_pixels: &emitter_pixels,
        boosted_offsets: &boosted_offsets,
        rect_lit: RectLit::of(scene),
        adaptive,
    };
    let window = window.clip(settings.width, settings.height);
    let tiles = tiles(window);
    let threads = options.threads.unwrap_or(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .ok();
    let used_threads = pool.as_ref().map_or(1, |p| p.current_num_threads());
    // An adaptive render goes band by band (rows of tiles, `bands`), in three passes: the first
    // batches of the band's rows and of a margin of twice `early_stop::RADIUS` rows and
    // columns around them (the rows above kept from the band before); then every pixel of the
    // band and a margin of `RADIUS` to its first whole batch, which may stop early on its
    // neighbours' first batches (`early_stop`); then the band's pixels, which pool their
    // neighbours' replicate spreads there (`pooled_stop`) and go on. A `--tile` window's pixels
    // so decide as in the full render, and only about a band's pixels are held at a time.
    let (width, height) = (settings.width, settings.height);
    let bands = bands(window);
    let (first_fresh, second_fresh) = match job.adaptive {
        Some(_) => (
            fresh_tiles(&bands, 2 * early_stop::RADIUS, width, height),
            fresh_tiles(&bands, early_stop::RADIUS, width, height),
        ),
        None => (Vec::new(), Vec::new()),
    };
    let progress = Progress {
        report: progress,
        done: AtomicUsize::new(0),
        total: tiles.len()
            + first_fresh
                .iter()
                .chain(&second_fresh)
                .map(Vec::len)
                .sum::<usize>(),
    };
    let mut pass_counts = RayCounts::default();
    let results = match job.adaptive {
        None => job.run(&tiles, pool.as_ref(), &progress, cancel, |t, s| {
            job.tile(t, s)
        }),
        Some(ref a) => {
            let mut results = Vec::with_capacity(tiles.len());
            // The band whose first and second passes are done, waiting for its third.
            let mut ready: Option<(PixelWindow, FirstBatches, SecondPass)> = None;
            // The band before last's, whose buffers the next band reuses.
            let (mut spare_first, mut spare_second) = (None, None);
            // A band's third pass runs beside the next band's first two (which read only the
            // band's first batches and states, not its third pass's pixels): each fills the
            // other's last tiles' wait, where three joins a band left a thread idle.
            for k in 0..=bands.len() {
                let spares = (spare_first.take(), spare_second.take());
                let before = ready.as_ref();
                let third = || {
                    before.map(|(band, now, pooling)| {
                        let band_tiles = self::tiles(*band);
                        job.run(&band_tiles, pool.as_ref(), &progress, cancel, |t, s| {
                            job.tile_from_pool(a, t, (now, pooling), s)
                        })
                    })
                };
                let next = || {
                    let band = bands.get(k)?;
                    let fresh = (
                        first_fresh.get(k)?.as_slice(),
                        second_fresh.get(k)?.as_slice(),
                    );
                    let before = before.map(|(_, first, second)| (first, second));
                    let prepared = job.first_passes(
                        a,
                        *band,
                        fresh,
                        before,
                        spares,
                        (pool.as_ref(), &progress, cancel),
                    );
                    Some(prepared.map(|(now, pooling)| (*band, now, pooling)))
                };
                let (done, prepared) = both(pool.as_ref(), third, next);
                results.extend(done.into_iter().flatten());
                let prepared = prepared.transpose()?;
                if let Some((_, now, pooling)) = &prepared {
                    pass_counts.add(&now.counts);
                    pass_counts.add(&pooling.counts);
                }
                if let Some((_, first, second)) = std::mem::replace(&mut ready, prepared) {
                    (spare_first, spare_second) = (Some(first), Some(second));
                }
            }
            results
        }
    };
    if cancel.load(Ordering::Relaxed) {
        return Err(Cancelled);
    }
    let mut rendered = job.assemble(window, &tiles, results, side)?;
    rendered.stats.counts.add(&pass_counts);
    rendered.stats.camera_rays += pass_counts.camera;
    rendered.stats.shadow_rays += pass_counts.shadow;
    rendered.stats.brdf_rays += pass_counts.brdf;
    rendered.stats.wall = start.elapsed();
    rendered.stats.cpu = cpu_start.and_then(|t| t.try_elapsed().ok());
    rendered.stats.threads = used_threads;
    Ok(rendered)
}

/// `work` with this thread's traversal stacks, made at its first tile and kept for its next
/// (fresh ones where a tile's work would reach them again: never, a tile runs no nested jobs).
/// The stacks hold nothing from one query to the next, so which are used changes no bits.
fn with_worker_scratch<T>(work: impl FnOnce(&mut Scratch) -> T) -> T {
    thread_local! {
        static SPARE: std::cell::Cell<Option<Scratch>> = const { std::cell::Cell::new(None) };
    }
    let mut scratch = SPARE.take().unwrap_or_default();
    let out = work(&mut scratch);
    SPARE.set(Some(scratch));
    out
}

/// `a` and `b`, side by side on `pool` (in turn without one: the same results).
fn both<A: Send, B: Send>(
    pool: Option<&rayon::ThreadPool>,
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    match pool {
        Some(pool) => pool.install(|| rayon::join(a, b)),
        None => (a(), b()),
    }
}

/// Tiles done over both passes, for the caller's progress callback.
struct Progress<'a> {
    report: &'a (dyn Fn(f32) + Sync),
    done: AtomicUsize,
    total: usize,
}

/// One tile's pixels and ray counts; `None` when the render was cancelled before it.
type TileResult = Option<(Vec<PixelEstimate>, RayCounts)>;

/// The window's rows of tiles, top to bottom: [`tiles`] of each, in order, are the window's.
///
/// A band is as many rows of tiles as make [`BAND_TILES`] tiles (one row of a wide image):
/// each band's three passes end in a join of the threads, whose waits a small image's bands
/// of one row paid 24 times at 160×120 (docs/quality.md). A pixel's bits do not depend on
/// the bands (as `--tile` windows' do not).
fn bands(window: PixelWindow) -> Vec<PixelWindow> {
    let across = (window.x1.saturating_sub(window.x0))
        .div_ceil(TILE_SIZE)
        .max(1);
    let height = BAND_TILES.div_ceil(across).max(1) * TILE_SIZE;
    (window.y0..window.y1)
        .step_by(height as usize)
        .map(|y0| PixelWindow {
            y0,
            y1: (y0 + height).min(window.y1),
            ..window
        })
        .collect()
}

/// The fewest tiles in an adaptive render's band (short of the window's), which bounds how
/// often the threads join; a band's pixels are what the passes hold at a time.
const BAND_TILES: u32 = 40;

/// For each band, the tiles of its area grown by `margin` that the bands before did not
/// cover (their rows are kept from the band before).
fn fresh_tiles(bands: &[PixelWindow], margin: u32, width: u32, height: u32) -> Vec<Vec<Tile>> {
    let mut covered = None::<PixelWindow>;
    bands
        .iter()
        .map(|band| {
            let area = band.grow(margin, width, height);
            let y0 = covered.map_or(area.y0, |c| c.y1.max(area.y0));
            covered = Some(area);
            tiles(PixelWindow { y0, ..area })
        })
        .collect()
}

fn tiles(window: PixelWindow) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (window.y0..window.y1).step_by(TILE_SIZE as usize) {
        for x0 in (window.x0..window.x1).step_by(TILE_SIZE as usize) {
            out.push(Tile {
                x0,
                y0,
                x1: (x0 + TILE_SIZE).min(window.x1),
                y1: (y0 + TILE_SIZE).min(window.y1),
            });
        }
    }
    out
}

/// Adaptive sampling's settings for the pixel loop.
struct Adaptive {
    target: f64,
    /// Samples of each batch, in order (`estimate::batch_sizes`).
    batch_sizes: Vec<u32>,
    /// The fewest samples a pixel that may see an area light takes
    /// (`estimate::emitter_min_samples`).
    emitter_min: u32,
    /// The fewest samples any pixel takes (`estimate::min_samples`).
    min: u32,
    /// The fewest samples a pixel whose samples are all black takes
    /// (`estimate::black_min_samples`).
    black_min: u32,
    /// How much of each pixel area lights can cover ([`SliverRule`]).
    coverage: EmitterCoverage,
    /// The luminance below which a pixel's error is judged against it
    /// (`estimate::dim_floor`).
    dim_floor: f64,
}

/// What decides an adaptive pixel's stops besides its own samples.
struct PixelRules<'f> {
    /// The fewest samples it takes (the emitter minimum, or 0).
    min: u32,
    /// The sliver rule, where an area light's outline crosses it.
    sliver: Option<SliverRule>,
    /// The samples its neighbours' first batches took (`NeighbourPrior::seen`'s count).
    neighbour_samples: u32,
    /// The first batches and the pixel, which the early stop's prior and spread come from.
    first: &'f FirstBatches,
    at: (u32, u32),
    /// The scatter of its block's first-batch means (`early_stop`): derived at the first look
    /// that may stop early, which most pixels past their first round (and every pixel at 2%
    /// and tighter) never reach.
    spread: OnceCell<FirstBatchSpread>,
    /// Its neighbours' first batches pooled (`early_stop`): derived at the first look that
    /// reads it, after 4 samples (the look after the first batch reads the spread alone).
    prior: OnceCell<NeighbourPrior>,
}

impl PixelRules<'_> {
    /// The early stop's spread (derived once).
    fn spread(&self) -> &FirstBatchSpread {
        let (x, y) = self.at;
        self.spread.get_or_init(|| self.first.spread(x, y))
    }

    /// The early stop's prior (derived once).
    fn prior(&self) -> &NeighbourPrior {
        let (x, y) = self.at;
        self.prior.get_or_init(|| self.first.prior(x, y))
    }
}

struct Job<'a> {
    scene: &'a Scene,
    camera: PinholeCamera,
    offsets: &'a [Vec2],
    /// Pixels that may see an area light ([`emitter_pixels`]).
    emitter_pixels: &'a EmitterPixels,
    /// Their sub-pixel positions (a finer grid of the same pattern).
    boosted_offsets: &'a [Vec2],
    /// The scene's pixels take `rect_lit`'s path (a scene it covers, fixed-count or adaptive).
    rect_lit: Option<RectLit<'a>>,
    adaptive: Option<Adaptive>,
}

impl Job<'_> {
    /// Runs `work` on every tile on `pool` (on this thread without one: the same image, by
    /// construction), checking `cancel` before each; `None` for the tiles it skipped.
    fn run<T: Send>(
        &self,
        tiles: &[Tile],
        pool: Option<&rayon::ThreadPool>,
        progress: &Progress,
        cancel: &AtomicBool,
        work: impl Fn(Tile, &mut Scratch) -> T + Sync,
    ) -> Vec<Option<T>> {
        let each = vec![(); tiles.len()];
        self.run_into(tiles, each, (pool, progress, cancel), |t, (), s| work(t, s))
    }

    /// [`Job::run`], each tile handed its own `outs` item too (its pieces of a band buffer to
    /// write: `tile_rows`).
    fn run_into<U: Send, T: Send>(
        &self,
        tiles: &[Tile],
        outs: Vec<U>,
        (pool, progress, cancel): (Option<&rayon::ThreadPool>, &Progress, &AtomicBool),
        work: impl Fn(Tile, U, &mut Scratch) -> T + Sync,
    ) -> Vec<Option<T>> {
        // One set of traversal stacks per worker, not per tile: an adaptive render runs three
        // passes a band, and fresh stacks for each tile of each cost page faults.
        let run_tile = |scratch: &mut Scratch, (tile, out): (&Tile, U)| {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            let out = work(*tile, out, scratch);
            let n = progress.done.fetch_add(1, Ordering::Relaxed) + 1;
            (progress.report)(n as f32 / progress.total.max(1) as f32);
            Some(out)
        };
        match pool {
            // Every tile its own job (`with_max_len(1)`): rayon otherwise stops splitting
            // after a few halvings and runs what is left as one sequential chunk, so a
            // thread could be left with a chunk of a hundred tiles while the other had
            // nothing to steal (a cornell render's last 220 ms ran on one thread). A tile
            // is 0.1–25 ms of work, so a job per tile costs nothing that shows; the
            // results still come back in tile order, so the image is the same bits.
            // The stacks are the worker's own (`with_worker_scratch`): `map_init` made fresh
            // ones for every job, that is every tile of every pass (16 KB zeroed each: 0.7% of
            // an adaptive 10% render's instructions).
            Some(pool) => pool.install(|| {
                tiles
                    .par_iter()
                    .zip(outs)
                    .with_max_len(1)
                    .map(|item| with_worker_scratch(|scratch| run_tile(scratch, item)))
                    .collect()
            }),
            None => {
                let mut scratch = Scratch::new();
                tiles
                    .iter()
                    .zip(outs)
                    .map(|item| run_tile(&mut scratch, item))
                    .collect()
            }
        }
    }

    /// The tiles' pixels into the window's film, the error film and the statistics (all but
    /// the wall time and thread count); `Cancelled` if a tile is missing.
    fn assemble(
        &self,
        window: PixelWindow,
        tiles: &[Tile],
        results: Vec<TileResult>,
        side: u32,
    ) -> Result<Rendered, Cancelled> {
        let (width, height) = (window.width(), window.height());
        let mut film = Film::new(width, height);
        let mut std_error = Film::new(width, height);
        let mut counts = RayCounts::default();
        let mut noise = NoiseStats {
            target: self.adaptive.as_ref().map(|a| a.target as f32),
            max_samples: self
                .adaptive
                .as_ref()
                .map_or(side * side, |a| a.batch_sizes.iter().sum()),
            ..NoiseStats::default()
        };
        for (tile, result) in tiles.iter().zip(results) {
            let (pixels, c) = result.ok_or(Cancelled)?;
            counts.add(&c);
            let tw = (tile.x1 - tile.x0) as usize;
            for (k, p) in pixels.iter().enumerate() {
                let x = tile.x0 - window.x0 + (k % tw) as u32;
                let y = tile.y0 - window.y0 + (k / tw) as u32;
                film.set(x, y, p.mean);
                std_error.set(x, y, p.std_error);
                noise.add(p);
            }
        }
        noise.finish();
        let samples_per_pixel = match self.adaptive {
            Some(_) => noise.mean_samples().round() as u32,
            None => side * side,
        };
        let stats = RenderStats {
            camera_rays: counts.camera,
            shadow_rays: counts.shadow,
            brdf_rays: counts.brdf,
            wall: Duration::ZERO,
            cpu: None,
            threads: 0,
            samples_per_pixel,
            emitter_pixels: match self.emitter_pixels.boosted() {
                _ if self.adaptive.is_some() => (0, 0),
                0 => (0, 0),
                n => (n, self.boosted_offsets.len() as u32),
            },
            counts,
            noise,
        };
        Ok(Rendered {
            film,
            std_error,
            stats,
        })
    }

    fn tile(&self, t: Tile, scratch: &mut Scratch) -> (Vec<PixelEstimate>, RayCounts) {
        let mut counts = RayCounts::default();
        let mut pixels = Vec::with_capacity(((t.x1 - t.x0) * (t.y1 - t.y0)) as usize);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                pixels.push(self.fixed_pixel(x, y, &mut counts, scratch));
            }
        }
        (pixels, counts)
    }

    /// A band's first two passes (`band`'s area grown by the margins, the tiles `fresh` new to
    /// each): every pixel's first batch, then every pixel to its first whole batch, the rows
    /// above kept from the band `before`, in buffers reused from `spares`.
    fn first_passes(
        &self,
        a: &Adaptive,
        band: PixelWindow,
        (first_fresh, second_fresh): (&[Tile], &[Tile]),
        before: Option<(&FirstBatches, &SecondPass)>,
        (spare_first, spare_second): (Option<FirstBatches>, Option<SecondPass>),
        (pool, progress, cancel): (Option<&rayon::ThreadPool>, &Progress, &AtomicBool),
    ) -> Result<(FirstBatches, SecondPass), Cancelled> {
        let (width, height) = (self.scene.settings.width, self.scene.settings.height);
        let run = (pool, progress, cancel);
        let area = band.grow(2 * early_stop::RADIUS, width, height);
        let first = before.map(|(first, _)| first);
        let mut now = FirstBatches::start(area, first, spare_first);
        let fresh = now.fresh(first_fresh);
        let got = self.run_into(first_fresh, fresh, run, |t, mut rows, s| {
            self.first_batches(t, &mut rows, s)
        });
        let now = now.finish(got)?;
        let area = band.grow(early_stop::RADIUS, width, height);
        let second = before.map(|(_, second)| second);
        let mut pooling = SecondPass::start(area, second, spare_second);
        let fresh = pooling.fresh(second_fresh);
        let got = self.run_into(second_fresh, fresh, run, |t, mut rows, s| {
            self.tile_to_pool(a, t, &now, &mut rows, s)
        });
        let pooling = pooling.finish(got)?;
        Ok((now, pooling))
    }

    /// The first batch of every pixel of the tile (adaptive renders), written into its `rows`
    /// of the band's buffer: the first half of the jointly stratified first round, taken
    /// before any pixel decides (`early_stop`).
    fn first_batches(
        &self,
        t: Tile,
        rows: &mut TileRows<'_, Accumulator>,
        scratch: &mut Scratch,
    ) -> RayCounts {
        let mut counts = RayCounts::default();
        let size = estimate::FIRST_BATCH;
        if let Some(lit) = &self.rect_lit {
            self.first_batches_side_by_side(lit, t, rows, (&mut counts, scratch));
            return counts;
        }
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let sequences = rng::PixelSequences::new(self.scene.settings.seed, x, y);
                let mut acc = Accumulator::default();
                // Filtered for the first round's samples, as its second half is.
                let scale = footprint_scale(early_stop::LAST_EARLY);
                let (samples, sinks) = (0..size, (&mut counts, &mut *scratch));
                self.progressive_batch((x, y), &sequences, samples, scale, &mut acc, sinks);
                if let Some(out) = rows.at(x, y) {
                    *out = acc;
                }
            }
        }
        counts
    }

    /// The tile's pixels in row order, each with its sample sequences (the side-by-side
    /// paths' per-tile lists).
    fn tile_pixels(&self, t: Tile) -> (Vec<(u32, u32)>, Vec<rng::PixelSequences>) {
        let seed = self.scene.settings.seed;
        let pixels: Vec<(u32, u32)> = (t.y0..t.y1)
            .flat_map(|y| (t.x0..t.x1).map(move |x| (x, y)))
            .collect();
        let sequences = pixels
            .iter()
            .map(|&(x, y)| rng::PixelSequences::new(seed, x, y))
            .collect();
        (pixels, sequences)
    }

    /// [`Job::first_batches`] on the rectangle-light path: several pixels' first batches a
    /// run (`RectLit::side_by_side`), the same sums.
    fn first_batches_side_by_side(
        &self,
        lit: &RectLit<'_>,
        t: Tile,
        rows: &mut TileRows<'_, Accumulator>,
        (counts, scratch): (&mut RayCounts, &mut Scratch),
    ) {
        let size = estimate::FIRST_BATCH;
        let (pixels, sequences) = self.tile_pixels(t);
        let mut accs = vec![Accumulator::default(); pixels.len()];
        let per_run = RectLit::pixels_a_run(size);
        for start in (0..pixels.len()).step_by(per_run) {
            let n = per_run.min(pixels.len() - start);
            let pixel = |k: usize| (pixels[start + k], &sequences[start + k]);
            let add = |k: usize, l, replicate| accs[start + k].add_replicate(l, replicate);
            let sinks = (&mut *counts, &mut *scratch);
            lit.side_by_side(&self.camera, (n, pixel), 0..size, add, sinks.0, sinks.1);
        }
        for (&(x, y), acc) in pixels.iter().zip(&accs) {
            if let Some(out) = rows.at(x, y) {
                *out = *acc;
            }
        }
    }

    /// [`Job::tile_to_pool`] on the rectangle-light path: batch by batch over the tile's
    /// pixels, those that go on taking a batch of a few samples several pixels a run
    /// (`RectLit::side_by_side`); each pixel's batches, looks and stop are
    /// [`Job::pixel_to_pool`]'s, so the same bits.
    #[allow(clippy::too_many_arguments)] // reason: the tile, its buffers and the sinks
    fn tile_to_pool_side_by_side(
        &self,
        a: &Adaptive,
        lit: &RectLit<'_>,
        t: Tile,
        first: &FirstBatches,
        rows: &mut TileRows<'_, Option<PixelState>>,
        (counts, scratch): (&mut RayCounts, &mut Scratch),
    ) {
        let (pixels, sequences) = self.tile_pixels(t);
        let rules: Vec<_> = pixels
            .iter()
            .map(|&(x, y)| self.rules(a, x, y, first))
            .collect();
        let mut accs = vec![Accumulator::default(); pixels.len()];
        let mut open: Vec<usize> = (0..pixels.len()).collect();
        let mut taken = 0;
        for (batch, &size) in a.batch_sizes.iter().enumerate().take(POOL_BATCH + 1) {
            let per_run = RectLit::pixels_a_run(size);
            if batch == 0 {
                // Taken in the first pass, for every pixel.
                for &i in &open {
                    let (x, y) = pixels[i];
                    accs[i] = first.at(x, y).copied().unwrap_or_default();
                }
            } else if per_run > 1 {
                for run in open.chunks(per_run) {
                    let pixel = |k: usize| (pixels[run[k]], &sequences[run[k]]);
                    let add = |k: usize, l, replicate| accs[run[k]].add_replicate(l, replicate);
                    let sinks = (&mut *counts, &mut *scratch);
                    let samples = taken..taken + size;
                    let n = run.len();
                    lit.side_by_side(&self.camera, (n, pixel), samples, add, sinks.0, sinks.1);
                }
            } else {
                let scale = footprint_scale(taken + size);
                for &i in &open {
                    let samples = taken..taken + size;
                    let sinks = (&mut *counts, &mut *scratch);
                    let acc = &mut accs[i];
                    self.progressive_batch(pixels[i], &sequences[i], samples, scale, acc, sinks);
                }
            }
            taken += size;
            open.retain(|&i| {
                let acc = accs[i];
                let state = match batch == POOL_BATCH {
                    true => Some(PixelState::Pooling { acc, taken }),
                    false => self
                        .decide(a, &rules[i], &acc, taken, None)
                        .map(PixelState::Done),
                };
                let Some(state) = state else {
                    return true;
                };
                let (x, y) = pixels[i];
                if let Some(out) = rows.at(x, y) {
                    *out = Some(state);
                }
                false
            });
        }
        for i in open {
            let (x, y) = pixels[i];
            if let Some(out) = rows.at(x, y) {
                *out = Some(PixelState::Done(accs[i].finish(taken, true)));
            }
        }
    }

    /// Every pixel of the tile to its first whole batch, unless it stops before
    /// ([`PixelState`]), taken before any pixel decides on it (`pooled_stop`), written into
    /// its `rows` of the band's buffer.
    fn tile_to_pool(
        &self,
        a: &Adaptive,
        t: Tile,
        first: &FirstBatches,
        rows: &mut TileRows<'_, Option<PixelState>>,
        scratch: &mut Scratch,
    ) -> RayCounts {
        let mut counts = RayCounts::default();
        if let Some(lit) = &self.rect_lit {
            let sinks = (&mut counts, scratch);
            self.tile_to_pool_side_by_side(a, lit, t, first, rows, sinks);
            return counts;
        }
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let state = self.pixel_to_pool(a, x, y, first, &mut counts, scratch);
                if let Some(out) = rows.at(x, y) {
                    *out = Some(state);
                }
            }
        }
        counts
    }

    /// The tile's pixels from their first whole batch on to their stop.
    fn tile_from_pool(
        &self,
        a: &Adaptive,
        t: Tile,
        (first, pooling): (&FirstBatches, &SecondPass),
        scratch: &mut Scratch,
    ) -> (Vec<PixelEstimate>, RayCounts) {
        let mut counts = RayCounts::default();
        let mut pixels = Vec::with_capacity(((t.x1 - t.x0) * (t.y1 - t.y0)) as usize);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let sinks = (&mut counts, &mut *scratch);
                pixels.push(self.pixel_from_pool(a, (x, y), first, pooling, sinks));
            }
        }
        (pixels, counts)
    }

    /// Box filter: the plain mean of a fixed count of samples.
    fn fixed_pixel(
        &self,
        x: u32,
        y: u32,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) -> PixelEstimate {
        let mut acc = Accumulator::default();
        let offsets = match self.emitter_pixels.factor_at(x, y) {
            1 => self.offsets,
            _ => self.boosted_offsets,
        };
        let scale = footprint_scale(offsets.len() as u32);
        self.batch(x, y, (offsets, scale), &mut acc, counts, scratch);
        acc.finish(offsets.len() as u32, false)
    }

    /// What decides an adaptive pixel's stops besides its own samples.
    fn rules<'f>(&self, a: &Adaptive, x: u32, y: u32, first: &'f FirstBatches) -> PixelRules<'f> {
        PixelRules {
            // Emitter pixels' minimum is never cut short; `a.min` may be (`early_stop`).
            min: match self.emitter_pixels.factor_at(x, y) {
                1 => 0,
                _ => a.emitter_min.max(a.min),
            },
            sliver: a.coverage.at(x, y).map(|(share, luminance)| SliverRule {
                share: share as f64,
                luminance: luminance as f64,
            }),
            neighbour_samples: first.neighbour_samples(x, y),
            first,
            at: (x, y),
            spread: OnceCell::new(),
            prior: OnceCell::new(),
        }
    }

    /// Batch `batch` of an adaptive pixel (`size` samples, `taken` before it): the first from
    /// the first pass, the others sampled.
    #[allow(clippy::too_many_arguments)] // reason: the pixel, its batch and the sinks
    fn adaptive_batch(
        &self,
        (x, y): (u32, u32),
        sequences: &rng::PixelSequences,
        first: &FirstBatches,
        (batch, size): (usize, u32),
        taken: &mut u32,
        acc: &mut Accumulator,
        (counts, scratch): (&mut RayCounts, &mut Scratch),
    ) {
        if batch == 0 {
            // Taken in the first pass, for every pixel.
            *acc = first.at(x, y).copied().unwrap_or_default();
        } else {
            // Textures are filtered for the samples the pixel will have by this batch's end.
            let scale = footprint_scale(*taken + size);
            let samples = *taken..*taken + size;
            let sinks = (&mut *counts, &mut *scratch);
            self.progressive_batch((x, y), sequences, samples, scale, acc, sinks);
        }
        *taken += size;
    }

    /// An adaptive pixel up to its first whole batch ([`POOL_BATCH`]), or to its stop if it
    /// comes before (decided from this pixel's samples and its neighbours' first batches).
    fn pixel_to_pool(
        &self,
        a: &Adaptive,
        x: u32,
        y: u32,
        first: &FirstBatches,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) -> PixelState {
        let sequences = rng::PixelSequences::new(self.scene.settings.seed, x, y);
        let rules = self.rules(a, x, y, first);
        let mut acc = Accumulator::default();
        let mut taken = 0;
        for (batch, &size) in a.batch_sizes.iter().enumerate().take(POOL_BATCH + 1) {
            let at = (x, y);
            self.adaptive_batch(
                at,
                &sequences,
                first,
                (batch, size),
                &mut taken,
                &mut acc,
                (&mut *counts, &mut *scratch),
            );
            if batch == POOL_BATCH {
                return PixelState::Pooling { acc, taken };
            }
            if let Some(e) = self.decide(a, &rules, &acc, taken, None) {
                return PixelState::Done(e);
            }
        }
        PixelState::Done(acc.finish(taken, true))
    }

    /// An adaptive pixel from its first whole batch (`pooling`) on: the pooled stop there, then
    /// batches until its relative error reaches the target (decided from this pixel's samples,
    /// and before `1/target` samples from its neighbours' first batches).
    fn pixel_from_pool(
        &self,
        a: &Adaptive,
        (x, y): (u32, u32),
        first: &FirstBatches,
        pooling: &SecondPass,
        (counts, scratch): (&mut RayCounts, &mut Scratch),
    ) -> PixelEstimate {
        // Every band pixel is in the second pass; taking it again would give the same bits.
        let state = match pooling.at(x, y) {
            Some(state) => *state,
            None => self.pixel_to_pool(a, x, y, first, counts, scratch),
        };
        let (mut acc, mut taken) = match state {
            PixelState::Done(estimate) => return estimate,
            PixelState::Pooling { acc, taken } => (acc, taken),
        };
        let rules = self.rules(a, x, y, first);
        let pool = pooling.pool(x, y);
        if let Some(e) = self.decide(a, &rules, &acc, taken, Some(&pool)) {
            return e;
        }
        let sequences = rng::PixelSequences::new(self.scene.settings.seed, x, y);
        for (batch, &size) in a.batch_sizes.iter().enumerate().skip(POOL_BATCH + 1) {
            let at = (x, y);
            self.adaptive_batch(
                at,
                &sequences,
                first,
                (batch, size),
                &mut taken,
                &mut acc,
                (&mut *counts, &mut *scratch),
            );
            if let Some(e) = self.decide(a, &rules, &acc, taken, None) {
                return e;
            }
        }
        acc.finish(taken, true)
    }

    /// The pixel's estimate if it may stop after `taken` samples; `None` if it goes on. `pool`:
    /// its block's replicate spreads, after its first whole batch (`pooled_stop`).
    fn decide(
        &self,
        a: &Adaptive,
        rules: &PixelRules,
        acc: &Accumulator,
        taken: u32,
        pool: Option<&ReplicatePool>,
    ) -> Option<PixelEstimate> {
        let black = acc.is_black() && taken < a.black_min;
        let unseen = rules
            .sliver
            .is_some_and(|r| r.holds(taken, acc.mean_luminance(), acc.brightest(), a.target));
        if taken < rules.min || black || unseen {
            return None;
        }
        if taken < a.min && taken <= early_stop::LAST_EARLY {
            // `confident_error` would say `None` without them (`early_stop::may_look`).
            if !early_stop::may_look(acc.count(), rules.neighbour_samples, a.target) {
                return None;
            }
            let (samples, spread) = (rules.neighbour_samples, rules.spread());
            let prior = || rules.prior();
            let e = early_stop::confident_error_with(acc, samples, spread, prior, a.target)?;
            return Some(acc.finish_with(taken, false, e));
        }
        if taken.saturating_add(rules.neighbour_samples) < a.min {
            return None;
        }
        // `1/target` samples counted over the pixel and its neighbours' first batches (the
        // rule of three, as for the early stop). The pooled stop and the cap on the per-sample
        // prior only once the pixel alone has taken them: before, it leans on its neighbours'
        // count, and the prior at full weight keeps soft_shadows' bright walls at 2% sampling
        // on (docs/quality.md).
        // Pixels darker than the dim floor judged against it (`estimate::dim_scale`).
        let target = a.target * estimate::dim_scale(acc.mean_luminance(), a.dim_floor);
        if taken >= a.min {
            if let Some(e) = pool.and_then(|p| pooled_stop::pooled_error(acc, p, target)) {
                return Some(acc.finish_with(taken, false, e));
            }
        }
        let error = match taken >= a.min {
            true => acc.stopping_error(),
            false => acc.relative_error(),
        };
        (error <= target).then(|| acc.finish(taken, false))
    }

    /// Samples `samples` (counted over all the pixel's batches) of an adaptive pixel: each
    /// continues its replicate's sequences, sub-pixel position and light samples alike.
    #[allow(clippy::too_many_arguments)] // reason: the pixel, its sequences and the sinks
    fn progressive_batch(
        &self,
        (x, y): (u32, u32),
        sequences: &rng::PixelSequences,
        samples: std::ops::Range<u32>,
        footprint_scale: f32,
        acc: &mut Accumulator,
        (counts, scratch): (&mut RayCounts, &mut Scratch),
    ) {
        if let Some(lit) = &self.rect_lit {
            // Its scenes have no textures: the footprint scale is unread.
            let samples = Samples::Progressive { sequences, samples };
            lit.pixel(&self.camera, (x, y), samples, acc, counts, scratch);
            return;
        }
        // The sub-pixel positions a batch at a time, apart from the rays (`points_2d`).
        let mut offsets = [Vec2::ZERO; estimate::BATCH as usize];
        let mut next = samples.start;
        while next < samples.end {
            let chunk = next..samples.end.min(next + estimate::BATCH);
            sequences.points_2d(rng::STREAM_SUBPIXEL, chunk.clone(), &mut offsets);
            for (g, &o) in chunk.clone().zip(&offsets) {
                let mut sampler = sequences.sampler(g);
                let ray = self.camera.ray(Vec2::new(x as f32, y as f32) + o);
                let l = radiance_scaled(self.scene, &ray, footprint_scale, &mut sampler, counts);
                if l.is_finite() {
                    acc.add_replicate(l, rng::PixelSequences::replicate(g));
                } else {
                    counts.nonfinite += 1;
                }
            }
            next = chunk.end;
        }
    }

    /// The pixel's samples, one at each of `offsets`, stratified together (a fixed-count
    /// render's one batch), textures filtered with the footprint scaled by `footprint_scale`.
    fn batch(
        &self,
        x: u32,
        y: u32,
        (offsets, footprint_scale): (&[Vec2], f32),
        acc: &mut Accumulator,
        counts: &mut RayCounts,
        scratch: &mut Scratch,
    ) {
        let count = offsets.len() as u32;
        let seed = self.scene.settings.seed;
        // The pattern is shifted (toroidally, which keeps the rotated grid's one sample per row
        // and column) by its own random offset per pixel (Cranley–Patterson rotation). A fixed
        // pattern would be a fixed quadrature of the pixel's footprint: its error at edges
        // never averages out, whatever the seed.
        // A single sample stays at the pixel centre: a 1-spp render is a point-sampled image
        // (sharp, and what closed-form tests of one pixel expect).
        let samplers = rng::PixelBatch::new(seed, x, y, 0, count);
        let shift = if count > 1 {
            let bits = samplers.pixel_bits(rng::STREAM_SUBPIXEL);
            Vec2::new(rng::unit(bits), rng::unit(bits << 24))
        } else {
            Vec2::ZERO
        };
        if let Some(lit) = &self.rect_lit {
            let samples = Samples::Fixed {
                offsets,
                shift,
                samplers: &samplers,
            };
            lit.pixel(&self.camera, (x, y), samples, acc, counts, scratch);
            return;
        }
        for (s, offset) in offsets.iter().enumerate() {
            let o = *offset + shift;
            let o = Vec2::new(rng::wrap_unit(o.x), rng::wrap_unit(o.y));
            let ray = self.camera.ray(Vec2::new(x as f32, y as f32) + o);
            let mut sampler = samplers.sampler(s as u32);
            let l = radiance_scaled(self.scene, &ray, footprint_scale, &mut sampler, counts);
            // A non-finite sample (a degenerate configuration the guards missed) must not
            // poison the pixel; it is counted for `--stats` instead (and as black in the mean).
            if l.is_finite() {
                acc.add(l);
            } else {
                counts.nonfinite += 1;
            }
        }
    }
}
