//! Stage 4: when an adaptive pixel may stop before `estimate::min_samples` (`1/target`), after
//! its first 2 or 4 samples, from its own samples and its neighbours' first batches.
//!
//! Syntax: no syntax of its own; it decides for `render { noise 0.1 }` / `--noise 0.1`.
//!
//! A pixel that sees a flat, directly lit wall is done after a few samples, but its own
//! estimate after so few has 1 to 7 degrees of freedom: stopping whenever it says "within the
//! target" stops pixels on a luckily small value (texture_bench at 1.4× its target,
//! docs/quality.md). Its neighbours know more, and every pixel's first batch is taken before
//! any pixel goes on.
//!
//! **After the first batch (2 samples).** The first round of an adaptive pixel is one jointly
//! stratified set (`rng::PixelSequences`: as efficient as a fixed-count render's samples, where
//! independent ones left flat walls with 1.5× the error), so a per-sample variance over-states
//! its error; but neighbouring pixels' sets are scrambled independently, so the scatter of the
//! 3×3 block's first-batch means about a plane fitted to them ([`FirstBatchSpread`], 6 degrees
//! of freedom) measures the error of one such mean. The pixel stops if that relative variance
//! is within the target (since 2026-11-26, fourth session: it used to be its **upper confidence
//! bound** at [`CONFIDENCE`], chi-square quantile, which kept cornell and env at 10% at 0.50–0.54×
//! the target; the bound is still asked at the image's edge, where the block is cut and the
//! spread has 3 degrees of freedom or fewer). An edge, a texture or a curved falloff across the
//! block adds to the scatter: such pixels sample on. A spread under a quarter of the target's
//! variance is not trusted there ([`QUIET_SHARE`], since 2026-11-29, eighteenth session): the
//! pixel takes its whole first round and looks again after 4 samples.
//!
//! **After 4 samples** (the whole first round, a 4-point net), it stops if the upper confidence
//! bound of half that spread is within the target and its own per-sample estimate within twice
//! the target ([`OWN_OVER_TARGET_SQ`]: a penumbra block whose first batches all fell the same way
//! has a luckily small spread; since 2026-11-26, fifth session) (assumed: a 4-point net's mean has at most
//! half the variance of its first two points' mean, as independent samples' has;
//! stratification usually does better, and cornell at 5% reported 0.82× its measured error with
//! it, so this stop keeps the bound; where a 2-sample stop was possible, an interior pixel that
//! did not take it does not take this one either),
//! or on the older rule: the pixel's own per-sample relative variance shrunk toward its 8
//! neighbours' first-batch values (both weighted by their degrees of freedom: the
//! [`NeighbourPrior`]; relative, not absolute, so that it carries over between neighbours of
//! different brightness), whose upper confidence bound and its own estimate alone are within
//! the target (the per-sample formula over-states a net, so this stop is conservative).
//!
//! Every early stop reports the [`posterior_mean`] of its variance, not the estimate: a pixel
//! stops because its estimate came out low, and the estimate then under-states its error
//! (the early stops reported 0.6× their measured error at 10%).
//!
//! Either way the pixel and its neighbours together must have taken `1/target` samples (the
//! rule of three behind `estimate::min_samples`: the neighbourhood has seen what the pixel
//! alone could not have yet, [`NeighbourPrior::seen`]), and the black-pixel, emitter and
//! sliver rules apply first. The same count lets a pixel past its first round stop on its own
//! replicates' estimate before it alone has taken `1/target` samples (since 2026-11-26, later:
//! at 2%, 36 samples instead of 52).
//!
//! Deterministic for any thread count and any tiling: the decisions use the neighbours' first
//! batches only, which every pixel takes whatever happens next and which a render computes for
//! all pixels (and a one-pixel margin around a `--tile` window) before any pixel goes on.

use super::estimate::{Accumulator, FIRST_BATCH, REL_FLOOR};

