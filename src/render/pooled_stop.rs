//! Stage 4: the stop after an adaptive pixel's first whole batch (its first round and one
//! 4-point block of each replicate: 20 samples), on its own and its neighbours' replicate
//! spreads pooled.
//!
//! Syntax: no syntax of its own; it decides for `render { noise 0.1 }` / `--noise 0.1`.
//!
//! A pixel's four replicates give an estimate of its error with 3 degrees of freedom: stopping
//! whenever it says "within the target" stops pixels on a luckily small value, so the later
//! stops (`estimate::Accumulator::stopping_error`) lean on the per-sample variance as a prior,
//! which over-states stratified samples' error and keeps dim penumbrae sampling to about 40 at
//! 10% (docs/quality.md). Here every pixel of a band and a one-pixel margin has taken its first
//! whole batch before any decides (`render::second_pass`), so a pixel pools the replicate
//! spreads of its 3×3 block (its own and those of the neighbours that did not stop early),
//! each relative to its own squared mean and weighted by its degrees of freedom: up to 27
//! degrees of freedom, enough to decide without the prior. As at the 4-sample early stop, the
//! pixel's own replicates must also be within twice the target ([`OWN_OVER_TARGET_SQ`]), so a
//! pixel that differs from its block (a noisier neighbour of quieter ones) samples on, and it
//! reports the posterior mean of the pooled variance (`early_stop::posterior_mean`), which
//! accounts for its stopping because the estimate came out low.
//!
//! Deterministic for any thread count and tiling: a pixel's first whole batch, and whether it
//! stopped before it, depend on its own samples and its neighbours' first batches only.

use super::early_stop::posterior_mean;
use super::estimate::{Accumulator, REL_FLOOR};

/// The batch (index into `estimate::batch_sizes`) after which the pooled stop decides: the
/// first whole batch of the replicates, after the first round's two halves.
pub const POOL_BATCH: usize = 2;

/// The fewest pooled degrees of freedom the stop decides on (the pixel's own 3 and at least
/// three neighbours'); with fewer it leaves the decision to the pixel's own rule.
pub const MIN_POOLED_DOF: f64 = 12.0;

/// How far over the target (in variance) the pixel's own replicates' estimate may be.
pub const OWN_OVER_TARGET_SQ: f64 = 4.0;

/// The relative replicate variances of a block, pooled (weighted by degrees of freedom).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReplicatePool {
    /// Per-sample between-replicate variance over the squared mean, pooled.
    relative_variance: f64,
    /// Degrees of freedom pooled (0: nothing to pool).
    dof: f64,
}

impl ReplicatePool {
    /// Pools `(relative variance, degrees of freedom)` pairs
    /// (`Accumulator::relative_replicate_variance` of the block's pixels that took their
    /// first whole batch).
    pub fn pool(block: impl IntoIterator<Item = (f64, f64)>) -> ReplicatePool {
        let (mut weighted, mut dof) = (0.0, 0.0);
        for (r, d) in block {
            weighted += r * d;
            dof += d;
        }
        ReplicatePool {
            relative_variance: if dof > 0.0 { weighted / dof } else { 0.0 },
            dof,
        }
    }
}

/// The pixel's relative standard error if it may stop now on the pooled estimate, at `target`;
/// `None` if it must go on (or leave the decision to its own rule).
pub fn pooled_error(acc: &Accumulator, pool: &ReplicatePool, target: f64) -> Option<f64> {
    if pool.dof < MIN_POOLED_DOF {
        return None;
    }
    let (own, _) = acc.relative_replicate_variance()?;
    let n = acc.count() as f64;
    let floor = (REL_FLOOR / n / acc.mean_luminance().abs().max(REL_FLOOR)).powi(2);
    let limit = target * target;
    let within = |r: f64, scale: f64| r / n + floor <= scale * limit;
    (within(pool.relative_variance, 1.0) && within(own, OWN_OVER_TARGET_SQ))
        .then(|| (posterior_mean(pool.relative_variance, pool.dof) / n + floor).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A pixel at 20 samples: a first round of 4 (in the mean only), then 4 points of each
    /// replicate, replicate `r`'s samples all `mean · (1 + shifts[r])`.
    fn pixel(mean: f32, shifts: [f32; 4]) -> Accumulator {
        let mut acc = Accumulator::default();
        for _ in 0..4 {
            acc.add_replicate(Vec3::splat(mean), None);
        }
        for g in 0..16 {
            let r = g % 4;
            acc.add_replicate(Vec3::splat(mean * (1.0 + shifts[r])), Some(r));
        }
        acc
    }

    #[test]
    fn the_pool_weights_each_spread_by_its_degrees_of_freedom() {
        let pool = ReplicatePool::pool([(1.0, 3.0), (4.0, 3.0), (0.5, 6.0)]);
        assert!((pool.relative_variance - (3.0 + 12.0 + 3.0) / 12.0).abs() < 1e-12);
        assert_eq!(pool.dof, 12.0);
        assert_eq!(ReplicatePool::pool([]), ReplicatePool::default());
    }

    #[test]
    fn a_pixel_stops_on_its_block_when_its_own_replicates_agree() {
        let target = 0.1;
        // Replicate means ±10% about the mean: relative replicate variance (per sample) about
        // 4 · 4 · 0.01 / 3 / 1 ≈ 0.053, over 20 samples 0.0027 ≤ 0.01.
        let steady = pixel(0.5, [0.1, -0.1, 0.1, -0.1]);
        let (own, dof) = steady
            .relative_replicate_variance()
            .expect("every replicate");
        assert_eq!(dof, 3.0);
        let block = ReplicatePool::pool([(own, dof); 9]);
        let e = pooled_error(&steady, &block, target).expect("within the target");
        // It reports the posterior mean of the pooled variance: 27/25 of it.
        let n = 20.0;
        let expected = (own * 27.0 / 25.0 / n).sqrt();
        assert!(
            (e - expected).abs() < 1e-3 * expected,
            "{e} against {expected}"
        );
        // Too few degrees of freedom (the pixel and two neighbours): no decision here.
        let thin = ReplicatePool::pool([(own, dof); 3]);
        assert_eq!(pooled_error(&steady, &thin, target), None);
        // A block that is noisier than the target does not let it stop.
        let noisy = ReplicatePool::pool([(1.0, 3.0); 9]);
        assert_eq!(pooled_error(&steady, &noisy, target), None);
        // A pixel whose own replicates disagree by far more than its quiet block's does not
        // stop on their say (±60%: 4 · 0.36 · 16 / 3 / 20 ≈ 0.38 > 4 · 0.01).
        let swinging = pixel(0.5, [0.6, -0.6, 0.6, -0.6]);
        assert_eq!(pooled_error(&swinging, &block, target), None);
        // A black pixel has no relative spread to pool or to check.
        assert_eq!(pooled_error(&pixel(0.0, [0.0; 4]), &block, target), None);
    }
}
