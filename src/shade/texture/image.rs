//! Shading layer: image texture storage and lookup — texels, wrap modes, filters and the mip
//! pyramid behind `texture wood = image("wood.png") { wrap repeat|clamp|mirror  filter
//! nearest|bilinear|trilinear|anisotropic }` (decoding the file is the build's,
//! `scene::texture_load`; the anisotropic filter is `anisotropic`'s).
//!
//! Conventions (those of OpenGL and OBJ files): u runs left to right, v bottom to top, and image
//! row 0 is the top of the image, so UV (0, 0) is the bottom-left corner of the picture. Texel
//! (i, j) (column i, row j from the top) has its centre at `((i + ½)/w, 1 − (j + ½)/h)`:
//! a bilinear lookup exactly at a texel centre returns that texel.
//!
//! Wrap modes apply to integer texel indices: `repeat` takes them modulo the size, `clamp`
//! clamps them to the edge, `mirror` reflects them every other period (…, 1, 0, 0, 1, …, w−1,
//! w−1, …).
//!
//! The pyramid (built only for `filter trilinear` and `anisotropic`, see [`ImageData::new`]) halves each side
//! (rounding down, never below 1) and box-filters exactly: each texel of level k+1 averages the
//! area of level k it covers, with fractional weights when a side is odd, so non-power-of-two
//! and non-square images keep their mean at every level. `lod` is the level as a real number
//! (0 = full resolution); trilinear blends bilinear lookups in the two nearest levels.

use glam::{Vec2, Vec4};

use super::anisotropic::{self, FilterStats};
use super::footprint::Footprint;
use crate::ir::{Filter, WrapMode};

/// One level of the pyramid.
#[derive(Debug, Clone)]
pub struct MipLevel {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Linear RGBA, row 0 at the top of the image.
    pub texels: Vec<Vec4>,
}

/// A decoded image and (for mip filtering) its pyramid, shared by every texture that
/// names the same file with the same encoding.
#[derive(Debug, Clone)]
pub struct ImageData {
    /// `levels[0]` is the image itself; further levels only when mipmapped.
    pub levels: Vec<MipLevel>,
}

impl ImageData {
    /// Wraps a decoded image; builds the whole pyramid (down to 1 × 1) if `mipmaps`.
    /// `texels.len()` must be `width × height` (the decoder guarantees it).
    pub fn new(width: u32, height: u32, texels: Vec<Vec4>, mipmaps: bool) -> ImageData {
        debug_assert_eq!(texels.len(), width as usize * height as usize);
        let mut levels = vec![MipLevel {
            width,
            height,
            texels,
        }];
        if mipmaps {
            while let Some(last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
                let next = downsample(last);
                levels.push(next);
            }
        }
        ImageData { levels }
    }

    /// Width of the full-resolution image.
    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    /// Height of the full-resolution image.
    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Heap memory of all levels, bytes.
    pub fn bytes(&self) -> usize {
        self.levels
            .iter()
            .map(|l| l.texels.len() * std::mem::size_of::<Vec4>())
            .sum()
    }

    /// `(w, h)` of the full-resolution image: UV units times this are texels.
    pub fn size(&self) -> Vec2 {
        Vec2::new(self.width() as f32, self.height() as f32)
    }

    /// The filtered value at `uv` for a pixel whose footprint there is `footprint` (only the
    /// mip-filtered modes use it); anisotropic lookups are counted in `stats`.
    pub fn lookup(
        &self,
        uv: Vec2,
        wrap: WrapMode,
        filter: Filter,
        footprint: Footprint,
        stats: &mut FilterStats,
    ) -> Vec4 {
        match filter {
            Filter::Nearest => self.levels[0].nearest(uv, wrap),
            Filter::Bilinear => self.levels[0].bilinear(uv, wrap),
            Filter::Trilinear => self.trilinear(uv, wrap, self.lod(footprint)),
            Filter::Anisotropic if self.levels.len() > 1 => {
                anisotropic::lookup(self, uv, wrap, footprint, stats)
            }
            Filter::Anisotropic => self.levels[0].bilinear(uv, wrap),
        }
    }

    /// The isotropic mip level of a footprint: `log2` of its longer axis in texels (the GPU
    /// convention: level 0 when a texel spans the footprint).
    pub fn lod(&self, footprint: Footprint) -> f32 {
        let (a, b) = footprint.in_texels(self.size());
        a.length().max(b.length()).log2()
    }