/// One-sided confidence with which an early stop's relative error is within the target.
pub const CONFIDENCE: f64 = 0.9;
/// The standard normal quantile of [`CONFIDENCE`] (the chi-square quantile is Wilson and
/// Hilferty's approximation from it, [`chi_square_lower`]).
const Z_CONFIDENCE: f64 = 1.281_551_565_5;
/// The most samples after which a pixel may stop early: its first round (one point of each
/// replicate). Later the replicates' spread measures the error; the per-sample variance
/// over-states it for stratified samples (cornell at 2%, stopping early at 24 and 40 samples:
/// reported 1.27× the measured, against 1.03× without).
pub const LAST_EARLY: u32 = super::estimate::REPLICATES;
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
    /// Samples the neighbours' first batches took.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Samples the pixel (`own` so far) and its neighbours' first batches have taken together:
    /// what the rule of three behind `estimate::min_samples` counts once the pixel may lean on
    /// its neighbourhood.
    pub fn seen(&self, own: u32) -> u32 {
        own.saturating_add(self.samples)
    }

    /// Pools the neighbours' first-batch accumulators (the pixel's own excluded).
    pub fn pool<'a>(neighbours: impl IntoIterator<Item = &'a Accumulator>) -> NeighbourPrior {
        NeighbourPrior::pool_summaries(neighbours.into_iter().map(FirstBatchSummary::of))
    }

    /// [`NeighbourPrior::pool`] of the neighbours' [`FirstBatchSummary`]s.
    pub fn pool_summaries(
        neighbours: impl IntoIterator<Item = FirstBatchSummary>,
    ) -> NeighbourPrior {
        let mut prior = NeighbourPrior::default();
        let mut weighted = 0.0;
        for summary in neighbours {
            prior.samples += summary.samples;
            if let Some((r, dof)) = summary.relative_variance {
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

/// What one pixel's first batch tells its neighbourhood: its samples, its per-sample relative
/// variance ([`Accumulator::relative_sample_variance`]) and its mean luminance. Derived once per
/// pixel (`render::first_pass`) rather than once for each of the nine blocks that read it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FirstBatchSummary {
    /// Samples taken, black ones included.
    pub samples: u32,
    /// Per-sample variance of the luminance over its squared mean, and its degrees of freedom.
    pub relative_variance: Option<(f64, f64)>,
    /// Mean luminance.
    pub mean_luminance: f64,
}

impl FirstBatchSummary {
    /// The summary of a first batch.
    pub fn of(acc: &Accumulator) -> FirstBatchSummary {
        FirstBatchSummary {
            samples: acc.count(),
            relative_variance: acc.relative_sample_variance(),
            mean_luminance: acc.mean_luminance(),
        }
    }
}

/// The error of the first batch's mean, measured across the neighbourhood: the first batch is
/// one jointly stratified set (`rng::PixelSequences`), which a per-sample variance over-states,
/// but the neighbours' sets are scrambled independently, so the scatter of the `(2·RADIUS+1)²`
/// first-batch means about a plane fitted to them (least squares in the pixel offsets)
/// estimates the variance of one such mean, with `k − 3` degrees of freedom; relative to the
/// block's squared mean luminance. Shading that is not a plane over the block (an edge, a
/// texture, a curved falloff) adds to the scatter: the estimate errs on the side of sampling on.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FirstBatchSpread {
    /// Variance of a first-batch mean over the block's squared mean luminance.
    relative_variance: f64,
    /// Degrees of freedom (0: too few pixels, or a black block).
    dof: f64,
}

impl FirstBatchSpread {
    /// Fits `mean ≈ a + b·dx + c·dy` to the first-batch mean luminances at offsets
    /// (`dx`, `dy`) from the pixel (the pixel's own included).
    pub fn fit(block: impl IntoIterator<Item = (f64, f64, f64)>) -> FirstBatchSpread {
        // Normal equations of the plane, accumulated.
        let (mut k, mut sx, mut sy, mut sxx, mut syy, mut sxy) = (0.0f64, 0.0, 0.0, 0.0, 0.0, 0.0);
        let (mut sm, mut sxm, mut sym, mut smm) = (0.0, 0.0, 0.0, 0.0);
        for (dx, dy, m) in block {
            k += 1.0;
            sx += dx;
            sy += dy;
            sxx += dx * dx;
            syy += dy * dy;
            sxy += dx * dy;
            sm += m;
            sxm += dx * m;
            sym += dy * m;
            smm += m * m;
        }
        let mean = sm / k.max(1.0);
        if k < 4.0 || mean <= REL_FLOOR {
            return FirstBatchSpread::default();
        }
        let det3 = |a: [f64; 9]| {
            a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6])
                + a[2] * (a[3] * a[7] - a[4] * a[6])
        };
        let normal = [k, sx, sy, sx, sxx, sxy, sy, sxy, syy];
        let det = det3(normal);
        if det.abs() < 1e-9 {
            return FirstBatchSpread::default();
        }
        let rhs = [sm, sxm, sym];
        let solve = |col: usize| {
            let mut a = normal;
            for row in 0..3 {
                a[row * 3 + col] = rhs[row];
            }
            det3(a) / det
        };
        let coef = [solve(0), solve(1), solve(2)];
        // Residual sum of squares: Σm² − coef·rhs at the least-squares solution.
        let rss = (smm - coef[0] * rhs[0] - coef[1] * rhs[1] - coef[2] * rhs[2]).max(0.0);
        let dof = k - 3.0;
        FirstBatchSpread {
            relative_variance: rss / dof / (mean * mean),
            dof,
        }
    }
}

