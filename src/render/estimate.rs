//! Stage 4: one pixel's estimate from its samples: the mean (the box-filtered radiance), the
//! standard error of that mean, and the adaptive stopping rule of `render { noise 0.01
//! max_samples 4096 }` / `--noise 0.01`.
//!
//! **The error estimate is right for low-discrepancy samples.** An adaptive pixel's samples
//! after its first round (a stratified set of its own, in the mean only) are dealt round-robin
//! to [`REPLICATES`] independent replicates, each one progressive Owen-scrambled Sobol'
//! sequence continued from batch to batch (`rng::PixelSequences`). The replicates' means are
//! independent, identically distributed estimates, so the spread between them measures the
//! real error of their average, stratification included (the classic error
//! estimate of randomised quasi-Monte Carlo: independent replicates, as Owen and L'Ecuyer use
//! them). The samples' own spread (`σ̂² / n`, the formula for independent samples) over-states
//! the error of stratified samples, by 2–6× on cornell, which is why adaptive renders used to
//! stop with 4–6× less error than asked.
//!
//! The spread of four means has three degrees of freedom: noisy, and stopping on a luckily
//! small estimate biases the pixel. So it is combined with the per-sample estimate (an upper
//! bound in expectation) as a prior worth [`PRIOR_DOF`] degrees of freedom (less beyond
//! [`PRIOR_FULL_SAMPLES`] samples, [`prior_dof`]); when a pixel that has taken `1/target`
//! samples decides to stop, that prior is at most [`PRIOR_CAP`] times the replicates' estimate
//! ([`Accumulator::stopping_error`]; it reports the uncapped one). Relative error is
//! that of the luminance, divided by the mean luminance floored at [`REL_FLOOR`]; a term
//! `REL_FLOOR / n` keeps pixels whose samples all agree so far sampling until `n ≥ 1/target`,
//! a pixel whose samples are all black takes at least `3/target` ([`black_min_samples`]), a
//! pixel darker than [`DIM_LUMINANCE`] (after exposure) stops when its error relative to that
//! luminance is within the target ([`dim_scale`]), and
//! one an area light's outline crosses samples until it has seen the light or could not miss
//! it (`render::emitter_coverage`).
//!
//! A pixel takes batches of 2 and 2 samples (the first round, one jointly stratified set kept
//! out of the replicates, in two halves), then batches of [`BATCH`], and stops after the first
//! batch at which its relative error is at most the target (from [`min_samples`] on, counted
//! with the neighbours' first batches after the first round) or its
//! count reached `max_samples`. Before [`min_samples`], after 2 or 4 samples, a flat, directly
//! lit pixel may stop on the stricter rule of `render::early_stop`, which asks its
//! neighbours' first batches. Every decision uses
//! the pixel's own samples, its neighbours' first batches and the light's projected outline
//! (`render::emitter_coverage`) only,
//! so the image does not depend on threads or tiles.

use glam::{DVec3, Vec3};

use crate::shade::color::luminance_f64;

pub use super::rng::REPLICATES;

/// Samples of the first batch: half of the first round (one point of each replicate, the round
/// jointly stratified: `rng::PixelSequences`), so that a pixel that needs little (a flat,
/// directly lit wall) can stop after 2 or 4 samples (`render::early_stop`).
pub const FIRST_BATCH: u32 = REPLICATES / 2;
/// Samples per later batch.
pub const BATCH: u32 = 4 * REPLICATES;
/// Weight, in degrees of freedom, of the per-sample variance estimate (conservative for
/// stratified samples) against the between-replicate one (`REPLICATES − 1` degrees of freedom),
/// up to [`PRIOR_FULL_SAMPLES`] samples ([`prior_dof`]).
pub const PRIOR_DOF: f64 = 0.5;
/// Samples up to which the per-sample prior keeps its full weight [`PRIOR_DOF`].
pub const PRIOR_FULL_SAMPLES: f64 = 64.0;

