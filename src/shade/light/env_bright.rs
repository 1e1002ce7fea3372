//! Shading layer: the environment map's few brightest texels (a small sun), sampled on their own.
//!
//! A sky whose power sits largely in a small region (env-bench's sun: a disk of 67 texels of
//! 1024 × 512 holding 59% of the power) is badly served by one light sample per shading point
//! that picks between the sun and the rest by a random number: over a pixel's N samples the
//! number that land on the sun is `p·N ± 1`, a relative error of about `1 / (p·N)` in the
//! sun's share, and the sky behind gets only the rest. So the texels at least
//! [`MIN_CONTRAST`] times as bright as the map's mean, when together they hold at least
//! [`MIN_SHARE`] of the power and fit in a box of at most [`MAX_BOX_TEXELS`] texels (one
//! compact region: a sun), are taken out of the sky's tables and become a strategy of their
//! own: the integrator draws one sample of them *and* one of the remaining sky per environment
//! pick, each weighted against the other and the BRDF by multiple importance sampling
//! (`render::mis`). Within the box a texel is picked by its weight (a [`Distribution2D`] over
//! the box, zero outside the set), then a point uniform in the texel.

use glam::Vec2;

use super::env_sampler::TexelSample;
use crate::shade::distribution::clean_weight;
use crate::shade::distribution2d::Distribution2D;

/// A texel joins the set if its weight (luminance × sin θ) is at least this many times the
/// map's mean weight.
pub const MIN_CONTRAST: f64 = 16.0;
/// The set is sampled apart only if it holds at least this share of the map's power.
pub const MIN_SHARE: f64 = 0.25;
/// … and only if its bounding box has at most this many texels.
pub const MAX_BOX_TEXELS: usize = 4096;

/// The bright texels of a map: their bounding box and the table over it.
#[derive(Debug, Clone)]
pub struct BrightTexels {
    width: usize,
    height: usize,
    col0: usize,
    row0: usize,
    cols: usize,
    rows: usize,
    table: Distribution2D,
    share: f32,
}

impl BrightTexels {
    /// The bright set of a `width × height` map of texel `weights` (luminance × sin θ,
    /// row-major), or `None` when there is no such set (see the module doc).
    pub fn find(width: usize, height: usize, weights: &[f32]) -> Option<BrightTexels> {
        if width == 0 || weights.len() != width.checked_mul(height)? {
            return None;
        }
        let total: f64 = weights.iter().map(|&w| clean_weight(w)).sum();
        if total <= 0.0 {
            return None;
        }
        let threshold = MIN_CONTRAST * total / weights.len() as f64;
        let bright = |w: f32| clean_weight(w) >= threshold && clean_weight(w) > 0.0;
        let (mut c0, mut r0, mut c1, mut r1) = (usize::MAX, usize::MAX, 0, 0);
        let mut sum = 0.0f64;
        for (i, &w) in weights.iter().enumerate() {
            if bright(w) {
                let (c, r) = (i % width, i / width);
                (c0, r0, c1, r1) = (c0.min(c), r0.min(r), c1.max(c), r1.max(r));
                sum += clean_weight(w);
            }
        }
        if sum < MIN_SHARE * total {
            return None;
        }
        let (cols, rows) = (c1 + 1 - c0, r1 + 1 - r0);
        if cols * rows > MAX_BOX_TEXELS {
            return None;
        }
        let mut box_weights = Vec::with_capacity(cols * rows);
        for r in r0..=r1 {
            let line = &weights[r * width + c0..=r * width + c1];
            box_weights.extend(line.iter().map(|&w| if bright(w) { w } else { 0.0 }));
        }
        Some(BrightTexels {
            width,
            height,
            col0: c0,
            row0: r0,
            cols,
            rows,
            table: Distribution2D::new(cols, rows, box_weights)?,
            share: (sum / total) as f32,
        })
    }

    /// The set's bounding box in texels: first column, first row, columns, rows.
    pub fn texel_box(&self) -> (usize, usize, usize, usize) {
        (self.col0, self.row0, self.cols, self.rows)
    }

