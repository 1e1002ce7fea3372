//! Stage 4, render: which pixels a render computes. [`PixelWindow`] is a rectangle of the
//! image; [`split`] cuts the image into the `N` windows of `scnc render --tile K/N`.
//!
//! Syntax: no `.scn` syntax; the command line's `--tile K/N` (0-based `K`). Tile `K` is the
//! band of whole rows `⌊K·H/N⌋ .. ⌊(K+1)·H/N⌋`: an OpenEXR data window must be one
//! rectangle, so tiles are contiguous bands, and their heights differ by at most one row.
//! Rendering a window gives each of its pixels exactly the bits of the full render (a pixel's
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

#[cfg(test)]
mod tests {
    use super::*;

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
