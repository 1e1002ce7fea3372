//! Shading layer: a piecewise-constant 2-D distribution over a `width × height` grid of
//! non-negative weights (a marginal over rows, a conditional per row), sampled by inverting the
//! two CDFs. Used to importance-sample environment maps (`light sky = environment {
//! image("sky.hdr") }`), where the weights are luminance × sin θ.
//!
//! The density is over the unit square `[0, 1)²` (u along a row, v down the rows):
//! `pdf_uv(cell) = P(row) · P(col | row) · width · height`, constant inside a cell, with
//! `P(col | row) = cdf[col + 1] − cdf[col]`: the conditional probability is read from the same
//! f32 CDF the sampler inverts, so it is exactly the frequency with which the cell is sampled
//! (a cell whose weight is below f32 resolution of its row's total is never sampled and has
//! density 0, consistently). The conditional CDFs are stored flat (one allocation, not one per
//! row) and built in parallel, so a 4096 × 2048 map takes a few tens of milliseconds; each row
//! has a guide table of [`GUIDES`] entries (the first cell whose CDF passes `k / GUIDES`) so a
//! sample searches a few cache lines instead of the whole row (see `benches/environment.rs`).

use glam::Vec2;
use rayon::prelude::*;

use super::distribution::Distribution1D;

/// Guide entries per row, for rows of at least [`GUIDED_WIDTH`] cells.
pub const GUIDES: usize = 128;

/// Rows narrower than this are searched whole (a few steps), without guides.
pub const GUIDED_WIDTH: usize = 256;

/// Picks a cell of a `width × height` grid with probability proportional to its weight, and a
/// point uniform inside it.
#[derive(Debug, Clone)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    /// Per row, `width + 1` CDF values `0 … 1` (a zero row keeps an all-zero CDF: never picked).
    cdf: Vec<f32>,
    /// Per row, `guides + 1` cells: entry `k` is the first cell `c` with `cdf[c + 1] > k/guides`.
    guide: Vec<u32>,
    /// Guide entries per row: [`GUIDES`], or 0 for rows narrower than [`GUIDED_WIDTH`].
    guides: usize,
    marginal: Distribution1D,
}

