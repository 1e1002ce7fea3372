//! Stage 4, render: [`Scene`] → [`Film`] (linear RGB radiance per pixel).
//!
//! Syntax it executes: `render { resolution 512 x 512  samples rgss 4  light_samples 1
//! seed 0 }`. The image is cut into 16×16 tiles rendered in parallel on a local rayon pool;
//! each pixel's value depends only on its own samples (sub-pixel positions from
//! [`pattern`], random numbers hashed from pixel, sample and seed in [`rng`]), so the image is
//! bit-identical for any thread count. Cancellation is checked before every tile.

pub mod brdf;
pub mod camera;
pub mod footprint;
pub mod integrator;
mod mis;
pub mod normal_map;
pub mod pattern;
pub mod rng;
pub mod sampling;
pub mod spherical;
pub mod surface;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use self::camera::PinholeCamera;
use self::integrator::{radiance, RayCounts};
use self::rng::Sampler;
use crate::film::Film;
use crate::scene::Scene;

pub const TILE_SIZE: u32 = 16;

/// Command-line overrides of the scene's `render { }` block.
#[derive(Debug, Clone, Copy, Default)]
pub struct RenderOptions {
    /// `--spp N`: samples per pixel; rounded up to the next perfect square N² (the patterns
    /// are N×N). `None` keeps the scene's.
    pub spp: Option<u32>,
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
    pub camera_rays: u64,
    pub shadow_rays: u64,
    /// BRDF-sampled rays (multiple importance sampling of area lights and the environment).
    pub brdf_rays: u64,
    pub wall: Duration,
    pub threads: usize,
    pub samples_per_pixel: u32,
    /// Rays by kind, optional feature paths taken, and samples dropped as NaN or infinite.
    pub counts: RayCounts,
}

impl RenderStats {
    pub fn rays(&self) -> u64 {
        self.camera_rays + self.shadow_rays + self.brdf_rays
    }

    /// Millions of rays (camera + shadow + BRDF) per second of wall time.
    pub fn mrays_per_sec(&self) -> f64 {
        let secs = self.wall.as_secs_f64();
        if secs > 0.0 {
            self.rays() as f64 / secs / 1e6
        } else {
            0.0
        }
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
    let start = Instant::now();
    let (width, height) = (scene.settings.width, scene.settings.height);
    let side = pattern::side_for(options.spp.unwrap_or(scene.settings.samples_per_pixel));
    let offsets = pattern::offsets(side, scene.settings.pattern);
    let camera = PinholeCamera::new(&scene.camera, width, height);
    let tiles = tiles(width, height);
    let done = AtomicUsize::new(0);
    let job = Job {
        scene,
        camera,
        offsets: &offsets,
    };
    let run_tile = |tile: &Tile| {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let out = job.tile(*tile);
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress(n as f32 / tiles.len().max(1) as f32);
        Some(out)
    };
    let threads = options.threads.unwrap_or(0);
    let results: Vec<Option<(Vec<Vec3>, RayCounts)>> =
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(|| tiles.par_iter().map(run_tile).collect()),
            // No threads to be had: render on this one (same image, by construction).
            Err(_) => tiles.iter().map(run_tile).collect(),
        };
    let used_threads = match threads {
        0 => rayon::current_num_threads(),
        n => n,
    };
    if cancel.load(Ordering::Relaxed) {
        return Err(Cancelled);
    }
    let mut film = Film::new(width, height);
    let mut counts = RayCounts::default();
    for (tile, result) in tiles.iter().zip(results) {
        let (pixels, c) = result.ok_or(Cancelled)?;
        counts.add(&c);
        let tw = (tile.x1 - tile.x0) as usize;
        for (k, value) in pixels.into_iter().enumerate() {
            film.set(tile.x0 + (k % tw) as u32, tile.y0 + (k / tw) as u32, value);
        }
    }
    let stats = RenderStats {
        camera_rays: counts.camera,
        shadow_rays: counts.shadow,
        brdf_rays: counts.brdf,
        wall: start.elapsed(),
        threads: used_threads,
        samples_per_pixel: side * side,
        counts,
    };
    Ok((film, stats))
}

fn tiles(width: u32, height: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(TILE_SIZE as usize) {
        for x0 in (0..width).step_by(TILE_SIZE as usize) {
            out.push(Tile {
                x0,
                y0,
                x1: (x0 + TILE_SIZE).min(width),
                y1: (y0 + TILE_SIZE).min(height),
            });
        }
    }
    out
}

struct Job<'a> {
    scene: &'a Scene,
    camera: PinholeCamera,
    offsets: &'a [Vec2],
}

impl Job<'_> {
    fn tile(&self, t: Tile) -> (Vec<Vec3>, RayCounts) {
        let mut counts = RayCounts::default();
        let mut pixels = Vec::with_capacity(((t.x1 - t.x0) * (t.y1 - t.y0)) as usize);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                pixels.push(self.pixel(x, y, &mut counts));
            }
        }
        (pixels, counts)
    }

    /// Box filter: the plain mean of the pixel's samples.
    pub fn pixel(&self, x: u32, y: u32, counts: &mut RayCounts) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for (s, offset) in self.offsets.iter().enumerate() {
            let ray = self.camera.ray(Vec2::new(x as f32, y as f32) + *offset);
            let count = self.offsets.len() as u32;
            let mut sampler =
                Sampler::for_pixel_sample(self.scene.settings.seed, x, y, s as u32, count);
            let l = radiance(self.scene, &ray, &mut sampler, counts);
            // A non-finite sample (a degenerate configuration the guards missed) must not
            // poison the pixel; it is counted for `--stats` instead.
            if l.is_finite() {
                sum += l;
            } else {
                counts.nonfinite += 1;
            }
        }
        sum / self.offsets.len() as f32
    }
}