impl FirstBatchSpread {
    /// [`FirstBatchSpread::fit`] of a whole 3×3 block (`RADIUS` 1), its mean luminances row by
    /// row from offset (−1, −1): the same bits, the normal equations solved in closed form.
    /// Over the whole block the offsets' sums are exact small integers (k = 9, Σdx = Σdy =
    /// Σdx·dy = 0, Σdx² = Σdy² = 6), so `fit`'s Cramer determinants reduce term by term to
    /// `det = 324`, `sm·36`, `9·(sxm·6)` and `9·(sym·6)` (every other term a product with an
    /// exact zero, which adds or subtracts a zero: nothing, the sums being finite and never
    /// −0); the data sums are accumulated as `fit` does, in the same order. What nearly every
    /// pixel's first look computes (`render::first_pass`), where the general fit's
    /// determinants were about a tenth of the adaptive path's bookkeeping.
    pub fn fit_whole_block(means: [f64; 9]) -> FirstBatchSpread {
        const _: () = assert!(RADIUS == 1);
        let (mut sm, mut sxm, mut sym, mut smm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for (k, m) in means.into_iter().enumerate() {
            let (dx, dy) = ((k % 3) as f64 - 1.0, (k / 3) as f64 - 1.0);
            sm += m;
            sxm += dx * m;
            sym += dy * m;
            smm += m * m;
        }
        let mean = sm / 9.0;
        if mean <= REL_FLOOR {
            return FirstBatchSpread::default();
        }
        let det = 324.0;
        let coef = [
            (sm * 36.0) / det,
            (9.0 * (sxm * 6.0)) / det,
            (9.0 * (6.0 * sym)) / det,
        ];
        let rss = (smm - coef[0] * sm - coef[1] * sxm - coef[2] * sym).max(0.0);
        let dof = 6.0;
        FirstBatchSpread {
            relative_variance: rss / dof / (mean * mean),
            dof,
        }
    }
}

/// The lower `1 − CONFIDENCE` quantile of the chi-square distribution with `dof` degrees of
/// freedom (Wilson–Hilferty: within 2% of the exact value from 3 degrees of freedom on; 0.577
/// against 0.584 at 3).
pub fn chi_square_lower(dof: f64) -> f64 {
    let a = 2.0 / (9.0 * dof.max(1.0));
    (dof * (1.0 - a - Z_CONFIDENCE * a.sqrt()).max(0.0).powi(3)).max(1e-12)
}

/// Whether a pixel with `own` samples whose neighbours' first batches took `neighbours` may
/// stop early at `target` at all ([`confident_error`] is `None` otherwise): at most
/// [`LAST_EARLY`] samples, and `1/target` seen by the neighbourhood. Asked before the prior
/// and the spread are derived, which most looks never need (`render::Job::decide`).
pub fn may_look(own: u32, neighbours: u32, target: f64) -> bool {
    let seen = NeighbourPrior {
        samples: neighbours,
        ..NeighbourPrior::default()
    }
    .seen(own);
    own <= LAST_EARLY && f64::from(seen) >= 1.0 / target
}

/// The pixel's relative standard error if it may stop now, after `acc.count()` samples, at
/// `target`; `None` if it must go on. See the module doc for the rule.
pub fn confident_error(
    acc: &Accumulator,
    prior: &NeighbourPrior,
    spread: &FirstBatchSpread,
    target: f64,
) -> Option<f64> {
    confident_error_with(acc, prior.samples, spread, || prior, target)
}

/// [`confident_error`] with the neighbours' first-batch samples (`neighbour_samples`, the
/// prior's count) given, and the prior asked for only where the rule reads it: after the first
/// batch a pixel stops or not on the spread alone, so the 10% render, most of whose pixels
/// stop there, pools no neighbours' variances (`render::Job::decide`). The same value as
/// [`confident_error`] for the prior whose count is `neighbour_samples`.
pub fn confident_error_with<'p>(
    acc: &Accumulator,
    neighbour_samples: u32,
    spread: &FirstBatchSpread,
    prior: impl FnOnce() -> &'p NeighbourPrior,
    target: f64,
) -> Option<f64> {
    let n = acc.count() as f64;
    if !may_look(acc.count(), neighbour_samples, target) {
        return None;
    }
    if acc.count() == FIRST_BATCH {
        let stop = match spread.dof >= WHOLE_BLOCK_DOF {
            true => Stop::OnEstimate,
            false => Stop::OnBound,
        };
        if stop == Stop::OnEstimate && spread.relative_variance < QUIET_SHARE * target * target {
            // Too quiet to trust after 2 samples: the pixel takes its whole first round and
            // looks again (`QUIET_SHARE`).
            return None;
        }
        return first_batch_error(acc, spread, target, 1.0, stop);
    }
    if acc.count() == 2 * FIRST_BATCH {
        // Twice the first batch's points: at most half its variance (module doc).
        if let Some(e) = first_batch_error(acc, spread, target, 0.5, Stop::OnBound) {
            return Some(e);
        }
    }
    let (own, own_dof) = acc.relative_sample_variance()?;
    let prior = prior();
    debug_assert_eq!(prior.samples, neighbour_samples);
    let dof = own_dof + prior.dof;
    let pooled = (own * own_dof + prior.relative_variance * prior.dof) / dof;
    // The floor term of `Accumulator::relative_error`, relative.
    let floor = (REL_FLOOR / n / acc.mean_luminance().abs().max(REL_FLOOR)).powi(2);
    let upper = pooled * dof / chi_square_lower(dof);
    let within = |r: f64| r / n + floor <= target * target;
    (within(upper) && within(own)).then(|| (posterior_mean(pooled, dof) / n + floor).sqrt())
}