/// A sampled cell and point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample2D {
    /// The point in `[0, 1)²`.
    pub uv: Vec2,
    /// The cell's column (along u).
    pub col: usize,
    /// The cell's row (along v).
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
        let guides = if width >= GUIDED_WIDTH { GUIDES } else { 0 };
        let mut guide = vec![0u32; if guides > 0 { (guides + 1) * height } else { 0 }];
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
        if guides > 0 {
            guide
                .par_chunks_mut(guides + 1)
                .zip(cdf.par_chunks(width + 1))
                .for_each(|(guide, cdf)| {
                    for (k, g) in guide.iter_mut().enumerate() {
                        let threshold = k as f32 / guides as f32;
                        let first = cdf[1..].partition_point(|&c| c <= threshold);
                        *g = first.min(width - 1) as u32;
                    }
                });
        }
        let marginal = Distribution1D::new(&row_sums)?;
        Some(Distribution2D {
            width,
            height,
            cdf,
            guide,
            guides,
            marginal,
        })
    }

    /// Heap memory of the tables (conditional CDFs, guides, marginal).
    pub fn bytes(&self) -> usize {
        self.cdf.len() * std::mem::size_of::<f32>()
            + self.guide.len() * std::mem::size_of::<u32>()
            + self.marginal.bytes()
    }

    /// Cells per row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }

    /// A point for `u` in `[0, 1)²`: `u.y` picks the row, `u.x` the column, and the remainders
    /// place the point inside the cell (so stratified `u` stay stratified).
    pub fn sample(&self, u: Vec2) -> Sample2D {
        let (col, row, rest) = self.pick(u);
        let uv = Vec2::new(
            (col as f32 + rest.x) / self.width as f32,
            (row as f32 + rest.y) / self.height as f32,
        );
        Sample2D {
            uv: uv.min(Vec2::splat(1.0 - f32::EPSILON / 2.0)),
            col,
            row,
            pdf_uv: self.pmf(col, row) * (self.width * self.height) as f32,
        }
    }

    /// The cell for `u` in `[0, 1)²` (`u.y` picks the row, `u.x` the column), and `u` rescaled
    /// to `[0, 1)²` inside the cell's buckets, so that a finer table can use it again without
    /// losing its stratification in either coordinate.
    pub fn pick(&self, u: Vec2) -> (usize, usize, Vec2) {
        let (row, _, v_in) = self.marginal.sample(u.y);
        let cdf = &self.cdf[row * (self.width + 1)..(row + 1) * (self.width + 1)];
        let col = if self.guides > 0 {
            // The answer lies between the guides of u's bracket (`u < (k + 1)/guides`).
            let g = self.guides;
            let k = ((u.x * g as f32) as usize).min(g - 1);
            let guide = &self.guide[row * (g + 1)..(row + 1) * (g + 1)];
            let (lo, hi) = (guide[k] as usize, guide[k + 1] as usize);
            lo + cdf[lo + 1..=hi + 1].partition_point(|&c| c <= u.x)
        } else if self.width <= 64 {
            // A short row: count the cells that end at or before `u.x` (the binary search's
            // answer, without its unpredictable branches).
            cdf[1..].iter().filter(|&&c| c <= u.x).count()
        } else {
            cdf[1..].partition_point(|&c| c <= u.x)
        }
        .min(self.width - 1);
        let (lo, hi) = (cdf[col], cdf[col + 1]);
        let u_in = if hi > lo {
            ((u.x - lo) / (hi - lo)).clamp(0.0, 1.0 - f32::EPSILON / 2.0)
        } else {
            0.5
        };
        (col, row, Vec2::new(u_in, v_in))
    }

    /// The probability with which [`Distribution2D::pick`] chooses cell (`col`, `row`), read
    /// from the tables it inverts; 0 outside the grid.
    pub fn pmf(&self, col: usize, row: usize) -> f32 {
        if col >= self.width || row >= self.height {
            return 0.0;
        }
        self.marginal.pmf(row) * self.conditional(col, row)
    }

    /// The density of cell (`col`, `row`) over the unit square; 0 outside the grid.
    pub fn pdf_uv(&self, col: usize, row: usize) -> f32 {
        self.pmf(col, row) * (self.width * self.height) as f32
    }

    /// P(column | row), as sampled.
    fn conditional(&self, col: usize, row: usize) -> f32 {
        let i = row * (self.width + 1) + col;
        self.cdf[i + 1] - self.cdf[i]
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
    fn pick_is_the_sample_s_cell_and_its_remainders_are_stratified() {
        let weights = vec![1.0, 0.0, 2.0, 1.0, 0.5, 3.0, 0.0, 0.25, 3.0, 1.0, 1.0, 7.0];
        let d = Distribution2D::new(4, 3, weights).expect("positive");
        let total: f32 = (0..3)
            .flat_map(|r| (0..4).map(move |c| (c, r)))
            .map(|(c, r)| d.pmf(c, r))
            .sum();
        assert!((total - 1.0).abs() < 1e-6);
        // A 64 × 64 grid: each cell receives its pmf's share of the points, and the remainders
        // of the points that land in one cell cover the unit square evenly (each quadrant its
        // quarter), so a finer table fed with them stays stratified.
        let n = 64;
        let mut quadrants = vec![[0usize; 4]; 12];
        let mut counts = vec![0usize; 12];
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (col, row, rest) = d.pick(u);
                let s = d.sample(u);
                assert_eq!((col, row), (s.col, s.row));
                assert!((0.0..1.0).contains(&rest.x) && (0.0..1.0).contains(&rest.y));
                let q = usize::from(rest.x >= 0.5) + 2 * usize::from(rest.y >= 0.5);
                quadrants[row * 4 + col][q] += 1;
                counts[row * 4 + col] += 1;
            }
        }
        for c in 0..12 {
            let expected = d.pmf(c % 4, c / 4) * (n * n) as f32;
            assert!(
                (counts[c] as f32 - expected).abs() <= 2.0 * n as f32,
                "{c}: {counts:?}"
            );
            for &q in &quadrants[c] {
                let quarter = counts[c] as f32 / 4.0;
                assert!(
                    (q as f32 - quarter).abs() <= 0.1 * quarter + n as f32 / 4.0,
                    "{c}: {quadrants:?}"
                );
            }
        }
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

    #[test]
    fn the_guided_search_finds_what_a_full_search_finds() {
        let (w, h) = (1000, 3);
        // Uneven weights with zero runs, so guides bracket ranges of very different lengths.
        let weights: Vec<f32> = (0..w * h)
            .map(|i| {
                let x = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
                if x.is_multiple_of(7) {
                    0.0
                } else {
                    (x % 1000) as f32 * if i % 97 == 0 { 1e3 } else { 1.0 }
                }
            })
            .collect();
        let d = Distribution2D::new(w, h, weights).expect("positive");
        for k in 0..20_000 {
            let u = Vec2::new(
                (k as f32 * 0.618_034).fract(),
                (k as f32 * 0.414_214).fract(),
            );
            let s = d.sample(u);
            let cdf = &d.cdf[s.row * (w + 1)..(s.row + 1) * (w + 1)];
            let full = cdf[1..].partition_point(|&c| c <= u.x).min(w - 1);
            assert_eq!(s.col, full, "u = {u}");
            assert!(s.pdf_uv > 0.0);
        }
    }
}