/// The prior's weight after `n` samples: [`PRIOR_DOF`], then falling as `1/√n` beyond
/// [`PRIOR_FULL_SAMPLES`]. The per-sample formula over-states the error of stratified samples
/// by more the more samples there are (their error falls faster than `1/√n`), so a prior of
/// fixed weight makes well-stratified pixels over-sample and over-report at tight targets
/// (cornell at 2%: 0.46× the target, reported 1.27× the measured, pooled over four seeds; with
/// this fall 0.54× and 1.03×, env and texture_bench staying in the band; docs/quality.md).
pub fn prior_dof(n: f64) -> f64 {
    PRIOR_DOF * (PRIOR_FULL_SAMPLES / n.max(1.0)).sqrt().min(1.0)
}
/// The most the per-sample prior may say, as a multiple of the replicates' own estimate of the
/// variance of the mean, when a pixel decides to stop ([`Accumulator::stopping_error`]). The
/// replicates' three degrees of freedom put their estimate under 1/1600 of the truth with
/// probability about 2·10⁻⁵ (χ²₃'s lower tail, `(3/1600)^1.5 / (2^1.5 Γ(2.5))`), so a per-sample
/// estimate above it is known to over-state the pixel's error: its samples are stratified far
/// better than independent ones (cornell's ~90 pixels a render that stopped after 260 samples
/// measuring 0.38× the target at 2%, docs/quality.md). Tighter caps (40× or 180×, the 99% and
/// 99.94% points) let pixels stop on luckily small spreads (cornell at 5%: reports 0.49–0.67× the
/// measured).
pub const PRIOR_CAP: f64 = 1600.0;

/// A pixel that may see an area light takes at least this many samples over the target
/// ([`emitter_min_samples`]).
pub const EMITTER_MIN_PER_TARGET: f64 = 8.0;

/// The fewest samples an adaptive pixel that may see an area light takes at `target`. Its
/// relative error is what the target bounds, but on the light's edge (luminance about 12 on
/// cornell) a few percent of relative error is the image's largest absolute error: without
/// this minimum (the sliver rule of `render::emitter_coverage` alone) cornell's luminance RMSE
/// doubled at 10% and 5% for the same samples (0.0118 → 0.0251, 0.0061 → 0.0168 at 48×48,
/// pooled over four seeds), its relative figures hardly moving (docs/quality.md).
pub fn emitter_min_samples(target: f64) -> u32 {
    (EMITTER_MIN_PER_TARGET / target.max(1e-6))
        .ceil()
        .min(u32::MAX as f64) as u32
}

/// A pixel whose samples are all black so far takes at least this many samples over the
/// target ([`black_min_samples`]).
pub const BLACK_MIN_PER_TARGET: f64 = 3.0;

/// The fewest samples an adaptive pixel takes at `target` while every sample so far is black:
/// no event in `n` samples bounds its probability by about `3/n` (the rule of three, at 95%),
/// so `3/target` samples bound what a light seen through a gap, or a sliver of the light, can
/// still be worth. Before it, cornell's 10% and 5% renders had two or three such pixels stop
/// black after 24–88 samples (references 0.011 and 0.12) and carry half the squared error,
/// which the reported figure cannot see (docs/quality.md). Pixels with any light pay nothing.
pub fn black_min_samples(target: f64) -> u32 {
    (BLACK_MIN_PER_TARGET / target.max(1e-6))
        .ceil()
        .min(u32::MAX as f64) as u32
}

/// Every adaptive pixel takes at least this many samples over the target ([`min_samples`]).
pub const MIN_PER_TARGET: f64 = 1.0;

/// The fewest samples any adaptive pixel takes at `target`, whatever its estimate says: a
/// pixel whose first samples all agree (a light sample that almost always finds the sun, a
/// dark corner that rarely sees the light) has no spread to measure yet, and an event of
/// probability `p` is first seen after about `1/p` samples. `1/target` samples bound what an
/// unseen event can still be worth (the rule of three, as the black-pixel term does for
/// all-black pixels), without entering the reported estimate. Counted, once the pixel may lean
/// on its neighbourhood, over its own samples and its 8 neighbours' first batches
/// (`early_stop::NeighbourPrior::seen`): the pixel's own count alone kept three quarters of
/// cornell's pixels at 2% sampling to 52, where they estimated 0.33× the target and measured
/// less than the references' own noise (docs/quality.md).
pub fn min_samples(target: f64) -> u32 {
    (MIN_PER_TARGET / target.max(1e-6))
        .ceil()
        .min(u32::MAX as f64) as u32
}

/// Mean luminance below which relative error is measured against this value instead.
pub const REL_FLOOR: f64 = 1e-3;

