//! Stage 4, render: what each row of the image costs to render, for the cost-balanced split
//! of `scnc render --tile K/N` ([`window::split_by_cost`](super::window::split_by_cost)).
//!
//! A cheap pre-pass traces one camera path (the full integrator: shadow rays, BRDF rays) at
//! the centre of every `stride`-th pixel of every `stride`-th row, and counts the work it did:
//! BVH nodes tested and primitives handed to leaf tests (`bvh::tally`), plus a fixed amount
//! per ray traced. Counts, not times: every machine computes the same costs for the same
//! scene and settings (the paths are the render's own, seeded per pixel), so every tile
//! process cuts the same bands without talking to the others. The pre-pass runs on the
//! calling thread, so the thread-local count holds this pass's work alone. Rows crossing the
//! pixels that may see an area light (which a fixed-count render samples more,
//! `emitter_pixels`) add those pixels' extra samples at the row's average path cost.

use glam::Vec2;

use super::camera::PinholeCamera;
use super::emitter_pixels::EmitterPixels;
use super::integrator::{radiance, RayCounts};
use super::pattern;
use super::rng::Sampler;
use crate::bvh::tally;
use crate::scene::Scene;

/// Paths the pre-pass traces at most (about): 16,384 is a 128×128 thumbnail, a few
/// milliseconds to a few tens on a dense scene, small beside the BVH build every tile repeats.
pub const PATH_BUDGET: u64 = 16_384;

/// Work counted per ray traced, on top of its BVH work: generating and shading it (a ray that
/// misses the scene's bounds visits no node yet still costs a camera ray and a sky lookup).
const RAY_COST: u64 = 8;

/// The cost of each of the image's rows (one entry per row, each at least 1): rows in the
/// same `stride`-row block share the cost of the block's traced row.
pub fn row_costs(scene: &Scene) -> Vec<u64> {
    let (width, height) = (scene.settings.width, scene.settings.height);
    if width == 0 || height == 0 {
        return Vec::new();
    }
    let stride = stride_for(width, height);
    let camera = PinholeCamera::new(&scene.camera, width, height);
    let seed = scene.settings.seed;
    // Pixels that may see an area light take more samples in a fixed-count render
    // (`emitter_pixels`): their rows cost that much more.
    let light_pixels = match scene.settings.noise {
        None => EmitterPixels::find(
            scene,
            &camera,
            pattern::side_for(scene.settings.samples_per_pixel),
        ),
        Some(_) => EmitterPixels::none(),
    };
    let extra_per_boosted = u64::from(light_pixels.factor().pow(2) - 1);
    let mut costs = Vec::with_capacity(height as usize);
    for block in (0..height).step_by(stride as usize) {
        let rows = stride.min(height - block);
        let y = block + rows / 2;
        let mut cost = 1u64;
        for x in (stride / 2..width).step_by(stride as usize) {
            let mut counts = RayCounts::default();
            let before = tally::visits();
            let ray = camera.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let mut sampler = Sampler::for_batch_sample(seed, x, y, 0, 0, 1);
            // The radiance is not wanted: only the work it took.
            let _ = radiance(scene, &ray, &mut sampler, &mut counts);
            let visits = tally::visits().wrapping_sub(before);
            let rays = counts.camera + counts.shadow + counts.brdf;
            cost = cost.saturating_add(visits.saturating_add(rays * RAY_COST));
        }
        // `cost` sums the traced pixels of the row, about width / stride of them: a boosted
        // pixel adds (factor² − 1) of an average pixel, cost · stride / width each.
        for row in block..block + rows {
            let boosted = if extra_per_boosted == 0 {
                0
            } else {
                (0..width)
                    .filter(|&x| light_pixels.factor_at(x, row) > 1)
                    .count() as u64
            };
            let extra = boosted * extra_per_boosted * cost * u64::from(stride) / u64::from(width);
            costs.push(cost.saturating_add(extra));
        }
    }
    costs
}

/// Every `stride`-th pixel of every `stride`-th row keeps the pre-pass near [`PATH_BUDGET`].
fn stride_for(width: u32, height: u32) -> u32 {
    let pixels = u64::from(width) * u64::from(height);
    let mut stride = 1u32;
    while pixels / (u64::from(stride) * u64::from(stride)) > PATH_BUDGET {
        stride += 1;
    }
    stride
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stride_keeps_the_pass_within_budget() {
        assert_eq!(stride_for(64, 64), 1);
        assert_eq!(stride_for(128, 128), 1);
        let s = stride_for(2048, 2048);
        assert!(2048 * 2048 / u64::from(s * s) <= PATH_BUDGET);
        assert!(2048 * 2048 / u64::from((s - 1) * (s - 1)) > PATH_BUDGET);
    }
}