/// The share of the target's variance under which the look after the first batch (2 samples)
/// does not trust its estimate: the pixel takes the rest of its first round (2 more samples,
/// the 4-point net) and looks again after 4 (since 2026-11-29, eighteenth session). The
/// estimate there is the block's 6-degree-of-freedom spread; one a quarter of the target's
/// variance or less comes from a pixel at its target only 4% of the time (χ²₆ below 1.5), so
/// it says mostly "lucky" or "far below the target", and the pixels that stopped on it carried
/// more error than they reported: on cornell at 10% the rule adds 2% samples (28.7 → 29.4 a
/// pixel, seeds 7–10 at 48×48) and takes 14% off the measured RMS relative error (0.65× →
/// 0.56× the target), while the reported figure moves by 5% (from 0.93× to 1.02× the
/// measured). Where the walls are truly quiet (soft_shadows' walls, lit directly by one large
/// light, about 3% after 2 samples at a 10% target) their two more samples are cheap and they
/// carried most of the image's squared error: samples at equal RMSE 0.90 → 0.70 of a fixed
/// render's (docs/quality.md). Targets of 1/18 and looser only (the pixel's 2 samples and its 8
/// neighbours' 2 each are the `1/target` an early stop asks for): tighter ones never stop
/// after 2 samples.
pub const QUIET_SHARE: f64 = 0.25;

/// How far over the target (in variance: twice the target in standard error) a pixel's own
/// per-sample estimate may be at the 4-sample stop on half the neighbourhood's spread. The
/// per-sample formula over-states a 4-point net (by about 1.4× on cornell's walls), so this asks
/// little of a pixel its neighbours vouch for; but a block whose nine first batches all fell
/// the same way in a penumbra (each pixel sees the light or not) has a luckily small spread, and
/// its pixels then stopped after 4 samples 50–75% off while reporting 1–2% (cornell at 5%, seed
/// 8: row 41 beside the tall box, report 0.72× the measured; docs/quality.md). Their own
/// samples disagree: this stops them.
pub const OWN_OVER_TARGET_SQ: f64 = 4.0;