/// Luminance above which a pixel counts in [`NoiseStats::rms_relative_error`]: darker pixels'
/// relative error is dominated by the [`REL_FLOOR`] and says little about the image.
pub const RMS_MIN_LUMINANCE: f64 = 0.01;

/// The displayed luminance (after the scene's exposure) below which a pixel's error is judged
/// against this value rather than against its own mean when it decides to stop
/// ([`dim_floor`]): the same threshold the reported RMS ([`RMS_MIN_LUMINANCE`]), the issue's
/// calibration and `scnc bench quality`'s relative MSE (`(x − r)² / (r² + 10⁻⁴)`) use. Against
/// their own mean (floored at [`REL_FLOOR`] only), soft_shadows' dim penumbra pixels (luminance
/// 0.002–0.01, half of the pixels still sampling after 20 samples at 10%) took most of the
/// 10% render's samples for no measurable gain in RMSE (docs/quality.md).
pub const DIM_LUMINANCE: f64 = RMS_MIN_LUMINANCE;

/// [`DIM_LUMINANCE`] in radiance, for a scene shown at `exposure` stops.
pub fn dim_floor(exposure: f32) -> f64 {
    DIM_LUMINANCE * (-f64::from(exposure)).exp2()
}

/// How much larger an error a pixel of mean luminance `mean` may stop with than its relative
/// target says: `max(mean, floor) / max(mean, REL_FLOOR)`, never below 1 (a floor under
/// [`REL_FLOOR`], at a high exposure, does not tighten the rule). 1 for pixels brighter than the
/// floor; a pixel darker than it stops when its absolute error is the target times the floor.
pub fn dim_scale(mean: f64, floor: f64) -> f64 {
    (mean.abs().max(floor) / mean.abs().max(REL_FLOOR)).max(1.0)
}

/// Running sums of one pixel's samples and of its replicates' luminance.
#[derive(Debug, Clone, Copy, Default)]
pub struct Accumulator {
    /// f32 like the film, so a fixed-count render's mean is bit-identical to the plain average.
    sum: Vec3,
    sum_sq: DVec3,
    luma_sum: f64,
    luma_sum_sq: f64,
    n: u32,
    /// Luminance sum and sample count of each replicate (adaptive renders only).
    replicate_luma: [f64; REPLICATES as usize],
    replicate_n: [u32; REPLICATES as usize],
    /// The brightest sample's luminance (adaptive renders only).
    brightest: f64,
}

impl Accumulator {
    /// Adds one sample's radiance; returns its luminance.
    pub fn add(&mut self, l: Vec3) -> f64 {
        self.sum += l;
        let d = l.as_dvec3();
        self.sum_sq += d * d;
        let y = luminance_f64(d);
        self.luma_sum += y;
        self.luma_sum_sq += y * y;
        self.n += 1;
        y
    }

    /// Adds one sample of an adaptive pixel, of replicate `replicate`
    /// (`rng::PixelSequences::replicate`; `None`: a shared round's, in the mean only).
    pub fn add_replicate(&mut self, l: Vec3, replicate: Option<usize>) {
        let y = self.add(l);
        self.brightest = self.brightest.max(y);
        let Some(replicate) = replicate else {
            return;
        };
        if let (Some(sum), Some(n)) = (
            self.replicate_luma.get_mut(replicate),
            self.replicate_n.get_mut(replicate),
        ) {
            *sum += y;
            *n += 1;
        }
    }

    /// The between-replicate sum of squares, each replicate's squared deviation weighted by
    /// its count (an estimate of `c` times its degrees of freedom, where a mean of `k` samples
    /// has variance `c / k`, as in a one-way analysis of variance), and those degrees of
    /// freedom; `None` until every replicate has a sample.
    fn between_replicates(&self) -> Option<(f64, f64)> {
        if self.replicate_n.contains(&0) {
            return None;
        }
        let n: u32 = self.replicate_n.iter().sum();
        let grand = self.replicate_luma.iter().sum::<f64>() / n as f64;
        let ss = self
            .replicate_luma
            .iter()
            .zip(&self.replicate_n)
            .map(|(&s, &k)| {
                let m = s / k as f64;
                k as f64 * (m - grand) * (m - grand)
            })
            .sum::<f64>();
        Some((ss, (REPLICATES - 1) as f64))
    }

