//! Stage 4: one pixel's estimate from its samples: the mean (the box-filtered radiance), the
//! standard error of that mean, and the adaptive stopping rule of `render { noise 0.01
//! max_samples 4096 }` / `--noise 0.01`.
//!
//! The error is estimated from the samples' own spread: `σ̂² / n` with the unbiased sample
//! variance. The pixel samples are stratified (rotated grid, stratified light samples), so this
//! over-estimates the true error of the mean: adaptive sampling stops a little later than it
//! must, never earlier on average. Relative error is that of the luminance, divided by the mean
//! luminance floored at [`REL_FLOOR`] so that near-black pixels are not chased forever; a
//! term `REL_FLOOR / n` keeps pixels whose samples all agree so far (all black) sampling until
//! `n ≥ 1/target`, which removes most of the stopping bias of adaptive sampling.
//!
//! Adaptive sampling takes batches of [`BATCH`] samples (one 4×4 pattern, with its own
//! stratification sets), at least [`MIN_BATCHES`] of them, and stops after the first batch at
//! which the pixel's relative error is at most the target or its count reached `max_samples`.
//! Every decision uses the pixel's own samples only, so the image does not depend on threads.

use glam::{DVec3, Vec3};

/// Samples per adaptive batch: a 4×4 pattern.
pub const BATCH_SIDE: u32 = 4;
/// Samples per adaptive batch.
pub const BATCH: u32 = BATCH_SIDE * BATCH_SIDE;
/// Batches before the first stopping decision (32 samples: a sample variance from fewer is too
/// often luckily small).
pub const MIN_BATCHES: u32 = 2;
/// Mean luminance below which relative error is measured against this value instead.
pub const REL_FLOOR: f64 = 1e-3;

/// Rec. 709 luminance weights (linear RGB).
const LUMA: DVec3 = DVec3::new(0.2126, 0.7152, 0.0722);

/// Running sums of one pixel's samples.
#[derive(Debug, Clone, Copy, Default)]
pub struct Accumulator {
    /// f32 like the film, so a fixed-count render's mean is bit-identical to the plain average.
    sum: Vec3,
    sum_sq: DVec3,
    luma_sum: f64,
    luma_sum_sq: f64,
    n: u32,
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
        let var = ((self.luma_sum_sq - self.luma_sum * mean) / (n - 1.0)).max(0.0);
        // A pixel whose samples so far all agree (often all black: a light seen through a
        // small gap by a few percent of the samples) has a sample variance of zero, and
        // stopping there would bias it towards what it has not seen yet. The term
        // (REL_FLOOR / n)² keeps such a pixel sampling until n ≥ 1/target (the "rule of
        // three": no event in n samples bounds its probability by about 3/n).
        let floor = REL_FLOOR / n;
        (var / n + floor * floor).sqrt() / mean.abs().max(REL_FLOOR)
    }

    /// The estimate over `count` samples taken (dropped non-finite ones count as zero
    /// radiance, as in the plain average).
    pub fn finish(&self, count: u32, hit_max: bool) -> PixelEstimate {
        let count = count.max(1);
        let mean = self.sum / count as f32;
        let std_error = if self.n >= 2 {
            let n = self.n as f64;
            let m = self.sum.as_dvec3() / n;
            let var = ((self.sum_sq - self.sum.as_dvec3() * m) / (n - 1.0)).max(DVec3::ZERO);
            let se = var / n;
            Vec3::new(se.x.sqrt() as f32, se.y.sqrt() as f32, se.z.sqrt() as f32)
        } else {
            Vec3::ZERO
        };
        PixelEstimate {
            mean,
            std_error,
            relative_error: self.relative_error() as f32,
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
    }

    /// Turns the running sum into the mean (call once, after every pixel).
    pub fn finish(&mut self) {
        if self.pixels > 0 {
            self.mean_relative_error /= self.pixels as f64;
        }
    }

    /// Mean samples per pixel.
    pub fn mean_samples(&self) -> f64 {
        self.samples as f64 / self.pixels.max(1) as f64
    }

    /// The summary line, e.g. `noise: target 1.00%, achieved mean 0.71% (max 2.3%) relative
    /// standard error; 12 of 4096 pixels (0.29%) hit max_samples 4096; 803.1 samples/pixel`.
    pub fn summary(&self) -> String {
        let head = match self.target {
            Some(t) => format!("noise: target {:.2}%, achieved", t as f64 * 100.0),
            None => "noise: estimated".to_string(),
        };
        let mut s = format!(
            "{head} mean {:.2}% (max {:.2}%) relative standard error",
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

/// The adaptive cap rounded up to whole batches, at least [`MIN_BATCHES`].
pub fn batches_for(max_samples: u32) -> u32 {
    max_samples.div_ceil(BATCH).max(MIN_BATCHES)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(batches_for(4096), 256);
        assert_eq!(batches_for(17), 2);
        assert_eq!(batches_for(100), 7);
    }
}
