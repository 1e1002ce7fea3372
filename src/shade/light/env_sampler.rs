//! Shading layer: the environment map's importance sampling, globally and towards the
//! hemisphere a surface faces.
//!
//! Sampling directions in proportion to the sky's radiance alone (texel luminance × sin θ)
//! wastes, at a surface, every sample below its horizon: on a sphere's side turned from a small
//! bright sun, more than half of them. Weighting by the cosine as well would need one table per
//! normal. So the map is cut into a grid of [`CELLS_X`] × [`CELLS_Y`] cells, each with its own
//! table over its texels (luminance × sin θ), and the normals into [`NORMAL_BINS`]² bins of an
//! octahedral map; per bin, the cells are weighted by their power times a bound on the cosine
//! between any normal of the bin and any direction of the cell (the largest over a few points
//! of each, plus [`MARGIN`]). A sample picks a cell from its normal's bin,
//! then a texel inside the cell from the cell's table, then a point uniform in the texel:
//! `pdf_uv = P_bin(cell) · pdf_uv_cell / cell area`, exact to the frequency with which each
//! texel is drawn (both tables are inverted CDFs and read back from the same arrays). Without a
//! normal the cells are weighted by their power alone: the plain distribution ∝ luminance ×
//! sin θ, as before.
//!
//! The bound keeps every direction above the horizon of any normal in the bin at a positive
//! density, and the ratio of the true cosine to the weight at most about 1: no direction that
//! can light the point is left to the BRDF samples alone (multiple importance sampling would
//! still be unbiased, but those would be fireflies). The bins depend only on the normal,
//! which the light and BRDF strategies both pass, so their MIS weights agree.
//!
//! A bin's table is built the first time a sample or a density asks for it: a render that
//! leaves the sky to cosine rays (`render::mis::sky_by_cosine`) never reads one, and was
//! spending a fifth of the environment's build on all of them. Each table is a function of
//! the bin alone, so when (and on which thread) it is built does not change a bit of it.

use std::sync::OnceLock;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::shade::distribution2d::{Distribution2D, Sample2D};

/// Cells across the map (at most the map's width).
pub const CELLS_X: usize = 32;
/// Cells down the map (at most its height).
pub const CELLS_Y: usize = 16;
/// Octahedral normal bins per side.
pub const NORMAL_BINS: usize = 16;
/// Added to the largest cosine between a bin's sampled normals and a cell's corners and centre
/// (see the module doc): the cosine moves by at most the angle between neighbouring sampled
/// points, under 0.1 rad for these bin and cell sizes.
pub const MARGIN: f32 = 0.1;

/// One cell of the map: its texel range and its table.
#[derive(Debug, Clone)]
struct Cell {
    col0: usize,
    row0: usize,
    cols: usize,
    rows: usize,
    table: Option<Distribution2D>,
}

/// A drawn texel: its column and row in the whole map, and the point in the map's unit square.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelSample {
    /// The point in `[0, 1)²` of the whole map.
    pub uv: Vec2,
    /// Column in the map.
    pub col: usize,
    /// Row in the map.
    pub row: usize,
    /// Density over the map's unit square.
    pub pdf_uv: f32,
}

/// The tables: per cell, its texels; per normal bin (and one without a normal), the cells.
#[derive(Debug, Clone)]
pub struct EnvSampler {
    width: usize,
    height: usize,
    cells_x: usize,
    cells_y: usize,
    cells: Vec<Cell>,
    /// Cell of each map column and row.
    cell_of_col: Vec<u16>,
    cell_of_row: Vec<u16>,
    /// Cells by power alone, as a 2-D table over the grid of cells (row `cy`, column `cx`).
    plain: Distribution2D,
    /// Each cell's power (the weight of its table).
    power: Vec<f32>,
    /// Each cell's corners and centre as world directions.
    cell_points: Vec<[Vec3; 5]>,
    /// Cells by power × widened cosine, per octahedral bin, built on first use
    /// ([`EnvSampler::bin_table`]; `None`: no cell above its horizon).
    by_normal: Vec<OnceLock<Option<Distribution2D>>>,
}