    /// Whether every sample so far is black (zero luminance, so zero radiance).
    pub fn is_black(&self) -> bool {
        self.luma_sum <= 0.0
    }

    /// The brightest sample's luminance so far (adaptive samples only).
    pub fn brightest(&self) -> f64 {
        self.brightest
    }

    /// Mean luminance of the samples so far (0 before the first).
    pub fn mean_luminance(&self) -> f64 {
        self.luma_sum / self.n.max(1) as f64
    }

    /// Samples added so far (finite ones only).
    pub fn count(&self) -> u32 {
        self.n
    }

    /// The per-sample variance of the luminance relative to its squared mean (floored at
    /// [`REL_FLOOR`]), with its degrees of freedom: what one pixel tells its neighbours about
    /// theirs (`render::early_stop`). `None` before two samples or while every sample is black
    /// (a black pixel says nothing about relative spread).
    pub fn relative_sample_variance(&self) -> Option<(f64, f64)> {
        if self.n < 2 || self.is_black() {
            return None;
        }
        let n = self.n as f64;
        let mean = self.luma_sum / n;
        let var = ((self.luma_sum_sq - self.luma_sum * mean) / (n - 1.0)).max(0.0);
        Some((var / mean.abs().max(REL_FLOOR).powi(2), n - 1.0))
    }

    /// The between-replicate variance of the luminance, per sample (a mean of `n` samples has
    /// `1/n` of it), relative to the squared mean (floored at [`REL_FLOOR`]), with its degrees of
    /// freedom: what one pixel's replicates tell its neighbours at the pooled stop
    /// (`render::pooled_stop`). `None` until every replicate has a sample, or while every sample
    /// is black.
    pub fn relative_replicate_variance(&self) -> Option<(f64, f64)> {
        if self.is_black() {
            return None;
        }
        let (ss, dof) = self.between_replicates()?;
        Some((
            ss / dof / self.mean_luminance().abs().max(REL_FLOOR).powi(2),
            dof,
        ))
    }

    /// Relative standard error of the mean luminance (0 with fewer than two samples): the
    /// estimate a pixel reports, the per-sample prior at its full weight.
    pub fn relative_error(&self) -> f64 {
        self.relative_error_with_prior_cap(f64::INFINITY)
    }

    /// The estimate a pixel that has taken `1/target` samples itself decides to stop on:
    /// [`Accumulator::relative_error`] with the per-sample prior at most [`PRIOR_CAP`] times the
    /// replicates' estimate. It only lowers the estimate of pixels whose per-sample variance
    /// over-states their error by more than the replicates' spread could plausibly hide; what
    /// they report stays [`Accumulator::relative_error`] (reporting the capped figure too put
    /// cornell's reports at 0.56× the measured at 2%, the stop selecting pixels whose spread came
    /// out small; docs/quality.md).
    pub fn stopping_error(&self) -> f64 {
        self.relative_error_with_prior_cap(PRIOR_CAP)
    }