    /// The filtered value at `uv` at mip level `lod` (nearest and bilinear read level 0; the
    /// mip-filtered modes are trilinear at `lod`).
    pub fn at_lod(&self, uv: Vec2, wrap: WrapMode, filter: Filter, lod: f32) -> Vec4 {
        match filter {
            Filter::Nearest => self.levels[0].nearest(uv, wrap),
            Filter::Bilinear => self.levels[0].bilinear(uv, wrap),
            Filter::Trilinear | Filter::Anisotropic => self.trilinear(uv, wrap, lod),
        }
    }

    /// Bilinear lookups in the two levels around `lod`, blended; `lod` is clamped to the
    /// pyramid (NaN, a degenerate footprint, lands on level 0).
    pub fn trilinear(&self, uv: Vec2, wrap: WrapMode, lod: f32) -> Vec4 {
        let top = (self.levels.len() - 1) as f32;
        let lod = if lod > 0.0 { lod.min(top) } else { 0.0 };
        let l0 = lod.floor();
        let f = lod - l0;
        let a = self.levels[l0 as usize].bilinear(uv, wrap);
        if f == 0.0 {
            return a;
        }
        let b = self.levels[l0 as usize + 1].bilinear(uv, wrap);
        a + (b - a) * f
    }
}

impl MipLevel {
    /// The texel at integer indices `(x, y)`, wrapped.
    pub(super) fn texel(&self, x: i64, y: i64, wrap: WrapMode) -> Vec4 {
        let x = wrap_index(x, self.width, wrap);
        let y = wrap_index(y, self.height, wrap);
        self.texels[y * self.width as usize + x]
    }

    /// Continuous texel coordinates of `uv` (texel centres at half-integers).
    pub(super) fn coords(&self, uv: Vec2) -> Vec2 {
        Vec2::new(uv.x * self.width as f32, (1.0 - uv.y) * self.height as f32)
    }

    /// The texel containing `uv`.
    pub fn nearest(&self, uv: Vec2, wrap: WrapMode) -> Vec4 {
        let c = self.coords(uv);
        self.texel(floor_index(c.x), floor_index(c.y), wrap)
    }

    /// The four texels around `uv`, blended by distance to their centres.
    pub fn bilinear(&self, uv: Vec2, wrap: WrapMode) -> Vec4 {
        let c = self.coords(uv) - Vec2::splat(0.5);
        let (x0, y0) = (floor_index(c.x), floor_index(c.y));
        let fx = if c.x.is_finite() {
            c.x - c.x.floor()
        } else {
            0.0
        };
        let fy = if c.y.is_finite() {
            c.y - c.y.floor()
        } else {
            0.0
        };
        // Wrap each of the two columns and rows once (not once per texel).
        let w = self.width as usize;
        let (xa, xb) = (
            wrap_index(x0, self.width, wrap),
            wrap_index(x0 + 1, self.width, wrap),
        );
        let (ya, yb) = (
            wrap_index(y0, self.height, wrap) * w,
            wrap_index(y0 + 1, self.height, wrap) * w,
        );
        let t = &self.texels;
        let top = t[ya + xa] + (t[ya + xb] - t[ya + xa]) * fx;
        let bottom = t[yb + xa] + (t[yb + xb] - t[yb + xa]) * fx;
        top + (bottom - top) * fy
    }
}

/// `floor(x)` as an index; NaN maps to 0 and huge values are clamped far enough from `i64`'s
/// range that `+ 1` cannot overflow (then wrapped into range).
fn floor_index(x: f32) -> i64 {
    x.floor().clamp(-1e15, 1e15) as i64
}

/// An integer texel index mapped into `0..n` by the wrap mode.
pub fn wrap_index(i: i64, n: u32, wrap: WrapMode) -> usize {
    let n = n.max(1) as i64;
    let w = match wrap {
        WrapMode::Repeat => i.rem_euclid(n),
        WrapMode::Clamp => i.clamp(0, n - 1),
        WrapMode::Mirror => {
            let m = i.rem_euclid(2 * n);
            if m >= n {
                2 * n - 1 - m
            } else {
                m
            }
        }
    };
    w as usize
}