/// The bin of unit normal `n` in the octahedral map.
pub fn normal_bin(n: Vec3) -> usize {
    let uv = octahedral(n);
    let b = NORMAL_BINS as f32;
    let x = ((uv.x * b) as usize).min(NORMAL_BINS - 1);
    let y = ((uv.y * b) as usize).min(NORMAL_BINS - 1);
    y * NORMAL_BINS + x
}

/// `n` (unit) on the octahedral map, in [0, 1]².
fn octahedral(n: Vec3) -> Vec2 {
    let n = n / (n.x.abs() + n.y.abs() + n.z.abs()).max(f32::MIN_POSITIVE);
    let p = if n.y >= 0.0 {
        Vec2::new(n.x, n.z)
    } else {
        Vec2::new(
            (1.0 - n.z.abs()) * n.x.signum(),
            (1.0 - n.x.abs()) * n.z.signum(),
        )
    };
    (p * 0.5 + 0.5).clamp(Vec2::ZERO, Vec2::ONE)
}

/// The unit normal at the centre of bin `b`.
#[cfg(test)]
fn bin_centre(b: usize) -> Vec3 {
    bin_point(b, Vec2::splat(0.5))
}

/// The unit normal at point `at` ∈ [0, 1]² of bin `b` (0: its first corner, 0.5 its centre).
fn bin_point(b: usize, at: Vec2) -> Vec3 {
    let (x, y) = (b % NORMAL_BINS, b / NORMAL_BINS);
    let p = Vec2::new(
        (x as f32 + at.x) / NORMAL_BINS as f32,
        (y as f32 + at.y) / NORMAL_BINS as f32,
    ) * 2.0
        - 1.0;
    let y_up = 1.0 - p.x.abs() - p.y.abs();
    let v = if y_up >= 0.0 {
        Vec3::new(p.x, y_up, p.y)
    } else {
        Vec3::new(
            (1.0 - p.y.abs()) * p.x.signum(),
            y_up,
            (1.0 - p.x.abs()) * p.y.signum(),
        )
    };
    v.normalize()
}

impl EnvSampler {
    /// The tables for a `width × height` map of texel `weights` (luminance × sin θ, row-major);
    /// `direction(u, v)` is the world direction of map point (u, v). `None` when nothing can be
    /// sampled.
    pub fn new(
        width: usize,
        height: usize,
        weights: &[f32],
        direction: impl Fn(f32, f32) -> Vec3 + Sync,
    ) -> Option<EnvSampler> {
        if width == 0 || height == 0 || weights.len() != width.checked_mul(height)? {
            return None;
        }
        let (cells_x, cells_y) = (CELLS_X.min(width), CELLS_Y.min(height));
        let bounds = |i: usize, n: usize, size: usize| (i * size / n, (i + 1) * size / n);
        let cells: Vec<Cell> = (0..cells_x * cells_y)
            .into_par_iter()
            .map(|c| {
                let (col0, col1) = bounds(c % cells_x, cells_x, width);
                let (row0, row1) = bounds(c / cells_x, cells_y, height);
                let (cols, rows) = (col1 - col0, row1 - row0);
                let mut w = Vec::with_capacity(cols * rows);
                for r in row0..row1 {
                    w.extend_from_slice(&weights[r * width + col0..r * width + col1]);
                }
                Cell {
                    col0,
                    row0,
                    cols,
                    rows,
                    table: Distribution2D::new(cols, rows, w),
                }
            })
            .collect();
        let power: Vec<f32> = cells
            .iter()
            .map(|c| {
                if c.table.is_none() {
                    return 0.0;
                }
                let mut sum = 0.0f64;
                for r in c.row0..c.row0 + c.rows {
                    for &w in &weights[r * width + c.col0..r * width + c.col0 + c.cols] {
                        if w.is_finite() && w > 0.0 {
                            sum += w as f64;
                        }
                    }
                }
                sum as f32
            })
            .collect();
        let plain = Distribution2D::new(cells_x, cells_y, power.clone())?;
        let cell_points: Vec<[Vec3; 5]> = cells
            .iter()
            .map(|c| {
                let at = |a: f32, b: f32| {
                    direction(
                        (c.col0 as f32 + a * c.cols as f32) / width as f32,
                        (c.row0 as f32 + b * c.rows as f32) / height as f32,
                    )
                };
                [
                    at(0.0, 0.0),
                    at(1.0, 0.0),
                    at(0.0, 1.0),
                    at(1.0, 1.0),
                    at(0.5, 0.5),
                ]
            })
            .collect();
        let lookup = |n: usize, size: usize| -> Vec<u16> {
            (0..size)
                .map(|i| ((0..n).rfind(|&c| c * size / n <= i).unwrap_or(0)) as u16)
                .collect()
        };
        Some(EnvSampler {
            width,
            height,
            cells_x,
            cells_y,
            cell_of_col: lookup(cells_x, width),
            cell_of_row: lookup(cells_y, height),
            cells,
            plain,
            power,
            cell_points,
            by_normal: (0..NORMAL_BINS * NORMAL_BINS)
                .map(|_| OnceLock::new())
                .collect(),
        })
    }