    fn relative_error_with_prior_cap(&self, cap: f64) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        let n = self.n as f64;
        let mean = self.luma_sum / n;
        let per_sample = ((self.luma_sum_sq - self.luma_sum * mean) / (n - 1.0)).max(0.0) / n;
        let var = match self.between_replicates() {
            Some((ss, dof)) => {
                let between = ss / dof / n;
                let per_sample = per_sample.min(cap * between);
                let prior = prior_dof(n);
                (prior * per_sample + dof * between) / (prior + dof)
            }
            None => per_sample,
        };
        // A pixel whose samples so far all agree (often all black: a light seen through a
        // small gap by a few percent of the samples) has a sample variance of zero, and
        // stopping there would bias it towards what it has not seen yet. The term
        // (REL_FLOOR / n)² keeps such a pixel sampling until n ≥ 1/target (the "rule of
        // three": no event in n samples bounds its probability by about 3/n).
        let floor = REL_FLOOR / n;
        (var + floor * floor).sqrt() / mean.abs().max(REL_FLOOR)
    }

    /// The estimate over `count` samples taken (dropped non-finite ones count as zero
    /// radiance, as in the plain average). The per-channel standard error is the per-sample
    /// one scaled by the ratio the luminance's two estimates show (the between-batch estimate
    /// is only kept for the luminance).
    pub fn finish(&self, count: u32, hit_max: bool) -> PixelEstimate {
        self.finish_with(count, hit_max, self.relative_error())
    }

    /// [`Accumulator::finish`] with the relative error estimated elsewhere (an early stop's,
    /// which pools the neighbourhood: `render::early_stop`).
    pub fn finish_with(&self, count: u32, hit_max: bool, relative_error: f64) -> PixelEstimate {
        let count = count.max(1);
        let mean = self.sum / count as f32;
        let std_error = if self.n >= 2 {
            let n = self.n as f64;
            let m = self.sum.as_dvec3() / n;
            let var = ((self.sum_sq - self.sum.as_dvec3() * m) / (n - 1.0)).max(DVec3::ZERO);
            let se = (var / n).map(f64::sqrt);
            // Luminance: per-sample relative error against the combined one.
            let luma_mean = self.luma_sum / n;
            let per_sample =
                (((self.luma_sum_sq - self.luma_sum * luma_mean) / (n - 1.0)).max(0.0) / n).sqrt();
            let combined = relative_error * luma_mean.abs().max(REL_FLOOR);
            let ratio = if per_sample > 0.0 {
                (combined / per_sample).min(1.0)
            } else {
                1.0
            };
            (se * ratio).as_vec3()
        } else {
            Vec3::ZERO
        };
        PixelEstimate {
            mean,
            std_error,
            relative_error: relative_error as f32,
            samples: count,
            hit_max,
        }
    }
}

/// What one pixel's samples say.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelEstimate {
    /// Linear RGB radiance: the plain mean of the samples.
    pub mean: Vec3,
    /// Standard error of the mean per channel (0 with fewer than two samples).
    pub std_error: Vec3,
    /// Relative standard error of the mean luminance.
    pub relative_error: f32,
    /// Samples taken.
    pub samples: u32,
    /// Adaptive sampling stopped at `max_samples` above the target.
    pub hit_max: bool,
}

/// The image's sampling figures, for `--stats`, the summary line and `scnc bench quality`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NoiseStats {
    /// The adaptive target, if the render was adaptive.
    pub target: Option<f32>,
    /// The most samples a pixel could take.
    pub max_samples: u32,
    /// Mean over pixels of the relative standard error of the mean.
    pub mean_relative_error: f64,
    /// Maximum over pixels of the relative standard error of the mean.
    pub max_relative_error: f64,
    /// Root mean square over pixels brighter than [`RMS_MIN_LUMINANCE`] of the relative
    /// standard error (the figure to compare with a measured RMS relative error).
    pub rms_relative_error: f64,
    /// Pixels counted in `rms_relative_error`.
    pub rms_pixels: u64,
    /// Pixels counted.
    pub pixels: u64,
    /// Pixels whose adaptive sampling stopped at `max_samples`.
    pub pixels_at_max: u64,
    /// Samples over all pixels.
    pub samples: u64,
}

impl NoiseStats {
    /// Counts one pixel.
    pub fn add(&mut self, p: &PixelEstimate) {
        self.pixels += 1;
        self.samples += p.samples as u64;
        self.pixels_at_max += p.hit_max as u64;
        self.mean_relative_error += p.relative_error as f64;
        self.max_relative_error = self.max_relative_error.max(p.relative_error as f64);
        if luminance_f64(p.mean.as_dvec3()) > RMS_MIN_LUMINANCE {
            self.rms_pixels += 1;
            self.rms_relative_error += (p.relative_error as f64).powi(2);
        }
    }

    /// Turns the running sum into the mean (call once, after every pixel).
    pub fn finish(&mut self) {
        if self.pixels > 0 {
            self.mean_relative_error /= self.pixels as f64;
        }
        if self.rms_pixels > 0 {
            self.rms_relative_error = (self.rms_relative_error / self.rms_pixels as f64).sqrt();
        }
    }

    /// Mean samples per pixel.
    pub fn mean_samples(&self) -> f64 {
        self.samples as f64 / self.pixels.max(1) as f64
    }

