//! Stage 3 helper: a piecewise-constant 2-D distribution over a `width × height` grid of
//! non-negative weights (a marginal over rows, a conditional per row), sampled by inverting the
//! two CDFs. Used to importance-sample environment maps (`light sky = environment {
//! image("sky.hdr") }`), where the weights are luminance × sin θ.
//!
//! The density is over the unit square `[0, 1)²` (u along a row, v down the rows):
//! `pdf_uv(cell) = weight(cell) / Σ weights · width · height`, constant inside a cell. The
//! conditional CDFs are stored flat (one allocation, not one per row) and built in parallel,
//! so a 4096 × 2048 map is a few tens of milliseconds (see `benches/environment.rs`).

use glam::Vec2;
use rayon::prelude::*;

use super::distribution::Distribution1D;

#[derive(Debug, Clone)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    /// Cleaned weights (finite, ≥ 0), row-major.
    weights: Vec<f32>,
    /// Per row, `width + 1` CDF values `0 … 1` (a zero row keeps an all-zero CDF: never picked).
    cdf: Vec<f32>,
    row_sums: Vec<f32>,
    marginal: Distribution1D,
}

/// A sampled cell and point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample2D {
    /// The point in `[0, 1)²`.
    pub uv: Vec2,
    pub col: usize,
    pub row: usize,
    /// Density with respect to area on the unit square.
    pub pdf_uv: f32,
}

impl Distribution2D {
    /// `None` when nothing can be picked (no cell with a positive, finite weight) or when
    /// `weights.len() != width · height`.
    pub fn new(width: usize, height: usize, mut weights: Vec<f32>) -> Option<Distribution2D> {
        if width == 0 || height == 0 || weights.len() != width.checked_mul(height)? {
            return None;
        }
        for w in &mut weights {
            if !(w.is_finite() && *w > 0.0) {
                *w = 0.0;
            }
        }
        let mut cdf = vec![0.0f32; (width + 1) * height];
        let row_sums: Vec<f32> = weights
            .par_chunks(width)
            .zip(cdf.par_chunks_mut(width + 1))
            .map(|(row, cdf)| {
                let mut acc = 0.0f64;
                cdf[0] = 0.0;
                for (c, &w) in row.iter().enumerate() {
                    acc += w as f64;
                    cdf[c + 1] = acc as f32;
                }
                if acc > 0.0 {
                    let inv = 1.0 / acc;
                    for c in cdf.iter_mut() {
                        *c = (*c as f64 * inv) as f32;
                    }
                    cdf[width] = 1.0;
                }
                acc as f32
            })
            .collect();
        let marginal = Distribution1D::new(&row_sums)?;
        Some(Distribution2D {
            width,
            height,
            weights,
            cdf,
            row_sums,
            marginal,
        })
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// A point for `u` in `[0, 1)²`: `u.y` picks the row, `u.x` the column, and the remainders
    /// place the point inside the cell (so stratified `u` stay stratified).
    pub fn sample(&self, u: Vec2) -> Sample2D {
        let (row, pmf_row, v_in) = self.marginal.sample(u.y);
        let cdf = &self.cdf[row * (self.width + 1)..(row + 1) * (self.width + 1)];
        let col = cdf[1..].partition_point(|&c| c <= u.x).min(self.width - 1);
        let (lo, hi) = (cdf[col], cdf[col + 1]);
        let u_in = if hi > lo {
            ((u.x - lo) / (hi - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0)
        } else {
            0.5
        };
        let uv = Vec2::new(
            (col as f32 + u_in) / self.width as f32,
            (row as f32 + v_in) / self.height as f32,
        );
        Sample2D {
            uv: uv.min(Vec2::splat(1.0 - f32::EPSILON / 2.0)),
            col,
            row,
            pdf_uv: pmf_row * self.conditional(col, row) * (self.width * self.height) as f32,
        }
    }

    /// The density of cell (`col`, `row`) over the unit square; 0 outside the grid.
    pub fn pdf_uv(&self, col: usize, row: usize) -> f32 {
        if col >= self.width || row >= self.height {
            return 0.0;
        }
        self.marginal.pmf(row) * self.conditional(col, row) * (self.width * self.height) as f32
    }

    /// P(column | row).
    fn conditional(&self, col: usize, row: usize) -> f32 {
        let sum = self.row_sums[row];
        if sum > 0.0 {
            self.weights[row * self.width + col] / sum
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_or_mismatched_weights_give_none() {
        assert!(Distribution2D::new(2, 2, vec![0.0; 4]).is_none());
        assert!(Distribution2D::new(2, 2, vec![1.0; 3]).is_none());
        assert!(Distribution2D::new(0, 2, vec![]).is_none());
        assert!(Distribution2D::new(1, 2, vec![f32::NAN, -1.0]).is_none());
    }

    #[test]
    fn pdf_sums_to_one_and_frequencies_match() {
        let (w, h) = (4, 3);
        let weights = vec![1.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.0, 3.0, 1.0, 1.0, 7.0];
        let d = Distribution2D::new(w, h, weights.clone()).expect("positive");
        let total: f32 = (0..h)
            .flat_map(|r| (0..w).map(move |c| (c, r)))
            .map(|(c, r)| d.pdf_uv(c, r) / (w * h) as f32)
            .sum();
        assert!((total - 1.0).abs() < 1e-6);
        let n = 200;
        let mut counts = vec![0usize; w * h];
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let s = d.sample(u);
                assert_eq!(s.col, (s.uv.x * w as f32) as usize);
                assert_eq!(s.row, (s.uv.y * h as f32) as usize);
                assert_eq!(s.pdf_uv, d.pdf_uv(s.col, s.row));
                counts[s.row * w + s.col] += 1;
            }
        }
        for (k, &c) in counts.iter().enumerate() {
            let expected = weights[k] / 16.0 * (n * n) as f32;
            // Stratified inputs: each count is within a couple of strata of its expectation.
            assert!((c as f32 - expected).abs() <= 2.0 * n as f32, "{counts:?}");
            assert_eq!(c == 0, weights[k] == 0.0);
        }
    }
}
