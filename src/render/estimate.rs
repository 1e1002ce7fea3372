//! Stage 4: one pixel's estimate from its samples: the mean (the box-filtered radiance), the
//! standard error of that mean, and the adaptive stopping rule of `render { noise 0.01
//! max_samples 4096 }` / `--noise 0.01`.
//!
//! **The error estimate is right for stratified samples.** Adaptive sampling takes batches;
//! each batch is an independent randomised stratified set (its own shifted
//! rotated grid and its own scrambled light-sample sets, see `render::batch`). The means of
//! independent batches are independent, identically distributed estimates, so the spread
//! between them measures the real error of their average, stratification included (the
//! classic error estimate of randomised quasi-Monte Carlo: independent replicates, as Owen
//! and L'Ecuyer use them). The samples' own spread (`σ̂² / n`, the formula for independent
//! samples) over-states the error of stratified samples, by 2–6× on cornell, which is why
//! adaptive renders used to stop with 4–6× less error than asked.
//!
//! With few batches the between-batch variance is itself noisy (B − 1 degrees of freedom),
//! and stopping on a luckily small estimate biases the pixel. So the two are combined as a
//! posterior with a prior: the per-sample estimate, an upper bound in expectation, counts as
//! [`PRIOR_DOF`] degrees of freedom, the between-batch estimate as `B − 1`; early decisions
//! lean on the conservative one, later ones on the accurate one. Relative error is that of the
//! luminance, divided by the mean luminance floored at [`REL_FLOOR`]; a term `REL_FLOOR / n`
//! keeps pixels whose samples all agree so far (all black) sampling until `n ≥ 1/target`.
//!
//! A pixel takes [`FIRST_BATCHES`] small batches of [`FIRST_BATCH`] (a flat, directly lit pixel
//! may stop there), then batches of [`BATCH`], and stops after the first batch at which its
//! relative error is at most the target or its count reached `max_samples`. Every decision uses the
//! pixel's own samples only, so the image does not depend on threads or tiles.

use glam::{DVec3, Vec3};

/// Samples per first batch along each side of the rotated grid.
pub const FIRST_BATCH_SIDE: u32 = 2;
/// Samples per first batch: small, so that a pixel that needs little (a flat, directly lit
/// wall) can stop after a few.
pub const FIRST_BATCH: u32 = FIRST_BATCH_SIDE * FIRST_BATCH_SIDE;
/// How many small batches come first; the first decision is after them.
pub const FIRST_BATCHES: u32 = 2;
/// Samples per later batch along each side of the rotated grid.
pub const BATCH_SIDE: u32 = 4;
/// Samples per later batch: a 4×4 stratified set keeps most of the stratification a fixed
/// pattern has (batches of 4 measured 3× the RMSE of a fixed 256-sample render at 256 samples
/// on cornell; batches of 16, under 2.5×).
pub const BATCH: u32 = BATCH_SIDE * BATCH_SIDE;
/// Weight, in degrees of freedom, of the per-sample variance estimate (conservative for
/// stratified samples) against the between-batch one (`B − 1` degrees of freedom).
pub const PRIOR_DOF: f64 = 1.0;
/// Mean luminance below which relative error is measured against this value instead.
pub const REL_FLOOR: f64 = 1e-3;

/// Luminance above which a pixel counts in [`NoiseStats::rms_relative_error`]: darker pixels'
/// relative error is dominated by the [`REL_FLOOR`] and says little about the image.
pub const RMS_MIN_LUMINANCE: f64 = 0.01;

/// Rec. 709 luminance weights (linear RGB).
const LUMA: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// Running sums of one pixel's samples and of its batches' means.
#[derive(Debug, Clone, Copy, Default)]
pub struct Accumulator {
    /// f32 like the film, so a fixed-count render's mean is bit-identical to the plain average.
    sum: Vec3,
    sum_sq: DVec3,
    luma_sum: f64,
    luma_sum_sq: f64,
    n: u32,
    /// Luminance sum and count of the batch under way.
    batch_luma: f64,
    batch_n: u32,
    /// Closed batches, in two groups of equal size (the small first ones, the full ones):
    /// count, sum of their mean luminances, sum of squares.
    groups: [BatchGroup; 2],
}

/// Batches of one size: how many, the sum of their mean luminances and of its squares.
#[derive(Debug, Clone, Copy, Default)]
struct BatchGroup {
    size: u32,
    count: u32,
    mean_sum: f64,
    mean_sum_sq: f64,
}

impl BatchGroup {
    /// The between-batch sum of squares scaled by the batch size (an estimate of `c` times
    /// its degrees of freedom, where a batch mean of `k` samples has variance `c / k`), and
    /// those degrees of freedom.
    fn scaled_spread(&self) -> (f64, f64) {
        if self.count < 2 {
            return (0.0, 0.0);
        }
        let b = self.count as f64;
        let ss = (self.mean_sum_sq - self.mean_sum * self.mean_sum / b).max(0.0);
        (ss * self.size as f64, b - 1.0)
    }
}

