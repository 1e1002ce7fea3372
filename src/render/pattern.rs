//! Stage 4: sub-pixel sample positions (`render { samples rgss 4 }` or `samples grid 9`).
//!
//! The rotated grid generalises the classic 4-sample RGSS to N×N samples: sample (i, j) sits in
//! column `i·N + j` and row `j·N + (N − 1 − i)` of the N²×N² sub-grid (at the sub-cell centre),
//! so every row and every column of that sub-grid holds exactly one sample (N-rooks) while the
//! samples still form a regular, sheared lattice. N = 2 gives exactly (1/8, 3/8), (3/8, 7/8),
//! (5/8, 1/8), (7/8, 5/8). The grid pattern puts N×N samples at cell centres. Positions are
//! fixed: no randomness, so they are the same for every pixel and every run. Like `rng`, this is
//! the render loop's sample sequence, so it stays in `render/` (the shading layer never sees
//! pixels).

use glam::Vec2;

use crate::ir::SamplePattern;

/// Offsets in [0, 1)² within a pixel, `n × n` of them (n ≥ 1), in sample-index order.
pub fn offsets(n: u32, pattern: SamplePattern) -> Vec<Vec2> {
    let n = n.max(1);
    let mut out = Vec::with_capacity((n * n) as usize);
    for i in 0..n {
        for j in 0..n {
            out.push(match pattern {
                SamplePattern::RotatedGrid => {
                    let cells = (n * n) as f32;
                    let col = i * n + j;
                    let row = j * n + (n - 1 - i);
                    Vec2::new((col as f32 + 0.5) / cells, (row as f32 + 0.5) / cells)
                }
                SamplePattern::Grid => {
                    Vec2::new((j as f32 + 0.5) / n as f32, (i as f32 + 0.5) / n as f32)
                }
            });
        }
    }
    out
}

/// The largest pattern side: 256² = 65 536 samples per pixel (a `--spp` typo must not try to
/// allocate billions of sample positions).
pub const MAX_SIDE: u32 = 256;

/// Samples per side for a requested sample count: the smallest N with N² ≥ `spp`, at most
/// [`MAX_SIDE`].
pub fn side_for(spp: u32) -> u32 {
    let spp = spp.min(MAX_SIDE * MAX_SIDE);
    let mut n = (spp.max(1) as f64).sqrt().floor() as u32;
    while n * n < spp.max(1) {
        n += 1;
    }
    n.max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn n2_is_the_classic_rgss() {
        let p = offsets(2, SamplePattern::RotatedGrid);
        let expected = [(1, 3), (3, 7), (5, 1), (7, 5)]
            .map(|(x, y)| Vec2::new(x as f32 / 8.0, y as f32 / 8.0));
        assert_eq!(p, expected.to_vec());
    }

    #[test]
    fn rotated_grid_is_n_rooks_inside_the_pixel_and_deterministic() {
        for n in 1..=8u32 {
            let p = offsets(n, SamplePattern::RotatedGrid);
            assert_eq!(p, offsets(n, SamplePattern::RotatedGrid));
            assert_eq!(p.len() as u32, n * n);
            let cells = (n * n) as usize;
            let (mut rows, mut cols) = (vec![0; cells], vec![0; cells]);
            for s in &p {
                assert!(s.x > 0.0 && s.x < 1.0 && s.y > 0.0 && s.y < 1.0);
                cols[(s.x * cells as f32) as usize] += 1;
                rows[(s.y * cells as f32) as usize] += 1;
            }
            assert!(rows.iter().chain(&cols).all(|&c| c == 1), "n = {n}");
        }
    }

    #[test]
    fn grid_is_at_cell_centres_and_side_rounds_up() {
        let p = offsets(3, SamplePattern::Grid);
        assert!(p.contains(&Vec2::new(0.5, 0.5)) && p.contains(&Vec2::new(1.0 / 6.0, 5.0 / 6.0)));
        assert_eq!(
            [
                side_for(0),
                side_for(1),
                side_for(4),
                side_for(5),
                side_for(16),
                side_for(u32::MAX)
            ],
            [1, 1, 2, 3, 4, MAX_SIDE]
        );
    }
}