    /// The cells' table of normal bin `b`, built on first use.
    fn bin_table(&self, b: usize) -> Option<&Distribution2D> {
        self.by_normal
            .get(b)?
            .get_or_init(|| self.weigh_cells_for_bin(b))
            .as_ref()
    }

    /// The cells weighted by power × widened cosine for bin `b`: each cell's corners and
    /// centre, and the bin's corners, edge midpoints and centre; the largest cosine between
    /// them, plus [`MARGIN`] for the gaps, bounds the cosine of any normal of the bin with any
    /// direction of the cell.
    fn weigh_cells_for_bin(&self, b: usize) -> Option<Distribution2D> {
        let spots = [0.0, 0.5, 1.0];
        let normals: Vec<Vec3> = spots
            .iter()
            .flat_map(|&x| spots.iter().map(move |&y| bin_point(b, Vec2::new(x, y))))
            .collect();
        let w: Vec<f32> = self
            .power
            .iter()
            .zip(&self.cell_points)
            .map(|(&p, points)| {
                // Finite cosines: a plain comparison gives `f32::max`'s result without its
                // NaN handling (this loop was most of the tables' time).
                let most = normals
                    .iter()
                    .flat_map(|n| points.iter().map(move |d| n.dot(*d)))
                    .fold(f32::NEG_INFINITY, |m, c| if c > m { c } else { m });
                p * (most + MARGIN).max(0.0)
            })
            .collect();
        Distribution2D::new(self.cells_x, self.cells_y, w)
    }

    /// How many of the [`NORMAL_BINS`]² normal bins' tables have been built so far.
    pub fn normal_bins_built(&self) -> usize {
        self.by_normal.iter().filter(|b| b.get().is_some()).count()
    }

    fn cells_for(&self, normal: Option<Vec3>) -> Option<&Distribution2D> {
        match normal {
            None => Some(&self.plain),
            Some(n) => self.bin_table(normal_bin(n)),
        }
    }

