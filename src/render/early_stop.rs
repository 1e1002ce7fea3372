//! Stage 4: when an adaptive pixel may stop before `estimate::min_samples` (`1/target`), after
//! its first 4 or 8 samples, from its own samples and its neighbours' first batches.
//!
//! Syntax: no syntax of its own; it decides for `render { noise 0.1 }` / `--noise 0.1`.
//!
//! A pixel that sees a flat, directly lit wall is done after a few samples (cornell's walls
//! measure 3.5% after 8), but its own estimate after 4 or 8 samples has 3 or 7 degrees of
//! freedom: stopping whenever it says "within the target" stops pixels on a luckily small
//! value (texture_bench at 1.4× its target, docs/quality.md). Its neighbours know more. Every
//! pixel takes a first batch of one sample per replicate (independent uniform samples), so
//! before any pixel goes on, each has an unbiased estimate of its per-sample relative variance
//! with 3 degrees of freedom; the [`NeighbourPrior`] pools those of the `(2·RADIUS+1)²−1`
//! neighbours (24 degrees of freedom in 3×3). Relative variance, not variance: it carries over
//! between neighbours of different brightness (a texture, a falloff) where the variance does
//! not.
//!
//! The pixel's own per-sample estimate is shrunk toward its neighbourhood's (both weighted by
//! their degrees of freedom), and the pixel stops early only if the **upper confidence bound**
//! of that estimate, at [`CONFIDENCE`] for the pooled degrees of freedom (chi-square quantile),
//! is within the target, its own estimate alone is too, and it and its neighbours together have
//! taken `1/target` samples (the rule of three behind `estimate::min_samples`: the
//! neighbourhood has seen what the pixel alone could not have yet). The figure reported is the
//! estimate, not the bound. The black-pixel, emitter and sliver rules still apply first.
//!
//! Deterministic for any thread count and any tiling: the prior uses the neighbours' first
//! batches only, which every pixel takes whatever happens next and which a render computes for
//! all pixels (and a one-pixel margin around a `--tile` window) before any pixel goes on.

use super::estimate::{Accumulator, REL_FLOOR};

/// One-sided confidence with which an early stop's relative error is within the target.
pub const CONFIDENCE: f64 = 0.9;
/// The standard normal quantile of [`CONFIDENCE`] (the chi-square quantile is Wilson and
/// Hilferty's approximation from it, [`chi_square_lower`]).
const Z_CONFIDENCE: f64 = 1.281_551_565_5;
/// The most samples after which a pixel may stop early: its first two batches, whose samples
/// are independent (4) or nearly (8: two points of each replicate's sequence), so that the
/// per-sample variance is the right estimate. Later, stratification makes it over-state the
/// error (cornell at 2%, stopping early at 24 and 40 samples: reported 1.27× the measured,
/// against 1.03× without).
pub const LAST_EARLY: u32 = 2 * super::estimate::FIRST_BATCH;
/// The neighbourhood's half side: 1 is the 3×3 block around the pixel.
pub const RADIUS: u32 = 1;

/// The neighbours' first batches, pooled: their per-sample relative variance, its degrees of
/// freedom and their samples.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NeighbourPrior {
    /// Per-sample variance of the luminance over its squared mean, pooled (weighted by
    /// degrees of freedom).
    relative_variance: f64,
    /// Degrees of freedom pooled (0: no neighbour with light).
    dof: f64,
    /// Samples the neighbours took, black ones included.
    samples: u32,
}

impl NeighbourPrior {
    /// Pools the neighbours' first-batch accumulators (the pixel's own excluded).
    pub fn pool<'a>(neighbours: impl IntoIterator<Item = &'a Accumulator>) -> NeighbourPrior {
        let mut prior = NeighbourPrior::default();
        let mut weighted = 0.0;
        for acc in neighbours {
            prior.samples += acc.count();
            if let Some((r, dof)) = acc.relative_sample_variance() {
                weighted += r * dof;
                prior.dof += dof;
            }
        }
        if prior.dof > 0.0 {
            prior.relative_variance = weighted / prior.dof;
        }
        prior
    }
}