impl Accumulator {
    /// Adds one sample's radiance.
    pub fn add(&mut self, l: Vec3) {
        self.sum += l;
        let d = l.as_dvec3();
        self.sum_sq += d * d;
        let y = d.dot(LUMA);
        self.luma_sum += y;
        self.luma_sum_sq += y * y;
        self.n += 1;
        self.batch_luma += y;
        self.batch_n += 1;
    }

    /// Closes the batch under way (of `size` samples planned); its mean joins the spread of
    /// the batches of its size.
    pub fn end_batch(&mut self, size: u32) {
        if self.batch_n > 0 {
            let m = self.batch_luma / self.batch_n as f64;
            let g = &mut self.groups[usize::from(size == BATCH)];
            g.size = size;
            g.count += 1;
            g.mean_sum += m;
            g.mean_sum_sq += m * m;
        }
        self.batch_luma = 0.0;
        self.batch_n = 0;
    }

    /// Samples added so far (finite ones only).
    pub fn count(&self) -> u32 {
        self.n
    }

    /// Relative standard error of the mean luminance (0 with fewer than two samples).
    pub fn relative_error(&self) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        let n = self.n as f64;
        let mean = self.luma_sum / n;
        let per_sample = ((self.luma_sum_sq - self.luma_sum * mean) / (n - 1.0)).max(0.0) / n;
        // Pooled over the two batch sizes, as in a one-way analysis of variance: a batch
        // mean of k samples has variance c / k, so the mean of all n has c / n.
        let (ss0, dof0) = self.groups[0].scaled_spread();
        let (ss1, dof1) = self.groups[1].scaled_spread();
        let dof = dof0 + dof1;
        let var = if dof > 0.0 {
            let between = (ss0 + ss1) / dof / n;
            (PRIOR_DOF * per_sample + dof * between) / (PRIOR_DOF + dof)
        } else {
            per_sample
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
        let count = count.max(1);
        let mean = self.sum / count as f32;
        let relative_error = self.relative_error();
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
        if p.mean.as_dvec3().dot(LUMA) > RMS_MIN_LUMINANCE {
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

/// The batch sizes of an adaptive pixel with cap `max_samples`: [`FIRST_BATCHES`] of
/// [`FIRST_BATCH`], then batches of [`BATCH`] until the cap is reached or passed.
pub fn batch_sizes(max_samples: u32) -> Vec<u32> {
    let mut sizes = vec![FIRST_BATCH; FIRST_BATCHES as usize];
    let mut total = FIRST_BATCH * FIRST_BATCHES;
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
    fn the_spread_between_batches_decides_once_there_are_enough() {
        // Samples that vary a lot within each batch but whose batch means agree (what
        // stratification does): the per-sample formula says "noisy", the batches say "done".
        let mut a = Accumulator::default();
        for _ in 0..64 {
            for x in [0.0f32, 2.0, 1.0, 1.0] {
                a.add(Vec3::splat(x));
            }
            a.end_batch(FIRST_BATCH);
        }
        let per_sample = {
            let mut b = Accumulator::default();
            for _ in 0..64 {
                for x in [0.0f32, 2.0, 1.0, 1.0] {
                    b.add(Vec3::splat(x));
                }
            }
            b.relative_error()
        };
        // 64 batches, identical means: the combined estimate is the prior's share only,
        // PRIOR_DOF / (PRIOR_DOF + 63) of the per-sample variance.
        let expected = per_sample * (PRIOR_DOF / (PRIOR_DOF + 63.0)).sqrt();
        assert!(
            (a.relative_error() - expected).abs() < 1e-3 * expected,
            "{a:?}"
        );
        // Batches whose means differ: the estimate follows the spread of the means.
        let mut c = Accumulator::default();
        for k in 0..400 {
            let m = if k % 2 == 0 { 0.9f32 } else { 1.1 };
            for _ in 0..4 {
                c.add(Vec3::splat(m));
            }
            c.end_batch(FIRST_BATCH);
        }
        // Means alternate 0.9/1.1: their spread is 0.1, over √400 batches: 0.005; the
        // per-sample spread says the same here, so the combination must too.
        assert!(
            (c.relative_error() - 0.005).abs() < 2e-4,
            "{}",
            c.relative_error()
        );
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
        assert_eq!(batch_sizes(8), vec![4, 4]);
        assert_eq!(batch_sizes(9), vec![4, 4, 16]);
        assert_eq!(batch_sizes(4096).iter().sum::<u32>(), 4104);
    }
}