    /// A texel and a point in it for `u` ∈ [0, 1)²: the cells' table (for a surface facing
    /// `normal`, or by power alone) picks a row of cells with `u.y` and a cell in it with `u.x`,
    /// and their remainders pick the texel's row and column inside the cell.
    ///
    /// Both coordinates reach the cells, so a pixel's stratified points stay stratified over
    /// the sky in two dimensions (a cell picked by `u.y` alone along a list of the cells
    /// stratified only one: sky samples measured 2.5× the variance of the cosine lobe's on
    /// env-bench's open ground, docs/speed.md). `u.x` grows with the sample's index in the
    /// pixel's set, as do the sub-pixel positions; each stream's own index permutation
    /// (`render::rng`) keeps the two from pairing.
    pub fn sample(&self, u: Vec2, normal: Option<Vec3>) -> Option<TexelSample> {
        let cells = self.cells_for(normal)?;
        let (cx, cy, rest) = cells.pick(u);
        let cell = &self.cells[cy * self.cells_x + cx];
        let s: Sample2D = cell.table.as_ref()?.sample(rest);
        let uv = Vec2::new(
            (cell.col0 as f32 + s.uv.x * cell.cols as f32) / self.width as f32,
            (cell.row0 as f32 + s.uv.y * cell.rows as f32) / self.height as f32,
        );
        Some(TexelSample {
            uv: uv.min(Vec2::splat(1.0 - f32::EPSILON / 2.0)),
            col: cell.col0 + s.col,
            row: cell.row0 + s.row,
            pdf_uv: self.cell_density(cells.pmf(cx, cy), cell, s.pdf_uv),
        })
    }

    /// The density over the map's unit square with which [`EnvSampler::sample`] draws texel
    /// (`col`, `row`).
    pub fn pdf_uv(&self, col: usize, row: usize, normal: Option<Vec3>) -> f32 {
        let (Some(&cx), Some(&cy)) = (self.cell_of_col.get(col), self.cell_of_row.get(row)) else {
            return 0.0;
        };
        let (cx, cy) = (cx as usize, cy as usize);
        let c = cy * self.cells_x + cx;
        let (Some(cells), Some(cell)) = (self.cells_for(normal), self.cells.get(c)) else {
            return 0.0;
        };
        let Some(table) = &cell.table else {
            return 0.0;
        };
        let inside = table.pdf_uv(col - cell.col0, row - cell.row0);
        self.cell_density(cells.pmf(cx, cy), cell, inside)
    }

    /// A cell picked with probability `pmf`, a density `pdf_cell` over the cell's unit square:
    /// the density over the map's.
    fn cell_density(&self, pmf: f32, cell: &Cell, pdf_cell: f32) -> f32 {
        pmf * pdf_cell * (self.width * self.height) as f32 / (cell.cols * cell.rows) as f32
    }

    /// Heap memory of the tables.
    pub fn bytes(&self) -> usize {
        let cells: usize = self
            .cells
            .iter()
            .map(|c| std::mem::size_of::<Cell>() + c.table.as_ref().map_or(0, |t| t.bytes()))
            .sum();
        let bins: usize = self
            .by_normal
            .iter()
            .map(|d| d.get().and_then(Option::as_ref).map_or(0, |d| d.bytes()))
            .sum();
        let bin_inputs = std::mem::size_of_val(self.power.as_slice())
            + std::mem::size_of_val(self.cell_points.as_slice())
            + std::mem::size_of_val(self.by_normal.as_slice());
        cells
            + bins
            + bin_inputs
            + self.plain.bytes()
            + 2 * (self.cell_of_col.len() + self.cell_of_row.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_normal_falls_in_a_bin_whose_centre_is_near() {
        for i in 0..2000 {
            let t = i as f32 * 0.618_034;
            let z = 1.0 - 2.0 * ((i as f32 + 0.5) / 2000.0);
            let r = (1.0 - z * z).max(0.0).sqrt();
            let n = Vec3::new(
                r * (t * std::f32::consts::TAU).cos(),
                z,
                r * (t * std::f32::consts::TAU).sin(),
            );
            let b = normal_bin(n);
            assert!(b < NORMAL_BINS * NORMAL_BINS);
            // Within the margin's allowance for a bin's radius (about 20°, well under 28°).
            let angle = n.dot(bin_centre(b)).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(angle < 28.0, "{n}: {angle}° from its bin's centre");
        }
    }
}