    /// The summary line, e.g. `noise: target 1.00%, achieved RMS 0.82% over pixels brighter
    /// than 0.01, mean 0.71% (max 2.3%) relative standard error; 12 of 4096 pixels (0.29%) hit
    /// max_samples 4096; 803.1 samples/pixel`.
    pub fn summary(&self) -> String {
        let head = match self.target {
            Some(t) => format!("noise: target {:.2}%, achieved", t as f64 * 100.0),
            None => "noise: estimated".to_string(),
        };
        let mut s = format!(
            "{head} RMS {:.2}% over pixels brighter than {RMS_MIN_LUMINANCE}, mean {:.2}% \
             (max {:.2}%) relative standard error",
            self.rms_relative_error * 100.0,
            self.mean_relative_error * 100.0,
            self.max_relative_error * 100.0
        );
        if self.target.is_some() {
            s += &format!(
                "; {} of {} pixels ({:.2}%) hit max_samples {}",
                self.pixels_at_max,
                self.pixels,
                100.0 * self.pixels_at_max as f64 / self.pixels.max(1) as f64,
                self.max_samples
            );
        }
        s + &format!("; {:.1} samples/pixel", self.mean_samples())
    }
}

/// The batch sizes of an adaptive pixel with cap `max_samples`: the shared first round in two
/// halves ([`FIRST_BATCH`] each), then batches of [`BATCH`] (a 4-point block of each
/// replicate's own sequence) until the cap is reached or passed.
pub fn batch_sizes(max_samples: u32) -> Vec<u32> {
    let mut sizes = vec![FIRST_BATCH];
    let mut total = FIRST_BATCH;
    if total < max_samples {
        sizes.push(REPLICATES - FIRST_BATCH);
        total = REPLICATES;
    }
    while total < max_samples {
        sizes.push(BATCH);
        total += BATCH;
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_between_replicates_decides() {
        // Samples that vary a lot within each replicate but whose replicate means agree (what
        // stratification does): the per-sample formula says "noisy", the replicates say
        // "done".
        let mut a = Accumulator::default();
        let mut b = Accumulator::default();
        for g in 0..64 * REPLICATES {
            let x = [0.0f32, 2.0, 1.0, 1.0][(g / REPLICATES % 4) as usize];
            a.add_replicate(Vec3::splat(x), Some((g % REPLICATES) as usize));
            b.add(Vec3::splat(x));
        }
        let per_sample = b.relative_error();
        // Identical replicate means: the combined estimate is the prior's share only.
        let dof = (REPLICATES - 1) as f64;
        let prior = prior_dof((64 * REPLICATES) as f64);
        assert!((prior - PRIOR_DOF / 2.0).abs() < 1e-12);
        let expected = per_sample * (prior / (prior + dof)).sqrt();
        assert!(
            (a.relative_error() - expected).abs() < 1e-3 * expected,
            "{a:?}"
        );
        // Replicates whose means differ: the estimate follows their spread. Means 0.9 and 1.1
        // (two replicates each), constant within: the between-replicate variance of the mean
        // is Σ k (m − 1)² / (R − 1) / n = 0.01 / 3 however large n is, while the per-sample
        // one is about 0.01 / n; the estimate is their mix, weighted by degrees of freedom.
        let mut c = Accumulator::default();
        let n = 100 * REPLICATES;
        for g in 0..n {
            let r = (g % REPLICATES) as usize;
            c.add_replicate(
                Vec3::splat(if r.is_multiple_of(2) { 0.9 } else { 1.1 }),
                Some(r),
            );
        }
        let between = 0.01 / dof;
        let per = 0.01 / (n as f64 - 1.0);
        let prior = prior_dof(n as f64);
        let mixed = ((prior * per + dof * between) / (prior + dof)).sqrt();
        assert!(
            (c.relative_error() - mixed).abs() < 1e-3 * mixed,
            "{} against {mixed}",
            c.relative_error()
        );
    }

    #[test]
    fn the_prior_is_capped_where_the_replicates_rule_it_out() {
        // Replicates whose means differ by ±1e-3 around 1 while every replicate's samples
        // swing between 0 and 2: the per-sample variance (about 1) over-states the error of
        // the mean, 1/n, by far more than PRIOR_CAP times the replicates' spread.
        let mut a = Accumulator::default();
        let n = 16 * REPLICATES;
        for g in 0..n {
            let r = (g % REPLICATES) as usize;
            let shift = if r.is_multiple_of(2) { 1e-3 } else { -1e-3 };
            let swing = if (g / REPLICATES).is_multiple_of(2) {
                1.0
            } else {
                -1.0
            };
            a.add_replicate(Vec3::splat((1.0 + shift + swing) as f32), Some(r));
        }
        let (ss, dof) = a.between_replicates().expect("every replicate sampled");
        let nf = n as f64;
        let between = ss / dof / nf;
        let per_sample = 1.0 / nf;
        assert!(
            per_sample > PRIOR_CAP * between,
            "{per_sample} against {between}"
        );
        // Reported: the prior at its full weight; deciding: the prior at PRIOR_CAP × between.
        let prior = prior_dof(nf);
        let mean = a.mean_luminance();
        let floor = (REL_FLOOR / nf).powi(2);
        let with = |p: f64| ((prior * p + dof * between) / (prior + dof) + floor).sqrt() / mean;
        let expected_report = with((a.luma_sum_sq - a.luma_sum * mean) / (nf - 1.0) / nf);
        assert!((a.relative_error() - expected_report).abs() < 1e-9 * expected_report);
        let expected_stop = with(PRIOR_CAP * between);
        assert!((a.stopping_error() - expected_stop).abs() < 1e-9 * expected_stop);
        assert!(a.stopping_error() < 0.5 * a.relative_error());
        // Where the replicates disagree as much as the samples, the cap changes nothing.
        let mut b = Accumulator::default();
        for g in 0..n {
            let r = (g % REPLICATES) as usize;
            b.add_replicate(Vec3::splat(if r < 2 { 0.5 } else { 1.5 }), Some(r));
        }
        assert_eq!(b.stopping_error(), b.relative_error());
    }

    #[test]
    fn dim_pixels_are_judged_against_the_floor() {
        let floor = dim_floor(0.0);
        assert_eq!(floor, DIM_LUMINANCE);
        // Two stops of exposure: the floor is a quarter in radiance.
        assert!((dim_floor(2.0) - DIM_LUMINANCE / 4.0).abs() < 1e-15);
        // Brighter than the floor: the relative target as it is.
        assert_eq!(dim_scale(0.5, floor), 1.0);
        // A quarter of the floor: four times the relative error, the same absolute one.
        assert!((dim_scale(0.25 * floor, floor) - 4.0).abs() < 1e-12);
        // Under REL_FLOOR the relative error is already measured against it.
        assert!((dim_scale(0.0, floor) - floor / REL_FLOOR).abs() < 1e-9);
        // A floor under REL_FLOOR (high exposure) never tightens the rule.
        assert_eq!(dim_scale(1e-4, 1e-4), 1.0);
    }

    #[test]
    fn standard_error_of_known_samples() {
        let mut a = Accumulator::default();
        for x in [1.0f32, 3.0, 1.0, 3.0] {
            a.add(Vec3::splat(x));
        }
        let e = a.finish(4, false);
        assert_eq!(e.mean, Vec3::splat(2.0));
        // Sample variance 4/3, standard error sqrt(4/3 / 4) = 0.57735.
        assert!((e.std_error.x - 0.57735).abs() < 1e-5, "{e:?}");
        assert!((e.relative_error - 0.57735 / 2.0).abs() < 1e-5);
    }

    #[test]
    fn constant_and_black_pixels_have_no_error() {
        let mut a = Accumulator::default();
        let mut b = Accumulator::default();
        for _ in 0..16 {
            a.add(Vec3::new(0.2, 0.5, 0.9));
            b.add(Vec3::ZERO);
        }
        // A constant pixel has no error beyond the floor term; a black one needs 1/target
        // samples before it may stop.
        assert!(a.relative_error() < 1e-3, "{}", a.relative_error());
        assert!((b.relative_error() - 1.0 / 16.0).abs() < 1e-9);
        assert_eq!(batch_sizes(2), vec![2]);
        assert_eq!(batch_sizes(4), vec![2, 2]);
        assert_eq!(batch_sizes(8), vec![2, 2, 16]);
        assert_eq!(batch_sizes(20), vec![2, 2, 16]);
        assert_eq!(batch_sizes(21), vec![2, 2, 16, 16]);
        assert_eq!(batch_sizes(4096).iter().sum::<u32>(), 4100);
        assert_eq!(emitter_min_samples(0.1), 80);
        assert_eq!(black_min_samples(0.1), 30);
        assert!(b.is_black() && !a.is_black());
    }
}