/// Exact box filter to `max(1, w/2) × max(1, h/2)`.
fn downsample(src: &MipLevel) -> MipLevel {
    let width = (src.width / 2).max(1);
    let height = (src.height / 2).max(1);
    let wx = box_weights(src.width, width);
    let wy = box_weights(src.height, height);
    // Rows first (horizontal pass), then columns.
    let mut rows = vec![Vec4::ZERO; width as usize * src.height as usize];
    for y in 0..src.height as usize {
        let line = &src.texels[y * src.width as usize..][..src.width as usize];
        for (x, taps) in wx.iter().enumerate() {
            rows[y * width as usize + x] = weighted(taps, |i| line[i]);
        }
    }
    let mut texels = vec![Vec4::ZERO; width as usize * height as usize];
    for (y, taps) in wy.iter().enumerate() {
        for x in 0..width as usize {
            texels[y * width as usize + x] = weighted(taps, |j| rows[j * width as usize + x]);
        }
    }
    MipLevel {
        width,
        height,
        texels,
    }
}

/// `Σ wᵢ·texel(i)` for weights summing to 1, as the first texel plus the weighted deviations
/// from it, so that a flat region stays exactly flat (the weights' float sum is not exactly 1).
fn weighted(taps: &[(usize, f32)], texel: impl Fn(usize) -> Vec4) -> Vec4 {
    let Some(&(first, _)) = taps.first() else {
        return Vec4::ZERO;
    };
    let base = texel(first);
    base + taps
        .iter()
        .map(|&(i, w)| (texel(i) - base) * w)
        .sum::<Vec4>()
}

