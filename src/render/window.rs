//! Stage 4, render: which pixels a render computes. [`PixelWindow`] is a rectangle of the
//! image; [`split`] cuts the image into the `N` windows of `scnc render --tile K/N`.
//!
//! Syntax: no `.scn` syntax; the command line's `--tile K/N` (0-based `K`). Tiles are bands
//! of whole rows (an OpenEXR data window must be one rectangle). [`split`] cuts bands of equal
//! height, `⌊K·H/N⌋ .. ⌊(K+1)·H/N⌋`; [`split_by_cost`], which `--tile` uses, cuts them at equal
//! cumulative cost from per-row costs (`render::balance`, a pure function of the scene and
//! settings, so every machine cuts the same bands). Rendering a window gives each of its pixels exactly the bits of the full render (a pixel's
//! samples depend only on the pixel and the settings), so the bands can be merged back
//! (`scnc merge`) into the image one machine would have made. How evenly bands share the cost
//! is measured in docs/cluster.md.

/// A rectangle of pixels: columns `x0..x1`, rows `y0..y1` (half-open, row 0 at the top).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelWindow {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl PixelWindow {
    /// The whole `width`×`height` image.
    pub fn full(width: u32, height: u32) -> PixelWindow {
        PixelWindow {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Columns in the window.
    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    /// Rows in the window.
    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    /// The window grown by `margin` pixels on every side, clipped to a `width`×`height` image.
    pub fn grow(&self, margin: u32, width: u32, height: u32) -> PixelWindow {
        PixelWindow {
            x0: self.x0.saturating_sub(margin),
            y0: self.y0.saturating_sub(margin),
            x1: self.x1.saturating_add(margin),
            y1: self.y1.saturating_add(margin),
        }
        .clip(width, height)
    }

    /// The window clipped to a `width`×`height` image.
    pub fn clip(&self, width: u32, height: u32) -> PixelWindow {
        let (x1, y1) = (self.x1.min(width), self.y1.min(height));
        PixelWindow {
            x0: self.x0.min(x1),
            y0: self.y0.min(y1),
            x1,
            y1,
        }
    }
}

/// Tile `k` of `n` of a `width`×`height` image: a band of whole rows (see the module doc).
/// `None` when `k >= n` or there are more tiles than rows (some bands would be empty).
pub fn split(k: u32, n: u32, width: u32, height: u32) -> Option<PixelWindow> {
    if k >= n || n > height || width == 0 {
        return None;
    }
    let row = |i: u32| (u64::from(i) * u64::from(height) / u64::from(n)) as u32;
    let (y0, y1) = (row(k), row(k + 1));
    (y1 > y0).then_some(PixelWindow {
        x0: 0,
        y0,
        x1: width,
        y1,
    })
}

/// Tile `k` of `n` of an image `width` wide whose rows cost `row_costs` (one per row): band
/// `i` starts at the last row where the rows above cost at most `i/n` of the total, pushed
/// down where needed so that every band keeps at least one row. `None` when `k >= n` or there
/// are more tiles than rows. With equal costs these are [`split`]'s bands.
pub fn split_by_cost(k: u32, n: u32, width: u32, row_costs: &[u64]) -> Option<PixelWindow> {
    let height = u32::try_from(row_costs.len()).ok()?;
    if k >= n || n > height || width == 0 {
        return None;
    }
    let mut prefix = Vec::with_capacity(row_costs.len() + 1);
    let mut total = 0u128;
    prefix.push(0u128);
    for &c in row_costs {
        total += u128::from(c);
        prefix.push(total);
    }
    // Exact integers: `p ≤ total·i/n` as `p·n ≤ total·i`.
    let wanted = |i: u32| {
        let fits = prefix.partition_point(|&p| p * u128::from(n) <= total * u128::from(i));
        fits.saturating_sub(1) as u32
    };
    let (mut y0, mut y1) = (0u32, 0u32);
    for i in 1..=k + 1 {
        y0 = y1;
        // Starts increase by at least one and leave a row for each later band.
        y1 = if i == n {
            height
        } else {
            wanted(i).max(y0 + 1).min(height - (n - i))
        };
    }
    (y1 > y0).then_some(PixelWindow {
        x0: 0,
        y0,
        x1: width,
        y1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bands_by_cost(n: u32, w: u32, costs: &[u64]) -> Vec<PixelWindow> {
        (0..n)
            .map(|k| split_by_cost(k, n, w, costs).expect("band"))
            .collect()
    }

    #[test]
    fn cost_bands_cover_the_image_once_and_are_never_empty() {
        let shapes: Vec<Vec<u64>> = vec![
            vec![1; 13],
            (0..100).map(|i| if i > 60 { 50 } else { 1 }).collect(),
            (0..40).map(|i| (i * i) as u64 + 1).collect(),
            {
                let mut v = vec![1; 30];
                v[29] = 1_000_000;
                v
            },
            {
                let mut v = vec![1; 30];
                v[0] = 1_000_000;
                v
            },
        ];
        for costs in &shapes {
            let h = costs.len() as u32;
            for n in 1..=h {
                let bands = bands_by_cost(n, 5, costs);
                assert_eq!(bands[0].y0, 0);
                assert_eq!(bands[n as usize - 1].y1, h);
                for pair in bands.windows(2) {
                    assert_eq!(pair[0].y1, pair[1].y0, "h={h} n={n}");
                }
                assert!(bands.iter().all(|b| b.height() >= 1 && b.width() == 5));
            }
            assert_eq!(split_by_cost(0, h + 1, 5, costs), None);
        }
    }

    #[test]
    fn equal_costs_give_the_equal_bands() {
        for h in [1u32, 7, 64, 100] {
            let costs = vec![3u64; h as usize];
            for n in 1..=h.min(20) {
                for k in 0..n {
                    assert_eq!(
                        split_by_cost(k, n, 9, &costs),
                        split(k, n, 9, h),
                        "{h} {n} {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn costly_rows_get_thinner_bands() {
        // The bottom half costs 9 times the top: the top band of 2 takes far more rows.
        let costs: Vec<u64> = (0..100).map(|i| if i < 50 { 1 } else { 9 }).collect();
        let top = split_by_cost(0, 2, 4, &costs).expect("band");
        assert_eq!(
            top.y1,
            50 + 22,
            "at most half the cost: 50 cheap rows and 22 of 9"
        );
        let bands = bands_by_cost(4, 4, &costs);
        let cost_of = |b: &PixelWindow| -> u64 { costs[b.y0 as usize..b.y1 as usize].iter().sum() };
        let most = bands.iter().map(cost_of).max().expect("bands");
        assert!(
            most <= 500 / 4 + 9,
            "every band near a quarter of 500: {most}"
        );
    }

    #[test]
    fn bands_cover_the_image_once_and_differ_by_at_most_a_row() {
        for (w, h) in [(7, 1), (5, 13), (64, 64), (3, 1000)] {
            for n in 1..=h.min(40) {
                let bands: Vec<PixelWindow> =
                    (0..n).map(|k| split(k, n, w, h).expect("band")).collect();
                assert_eq!(bands[0].y0, 0);
                assert_eq!(bands[n as usize - 1].y1, h);
                for pair in bands.windows(2) {
                    assert_eq!(pair[0].y1, pair[1].y0, "{w}x{h} n={n}");
                }
                let (lo, hi) = bands.iter().fold((u32::MAX, 0), |(lo, hi), b| {
                    (lo.min(b.height()), hi.max(b.height()))
                });
                assert!(hi - lo <= 1, "{w}x{h} n={n}: {lo}..{hi}");
                assert!(bands.iter().all(|b| b.x0 == 0 && b.x1 == w));
            }
        }
    }

    #[test]
    fn grown_windows_stay_in_the_image() {
        let w = PixelWindow {
            x0: 0,
            y0: 5,
            x1: 10,
            y1: 9,
        };
        assert_eq!(
            w.grow(1, 10, 20),
            PixelWindow {
                x0: 0,
                y0: 4,
                x1: 10,
                y1: 10
            }
        );
        assert_eq!(
            w.grow(3, 12, 10),
            PixelWindow {
                x0: 0,
                y0: 2,
                x1: 12,
                y1: 10
            }
        );
    }

    #[test]
    fn out_of_range_and_empty_bands_are_none() {
        assert_eq!(split(3, 3, 10, 10), None);
        assert_eq!(split(0, 0, 10, 10), None);
        assert_eq!(split(0, 5, 10, 2), None);
        assert_eq!(
            split(1, 5, 10, 4),
            None,
            "every tile of 5 over 4 rows is refused"
        );
        assert!(split(4, 4, 10, 4).is_none() && split(3, 4, 10, 4).is_some());
    }
}