/// Whether the pixel's own per-sample relative variance of the mean (with the floor term) is
/// at most `limit`.
fn own_within(acc: &Accumulator, n: f64, floor: f64, limit: f64) -> bool {
    acc.relative_sample_variance()
        .is_some_and(|(r, _)| r / n + floor <= limit)
}

/// What an early stop asks of its estimate of the relative variance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stop {
    /// The estimate itself within the target.
    OnEstimate,
    /// Its upper confidence bound at [`CONFIDENCE`] within the target.
    OnBound,
}

/// The degrees of freedom of a [`FirstBatchSpread`] over the whole `(2·RADIUS+1)²` block (6:
/// nine means less a plane's three coefficients).
const WHOLE_BLOCK_DOF: f64 = ((2 * RADIUS + 1) * (2 * RADIUS + 1) - 3) as f64;

/// The expected variance given its estimate `var` of `dof` degrees of freedom: the mean of the
/// scaled inverse chi-square posterior (Jeffreys prior), `dof / (dof − 2)` times the estimate;
/// the upper confidence bound where that mean is infinite (2 degrees of freedom or fewer). What
/// an early stop reports: a pixel stops because its estimate came out low, so the estimate
/// itself under-states the error of the pixels that stop (the early stops reported 0.6× their
/// measured error, docs/quality.md); conditioning on the estimate, as the posterior does,
/// accounts for that selection.
pub(super) fn posterior_mean(var: f64, dof: f64) -> f64 {
    if dof > 2.0 {
        var * dof / (dof - 2.0)
    } else {
        var * dof / chi_square_lower(dof)
    }
}