/// For each destination texel of `dst` covering `src/dst` source texels: the source texels it
/// overlaps and their normalised overlap lengths.
fn box_weights(src: u32, dst: u32) -> Vec<Vec<(usize, f32)>> {
    let scale = src as f64 / dst as f64;
    (0..dst)
        .map(|d| {
            let (lo, hi) = (d as f64 * scale, (d + 1) as f64 * scale);
            let first = lo.floor() as u32;
            let last = (hi.ceil() as u32).min(src);
            (first..last)
                .filter_map(|s| {
                    let overlap = (hi.min(s as f64 + 1.0) - lo.max(s as f64)).max(0.0);
                    (overlap > 0.0).then_some((s as usize, (overlap / scale) as f32))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 4 × 2 image whose texel (i, j) is (i, j, 10·j + i, 1).
    fn ramp(w: u32, h: u32) -> ImageData {
        let texels = (0..h)
            .flat_map(|j| {
                (0..w).map(move |i| Vec4::new(i as f32, j as f32, (10 * j + i) as f32, 1.0))
            })
            .collect();
        ImageData::new(w, h, texels, true)
    }

    /// The UV of the centre of texel (i, j).
    fn centre(i: f32, j: f32, w: f32, h: f32) -> Vec2 {
        Vec2::new((i + 0.5) / w, 1.0 - (j + 0.5) / h)
    }

    #[test]
    fn texel_centres_return_their_texel_with_every_filter() {
        let img = ramp(4, 2);
        for j in 0..2 {
            for i in 0..4 {
                let uv = centre(i as f32, j as f32, 4.0, 2.0);
                let want = Vec4::new(i as f32, j as f32, (10 * j + i) as f32, 1.0);
                for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
                    let got = img.at_lod(uv, WrapMode::Clamp, filter, 0.0);
                    assert!(
                        (got - want).abs().max_element() < 1e-5,
                        "{filter:?} {i},{j}"
                    );
                }
            }
        }
        // UV (0, 0) is the bottom-left corner: the last row, first column.
        assert_eq!(
            img.at_lod(Vec2::new(0.01, 0.01), WrapMode::Clamp, Filter::Nearest, 0.0)
                .z,
            10.0
        );
    }

    #[test]
    fn wrap_modes_at_known_texels() {
        let img = ramp(4, 2);
        let at = |i: f32, wrap| {
            img.at_lod(centre(i, 0.0, 4.0, 2.0), wrap, Filter::Nearest, 0.0)
                .x
        };
        // One texel left of the image, and five to the right.
        assert_eq!(at(-1.0, WrapMode::Repeat), 3.0);
        assert_eq!(at(-1.0, WrapMode::Clamp), 0.0);
        assert_eq!(at(-1.0, WrapMode::Mirror), 0.0);
        assert_eq!(at(5.0, WrapMode::Repeat), 1.0);
        assert_eq!(at(5.0, WrapMode::Clamp), 3.0);
        assert_eq!(at(5.0, WrapMode::Mirror), 2.0);
        assert_eq!(at(9.0, WrapMode::Mirror), 1.0);
        // Bilinear half-way between the last and the first column.
        let edge = Vec2::new(1.0, 1.0 - 0.5 / 2.0);
        assert_eq!(
            img.at_lod(edge, WrapMode::Repeat, Filter::Bilinear, 0.0).x,
            1.5
        );
        assert_eq!(
            img.at_lod(edge, WrapMode::Clamp, Filter::Bilinear, 0.0).x,
            3.0
        );
        assert_eq!(
            img.at_lod(edge, WrapMode::Mirror, Filter::Bilinear, 0.0).x,
            3.0
        );
        // Bilinear a quarter of the way from texel 1 to texel 2.
        let q = Vec2::new(2.25 / 4.0, 0.75);
        assert!((img.at_lod(q, WrapMode::Repeat, Filter::Bilinear, 0.0).x - 1.75).abs() < 1e-6);
    }

    #[test]
    fn pyramid_is_box_filtered_for_odd_and_non_square_sizes() {
        let img = ramp(5, 3);
        let sizes: Vec<(u32, u32)> = img.levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(5, 3), (2, 1), (1, 1)]);
        let mean = |l: &MipLevel| l.texels.iter().copied().sum::<Vec4>() / l.texels.len() as f32;
        for l in &img.levels {
            assert!((mean(l) - mean(&img.levels[0])).abs().max_element() < 1e-5);
        }
        // Level 1, texel 0 averages columns 0, 1 and half of 2: (0 + 1 + 1)/2.5.
        assert!((img.levels[1].texels[0].x - 0.8).abs() < 1e-6);
        let pow2 = ramp(4, 2);
        assert_eq!(pow2.levels[1].texels[0].x, 0.5);
        assert_eq!(pow2.levels.len(), 3);
        assert_eq!(
            ImageData::new(4, 2, vec![Vec4::ONE; 8], false).levels.len(),
            1
        );
        // A flat image stays exactly flat at every level, odd sides included.
        let flat = ImageData::new(37, 21, vec![Vec4::splat(0.3); 37 * 21], true);
        assert!(flat
            .levels
            .iter()
            .all(|l| l.texels.iter().all(|&t| t == Vec4::splat(0.3))));
    }

    #[test]
    fn trilinear_blends_levels_and_clamps_lod() {
        let img = ramp(4, 4);
        let uv = Vec2::new(0.3, 0.6);
        let l0 = img.at_lod(uv, WrapMode::Repeat, Filter::Bilinear, 0.0);
        let l1 = img.levels[1].bilinear(uv, WrapMode::Repeat);
        let mid = img.at_lod(uv, WrapMode::Repeat, Filter::Trilinear, 0.5);
        assert!((mid - (l0 + l1) / 2.0).abs().max_element() < 1e-5);
        // Whole levels: a texel centre of level 1 returns that texel, for every wrap mode.
        for wrap in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror] {
            let at = img.at_lod(centre(1.0, 0.0, 2.0, 2.0), wrap, Filter::Trilinear, 1.0);
            assert!((at - img.levels[1].texels[1]).abs().max_element() < 1e-5);
            // (1.5, 0.5) is level 1's texel (1, 0): the mean of level 0's 2 × 2 block there.
            assert!((at - Vec4::new(2.5, 0.5, 7.5, 1.0)).abs().max_element() < 1e-5);
        }
        let top = img.levels[2].texels[0];
        assert_eq!(
            img.at_lod(uv, WrapMode::Repeat, Filter::Trilinear, 99.0),
            top
        );
        for bad in [f32::NAN, -3.0, f32::NEG_INFINITY] {
            assert_eq!(img.at_lod(uv, WrapMode::Repeat, Filter::Trilinear, bad), l0);
        }
        for uv in [Vec2::splat(f32::NAN), Vec2::splat(1e30), Vec2::splat(-1e30)] {
            let v = img.at_lod(uv, WrapMode::Mirror, Filter::Trilinear, 1.3);
            assert!(v.is_finite());
        }
    }
}