    /// The share of the map's power the set holds.
    pub fn share(&self) -> f32 {
        self.share
    }

    /// Whether texel (`col`, `row`) is in the set (its weight is then left out of the sky's
    /// tables).
    pub fn contains(&self, col: usize, row: usize) -> bool {
        self.pdf_uv(col, row) > 0.0
    }

    /// A texel of the set by its weight and a point uniform in it.
    pub fn sample(&self, u: Vec2) -> Option<TexelSample> {
        let s = self.table.sample(u);
        let uv = Vec2::new(
            (self.col0 as f32 + s.uv.x * self.cols as f32) / self.width as f32,
            (self.row0 as f32 + s.uv.y * self.rows as f32) / self.height as f32,
        );
        Some(TexelSample {
            uv: uv.min(Vec2::splat(1.0 - f32::EPSILON / 2.0)),
            col: self.col0 + s.col,
            row: self.row0 + s.row,
            pdf_uv: self.map_density(s.pdf_uv),
        })
    }

    /// The density over the map's unit square with which [`BrightTexels::sample`] draws texel
    /// (`col`, `row`): 0 outside the set.
    #[inline]
    pub fn pdf_uv(&self, col: usize, row: usize) -> f32 {
        let (Some(c), Some(r)) = (col.checked_sub(self.col0), row.checked_sub(self.row0)) else {
            return 0.0;
        };
        if c >= self.cols || r >= self.rows {
            return 0.0;
        }
        self.map_density(self.table.pdf_uv(c, r))
    }

    /// A density over the box's unit square as one over the map's.
    fn map_density(&self, pdf_box: f32) -> f32 {
        pdf_box * (self.width * self.height) as f32 / (self.cols * self.rows) as f32
    }

    /// Heap memory.
    pub fn bytes(&self) -> usize {
        self.table.bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_sun_is_found_and_sampled_inside_its_texels() {
        let (w, h) = (64, 32);
        let mut weights = vec![1.0f32; w * h];
        let sun = [(20, 10), (21, 10), (20, 11)];
        for &(c, r) in &sun {
            weights[r * w + c] = 1000.0;
        }
        let b = BrightTexels::find(w, h, &weights).expect("a sun");
        assert!(sun.iter().all(|&(c, r)| b.contains(c, r)));
        assert!(!b.contains(21, 11) && !b.contains(0, 0) && !b.contains(22, 10));
        assert!((b.share() - 3000.0 / (3000.0 + 2045.0)).abs() < 1e-4);
        let mut seen = [0usize; 3];
        for k in 0..300 {
            let u = Vec2::new((k as f32 + 0.5) / 300.0, ((k * 37) % 300) as f32 / 300.0);
            let s = b.sample(u).expect("sample");
            let i = sun
                .iter()
                .position(|&t| t == (s.col, s.row))
                .expect("in the sun");
            seen[i] += 1;
            assert_eq!((s.uv.x * w as f32) as usize, s.col);
            assert_eq!((s.uv.y * h as f32) as usize, s.row);
            assert_eq!(s.pdf_uv, b.pdf_uv(s.col, s.row));
            assert!((s.pdf_uv - (w * h) as f32 / 3.0).abs() < 1.0);
        }
        assert!(seen.iter().all(|&n| n > 80), "{seen:?}");
    }

    #[test]
    fn a_map_without_a_dominant_region_has_none() {
        let (w, h) = (16, 8);
        let mut weights = vec![1.0f32; w * h];
        weights[5] = 20.0; // bright, but 20 / 147 of the power: below the share
        assert!(BrightTexels::find(w, h, &weights).is_none());
        weights[5] = 200.0;
        weights[120] = 200.0; // two suns far apart: a box too large for a bigger map
        assert!(BrightTexels::find(w, h, &weights).is_some());
        assert!(BrightTexels::find(w, h, &vec![0.0; w * h]).is_none());
    }
}