/// From the spread across the neighbourhood ([`FirstBatchSpread`]) times `scale` (1 after the
/// first batch, ½ after the whole first round), which must be within the target as `stop` asks;
/// the error reported is its [`posterior_mean`]. Not the pixel's own per-sample
/// estimate as well: it over-states a stratified set (requiring it too kept cornell at 10% at
/// 0.44× the target, docs/quality.md); a pixel whose first batch strays from its neighbours'
/// plane raises the spread itself.
fn first_batch_error(
    acc: &Accumulator,
    spread: &FirstBatchSpread,
    target: f64,
    scale: f64,
    stop: Stop,
) -> Option<f64> {
    if spread.dof <= 0.0 || acc.is_black() {
        return None;
    }
    let n = acc.count() as f64;
    let floor = (REL_FLOOR / n / acc.mean_luminance().abs().max(REL_FLOOR)).powi(2);
    let var = spread.relative_variance * scale;
    if scale < 1.0 && !own_within(acc, n, floor, OWN_OVER_TARGET_SQ * target * target) {
        return None;
    }
    let decides = match stop {
        Stop::OnEstimate => var,
        Stop::OnBound => var * spread.dof / chi_square_lower(spread.dof),
    };
    (decides + floor <= target * target).then(|| (posterior_mean(var, spread.dof) + floor).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn pixel(values: &[f32]) -> Accumulator {
        let mut acc = Accumulator::default();
        for (g, &v) in values.iter().enumerate() {
            acc.add_replicate(Vec3::splat(v), Some(g % 4));
        }
        acc
    }

    #[test]
    fn a_whole_blocks_closed_form_fit_is_the_general_fit_bit_for_bit() {
        let mut h = 0x0f1e_2d3c_u64;
        for round in 0..20_000 {
            let means: [f64; 9] = std::array::from_fn(|k| {
                h = crate::render::rng::mix64(h ^ k as u64);
                let u = (h >> 11) as f64 / (1u64 << 53) as f64;
                match round % 4 {
                    0 => u,
                    1 => 0.3 + 0.01 * u,
                    2 if k == 4 => 0.0,
                    2 => u * u * 5.0,
                    _ => (u * 4.0).floor() * 0.25,
                }
            });
            let cells = means
                .iter()
                .enumerate()
                .map(|(k, &m)| ((k % 3) as f64 - 1.0, (k / 3) as f64 - 1.0, m));
            let (general, closed) = (
                FirstBatchSpread::fit(cells),
                FirstBatchSpread::fit_whole_block(means),
            );
            assert_eq!(
                general.relative_variance.to_bits(),
                closed.relative_variance.to_bits(),
                "{means:?}"
            );
            assert_eq!(general.dof.to_bits(), closed.dof.to_bits());
        }
        let black = FirstBatchSpread::fit_whole_block([0.0; 9]);
        assert_eq!(black, FirstBatchSpread::default());
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
        assert_eq!(prior.seen(4), 36);
        assert!((prior.dof - 24.0).abs() < 1e-12);
        let e = confident_error(&flat, &prior, &FirstBatchSpread::default(), 0.1)
            .expect("a flat pixel in flat company stops");
        assert!(e < 0.05, "{e}");
        // Alone, its 4 samples are fewer than 1/target: it has not seen enough to stop.
        assert_eq!(
            confident_error(
                &flat,
                &NeighbourPrior::default(),
                &FirstBatchSpread::default(),
                0.1
            ),
            None
        );
        // A noisy pixel among flat ones does not stop on their say.
        let noisy = pixel(&[0.2, 1.8, 0.5, 1.5]);
        assert_eq!(
            confident_error(&noisy, &prior, &FirstBatchSpread::default(), 0.1),
            None
        );
        // Flat pixels next to noisy ones do not either.
        let noisy_prior = NeighbourPrior::pool(&[noisy; 8]);
        assert_eq!(
            confident_error(&flat, &noisy_prior, &FirstBatchSpread::default(), 0.1),
            None
        );
    }

    #[test]
    fn the_first_batch_spread_is_the_scatter_about_a_plane() {
        let block = |f: &dyn Fn(f64, f64) -> f64| {
            let cells: Vec<(f64, f64, f64)> = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx as f64, dy as f64)))
                .map(|(dx, dy)| (dx, dy, f(dx, dy)))
                .collect();
            FirstBatchSpread::fit(cells)
        };
        // A plane (a falloff across the block) has no scatter, with 9 − 3 degrees of freedom.
        let plane = block(&|dx, dy| 1.0 + 0.1 * dx - 0.05 * dy);
        assert!(
            plane.relative_variance < 1e-12 && plane.dof == 6.0,
            "{plane:?}"
        );
        // ±e in a checkerboard on a flat mean of 1: orthogonal to every plane, so the fit is
        // the block's mean and the residuals are ±e about it.
        let e = 0.05;
        let checker = block(&|dx, dy| 1.0 + if (dx + dy) as i64 % 2 == 0 { e } else { -e });
        let mean = 1.0 + e / 9.0;
        let rss = 5.0 * (e - e / 9.0).powi(2) + 4.0 * (e + e / 9.0).powi(2);
        let expected = rss / 6.0 / (mean * mean);
        let got = checker.relative_variance;
        assert!(
            (got - expected).abs() < 1e-9 * expected,
            "{got} against {expected}"
        );
        // A flat pixel stops after its first batch among neighbours that scatter little, and
        // not among neighbours that scatter a lot (one bright pixel in the block).
        let flat = pixel(&[1.0, 1.02]);
        let flat_prior = NeighbourPrior::pool(&[flat; 8]);
        let quiet = block(&|dx, dy| 1.0 + 0.002 * (dx - dy));
        let e = 0.05;
        let middling_low = block(&|dx, dy| 1.0 + if (dx + dy) as i64 % 2 == 0 { e } else { -e });
        assert!(confident_error(&flat, &flat_prior, &middling_low, 0.1).is_some());
        // A spread under a quarter of the target's variance is not trusted after 2 samples
        // (`QUIET_SHARE`): the pixel takes its whole first round and stops after 4.
        assert_eq!(confident_error(&flat, &flat_prior, &quiet, 0.1), None);
        let flat_four = pixel(&[1.0, 1.02, 0.99, 1.01]);
        assert!(confident_error(&flat_four, &flat_prior, &quiet, 0.1).is_some());
        let loud = block(&|dx, dy| if dx == 1.0 && dy == 0.0 { 3.0 } else { 1.0 });
        assert_eq!(confident_error(&flat, &flat_prior, &loud, 0.1), None);
        // After the first batch a whole block's spread decides itself: ±0.06 in a checkerboard
        // (relative variance about 1.48·0.06² = 0.0053) is within 10%², and the pixel reports
        // the posterior mean, 6/4 of it.
        let checker = |e: f64, rows: std::ops::RangeInclusive<i64>| {
            let cells: Vec<(f64, f64, f64)> = rows
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .map(|(dx, dy)| {
                    let m = 1.0 + if (dx + dy) % 2 == 0 { e } else { -e };
                    (dx as f64, dy as f64, m)
                })
                .collect();
            FirstBatchSpread::fit(cells)
        };
        let middling = checker(0.06, -1..=1);
        let e = confident_error(&flat, &flat_prior, &middling, 0.1).expect("within the target");
        assert!(
            (e - (1.5 * middling.relative_variance).sqrt()).abs() < 1e-3,
            "{e}"
        );
        // At the image's edge (two rows, 3 degrees of freedom) it must pass the 90% bound,
        // 5.1× the estimate: it does not.
        let edge = checker(0.06, 0..=1);
        assert_eq!(edge.dof, 3.0);
        assert_eq!(confident_error(&flat, &flat_prior, &edge, 0.1), None);
        // At 5% no pixel may stop after its first batch (2 + 16 samples < 20); after 4 it may, if
        // the 90% bound of half the spread is within the target: ±0.03 gives 2.7·0.5·0.0013 =
        // 0.0018 ≤ 0.0025.
        let slight = checker(0.03, -1..=1);
        assert_eq!(confident_error(&flat, &flat_prior, &slight, 0.05), None);
        let four = pixel(&[1.0, 1.02, 0.98, 1.0]);
        // Neighbours whose own samples disagree a lot: the per-sample rule would not stop.
        let noisy_prior = NeighbourPrior::pool(&[pixel(&[0.2, 1.8, 0.5, 1.5]); 8]);
        let e = confident_error(&four, &noisy_prior, &slight, 0.05).expect("half the spread");
        assert!(
            (e - (1.5 * 0.5 * slight.relative_variance).sqrt()).abs() < 1e-3,
            "{e}"
        );
        assert_eq!(confident_error(&four, &noisy_prior, &middling, 0.05), None);
        // Too few pixels to fit a plane and measure a scatter: no early stop.
        let corner = FirstBatchSpread::fit([(0.0, 0.0, 1.0), (1.0, 0.0, 1.0), (0.0, 1.0, 1.0)]);
        assert_eq!(corner.dof, 0.0);
        assert_eq!(confident_error(&flat, &flat_prior, &corner, 0.1), None);
    }

    #[test]
    fn the_four_sample_stop_asks_the_pixels_own_samples_too() {
        // A block whose first batches agree (a small spread) around a pixel whose own four
        // samples swing between 0 and 1 (a penumbra pixel that saw the light or not): half the
        // spread would stop it at 10%, its own samples do not (per-sample relative variance of
        // the mean 1/3 / 4 · 4 = 1/3, more than 4 · 0.1²).
        let quiet = FirstBatchSpread::fit(
            (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx as f64, dy as f64)))
                .map(|(dx, dy)| (dx, dy, 0.5 + 0.001 * dx)),
        );
        let noisy_prior = NeighbourPrior::pool(&[pixel(&[0.2, 1.8, 0.5, 1.5]); 8]);
        let swinging = pixel(&[1.0, 0.0, 1.0, 0.0]);
        assert_eq!(confident_error(&swinging, &noisy_prior, &quiet, 0.1), None);
        // A pixel whose own samples agree stops on the same spread.
        let steady = pixel(&[0.5, 0.52, 0.48, 0.5]);
        assert!(confident_error(&steady, &noisy_prior, &quiet, 0.1).is_some());
    }

    #[test]
    fn early_stops_report_the_posterior_mean_of_their_variance() {
        // dof / (dof − 2) times the estimate; the 90% bound where that mean is infinite.
        assert!((posterior_mean(1.0, 6.0) - 1.5).abs() < 1e-12);
        assert!((posterior_mean(1.0, 27.0) - 27.0 / 25.0).abs() < 1e-12);
        assert!((posterior_mean(1.0, 2.0) - 2.0 / chi_square_lower(2.0)).abs() < 1e-12);
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
        assert_eq!(
            confident_error(&flat, &flat_prior, &FirstBatchSpread::default(), 0.02),
            None
        );
    }
}