/// The lower `1 − CONFIDENCE` quantile of the chi-square distribution with `dof` degrees of
/// freedom (Wilson–Hilferty: within 2% of the exact value from 3 degrees of freedom on; 0.577
/// against 0.584 at 3).
pub fn chi_square_lower(dof: f64) -> f64 {
    let a = 2.0 / (9.0 * dof.max(1.0));
    (dof * (1.0 - a - Z_CONFIDENCE * a.sqrt()).max(0.0).powi(3)).max(1e-12)
}

/// The pixel's relative standard error if it may stop now, after `acc.count()` samples, at
/// `target`; `None` if it must go on. See the module doc for the rule.
pub fn confident_error(acc: &Accumulator, prior: &NeighbourPrior, target: f64) -> Option<f64> {
    let n = acc.count() as f64;
    if acc.count() > LAST_EARLY || n + (prior.samples as f64) < 1.0 / target {
        return None;
    }
    let (own, own_dof) = acc.relative_sample_variance()?;
    let dof = own_dof + prior.dof;
    let pooled = (own * own_dof + prior.relative_variance * prior.dof) / dof;
    // The floor term of `Accumulator::relative_error`, relative.
    let floor = (REL_FLOOR / n / acc.mean_luminance().abs().max(REL_FLOOR)).powi(2);
    let upper = pooled * dof / chi_square_lower(dof);
    let within = |r: f64| r / n + floor <= target * target;
    (within(upper) && within(own)).then(|| (pooled / n + floor).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn pixel(values: &[f32]) -> Accumulator {
        let mut acc = Accumulator::default();
        for (g, &v) in values.iter().enumerate() {
            acc.add_replicate(Vec3::splat(v), g % 4);
        }
        acc
    }

    #[test]
    fn chi_square_quantiles_are_close_to_the_tables() {
        // Lower 10% points: 0.584 (3), 2.833 (7), 18.114 (27), 64.278 (80).
        for (dof, exact) in [(3.0, 0.584), (7.0, 2.833), (27.0, 18.114), (80.0, 64.278)] {
            let q = chi_square_lower(dof);
            assert!(
                (q - exact).abs() < 0.02 * exact,
                "{dof}: {q} against {exact}"
            );
        }
    }

    #[test]
    fn a_flat_neighbourhood_lets_a_flat_pixel_stop_and_a_noisy_one_not() {
        let flat = pixel(&[1.0, 1.05, 0.95, 1.0]);
        let neighbours = [flat; 8];
        let prior = NeighbourPrior::pool(&neighbours);
        assert_eq!(prior.samples, 32);
        assert!((prior.dof - 24.0).abs() < 1e-12);
        let e = confident_error(&flat, &prior, 0.1).expect("a flat pixel in flat company stops");
        assert!(e < 0.05, "{e}");
        // Alone, its 4 samples are fewer than 1/target: it has not seen enough to stop.
        assert_eq!(
            confident_error(&flat, &NeighbourPrior::default(), 0.1),
            None
        );
        // A noisy pixel among flat ones does not stop on their say.
        let noisy = pixel(&[0.2, 1.8, 0.5, 1.5]);
        assert_eq!(confident_error(&noisy, &prior, 0.1), None);
        // Flat pixels next to noisy ones do not either.
        let noisy_prior = NeighbourPrior::pool(&[noisy; 8]);
        assert_eq!(confident_error(&flat, &noisy_prior, 0.1), None);
    }

    #[test]
    fn black_neighbours_say_nothing_and_too_few_samples_never_stop() {
        let flat = pixel(&[1.0, 1.05, 0.95, 1.0]);
        let black = pixel(&[0.0; 4]);
        let prior = NeighbourPrior::pool(&[black; 8]);
        assert_eq!(prior.dof, 0.0);
        assert_eq!(prior.samples, 32);
        // 4 + 32 samples are fewer than 1/target at 2%.
        let flat_prior = NeighbourPrior::pool(&[flat; 8]);
        assert_eq!(confident_error(&flat, &flat_prior, 0.02), None);
    }
}
