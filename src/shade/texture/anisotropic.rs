//! Shading layer: anisotropic filtering over the mip pyramid, for `filter anisotropic` (the
//! default): where the pixel's footprint ([`Footprint`]) is a long thin ellipse (a surface seen
//! at a grazing angle), one isotropic mip level would blur across its thin axis too.
//!
//! Two methods, measured against each other in `docs/textures.md`:
//! - [`ewa`]: Heckbert's elliptically weighted average (1989) as pbrt-v3's `MIPMap::EWA` does
//!   it: the ellipse's eccentricity is capped at [`MAX_ANISOTROPY`], the level is chosen from
//!   its minor axis, and every texel inside the ellipse in the two levels around it is weighted
//!   by a truncated Gaussian of its elliptical radius;
//! - [`multi_tap`]: what GPUs do: `n = ⌈major/minor⌉` (at most [`MAX_TAPS`]) trilinear
//!   lookups spaced along the major axis, at the level of `major/n`.
//!
//! [`lookup`] is the one `filter anisotropic` uses (multi-tap, chosen by measurement). A
//! footprint within [`ISOTROPIC_RATIO`] of a circle takes the plain trilinear path (one lookup).

use std::sync::OnceLock;

use glam::{Vec2, Vec4};

use super::footprint::Footprint;
use super::image::{ImageData, MipLevel};
use crate::ir::WrapMode;

/// Most trilinear taps [`multi_tap`] takes along the major axis (GPUs use 16).
pub const MAX_TAPS: u32 = 16;

/// Largest ratio of major to minor axis [`ewa`] filters; longer ellipses are widened (pbrt-v3's
/// default `maxanisotropy`).
pub const MAX_ANISOTROPY: f32 = 8.0;

/// Footprints whose axes differ by less than this ratio are filtered isotropically.
pub const ISOTROPIC_RATIO: f32 = 1.5;

/// How often the anisotropic path ran, for `--stats`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FilterStats {
    /// Lookups whose footprint was anisotropic enough to take several taps.
    pub anisotropic: u64,
    /// Taps (trilinear lookups, or texels for EWA) those lookups took in all.
    pub taps: u64,
}

impl FilterStats {
    /// Adds another tile's counts.
    pub fn add(&mut self, o: &FilterStats) {
        self.anisotropic += o.anisotropic;
        self.taps += o.taps;
    }

    /// The mean taps per anisotropic lookup (0 when there were none).
    pub fn mean_taps(&self) -> f64 {
        if self.anisotropic == 0 {
            0.0
        } else {
            self.taps as f64 / self.anisotropic as f64
        }
    }
}

/// `filter anisotropic`: [`multi_tap`].
pub fn lookup(
    img: &ImageData,
    uv: Vec2,
    wrap: WrapMode,
    fp: Footprint,
    stats: &mut FilterStats,
) -> Vec4 {
    multi_tap(img, uv, wrap, fp, stats)
}

/// The axes (UV units) and their lengths in level-0 texels, longest first.
fn ordered_axes(img: &ImageData, fp: Footprint) -> (Vec2, Vec2, f32, f32) {
    let (a, b) = fp.in_texels(img.size());
    let (la, lb) = (a.length(), b.length());
    if la >= lb {
        (fp.major, fp.minor, la, lb)
    } else {
        (fp.minor, fp.major, lb, la)
    }
}

/// Up to [`MAX_TAPS`] trilinear lookups spread evenly along the major axis, at the mip level of
/// the spacing between them (or of the minor axis, if longer).
pub fn multi_tap(
    img: &ImageData,
    uv: Vec2,
    wrap: WrapMode,
    fp: Footprint,
    stats: &mut FilterStats,
) -> Vec4 {
    let (major, _, la, lb) = ordered_axes(img, fp);
    if !(la.is_finite() && la > 0.0 && lb.is_finite()) || la < lb * ISOTROPIC_RATIO {
        return img.trilinear(uv, wrap, la.log2());
    }
    let n = (la / lb).ceil().clamp(1.0, MAX_TAPS as f32);
    let lod = (la / n).max(lb).log2();
    let taps = n as u32;
    stats.anisotropic += 1;
    stats.taps += u64::from(taps);
    let tap = |i: u32| img.trilinear(uv + major * ((i as f32 + 0.5) / n - 0.5), wrap, lod);
    // Deviations from the first tap are averaged, so a flat image returns its texel exactly.
    let first = tap(0);
    let mut deviation = Vec4::ZERO;
    for i in 1..taps {
        deviation += tap(i) - first;
    }
    first + deviation / n
}

/// Heckbert's EWA over the two mip levels around the (eccentricity-capped) minor axis's level.
pub fn ewa(
    img: &ImageData,
    uv: Vec2,
    wrap: WrapMode,
    fp: Footprint,
    stats: &mut FilterStats,
) -> Vec4 {
    let (major, mut minor, la, mut lb) = ordered_axes(img, fp);
    if !(la.is_finite() && la > 0.0 && lb.is_finite()) || la < lb * ISOTROPIC_RATIO {
        return img.trilinear(uv, wrap, la.log2());
    }
    if lb * MAX_ANISOTROPY < la {
        // A vanishing minor axis has no direction of its own: widen across the major one.
        let base = if lb > la * 1e-4 { minor } else { major.perp() };
        let base_texels = (base * img.size()).length();
        if !(base_texels > 0.0 && base_texels.is_finite()) {
            return img.trilinear(uv, wrap, la.log2());
        }
        lb = la / MAX_ANISOTROPY;
        minor = base * (lb / base_texels);
    }
    let top = (img.levels.len() - 1) as f32;
    let lod = lb.log2().clamp(0.0, top);
    let l0 = lod.floor();
    stats.anisotropic += 1;
    let at = |l: f32, stats: &mut FilterStats| match img.levels.get(l as usize) {
        Some(level) => ewa_level(level, uv, wrap, [major, minor], stats),
        None => img.levels[top as usize].texels[0],
    };
    let a = at(l0, stats);
    let f = lod - l0;
    if f == 0.0 {
        return a;
    }
    a + (at(l0 + 1.0, stats) - a) * f
}

/// Entries of the Gaussian weight table, indexed by the squared elliptical radius.
const WEIGHTS: usize = 128;

/// `exp(−2r²) − exp(−2)` for r² in [0, 1] (pbrt-v3's table).
fn weights() -> &'static [f32; WEIGHTS] {
    static TABLE: OnceLock<[f32; WEIGHTS]> = OnceLock::new();
    TABLE.get_or_init(|| {
        std::array::from_fn(|i| {
            let r2 = i as f32 / (WEIGHTS - 1) as f32;
            (-2.0 * r2).exp() - (-2.0f32).exp()
        })
    })
}

/// The EWA sum over one level: every texel centre inside the ellipse with conjugate axes `axes`
/// (UV units; one texel added to each for reconstruction).
fn ewa_level(
    level: &MipLevel,
    uv: Vec2,
    wrap: WrapMode,
    axes: [Vec2; 2],
    stats: &mut FilterStats,
) -> Vec4 {
    let size = Vec2::new(level.width as f32, -(level.height as f32));
    let c = level.coords(uv) - Vec2::splat(0.5);
    let [d0, d1] = axes.map(|a| a * size);
    let a = d0.y * d0.y + d1.y * d1.y + 1.0;
    let b = -2.0 * (d0.x * d0.y + d1.x * d1.y);
    let cc = d0.x * d0.x + d1.x * d1.x + 1.0;
    let inv_f = 1.0 / (a * cc - b * b * 0.25);
    let (a, b, cc) = (a * inv_f, b * inv_f, cc * inv_f);
    let det = 4.0 * a * cc - b * b;
    let (u_half, v_half) = (2.0 * (det * cc).sqrt() / det, 2.0 * (det * a).sqrt() / det);
    if !(c.is_finite() && u_half.is_finite() && v_half.is_finite()) {
        return level.bilinear(uv, wrap);
    }
    // The bounds cannot be large: the eccentricity is capped and the level chosen so that the
    // minor axis spans about a texel; the clamp only guards against float surprises.
    let (u_half, v_half) = (u_half.min(64.0), v_half.min(64.0));
    let (s0, s1) = ((c.x - u_half).ceil() as i64, (c.x + u_half).floor() as i64);
    let (t0, t1) = ((c.y - v_half).ceil() as i64, (c.y + v_half).floor() as i64);
    let table = weights();
    // Deviations from one texel are averaged, so a flat image returns its texel exactly.
    let base = level.texel(c.x.round() as i64, c.y.round() as i64, wrap);
    let (mut sum, mut total) = (Vec4::ZERO, 0.0);
    for t in t0..=t1 {
        let dt = t as f32 - c.y;
        for s in s0..=s1 {
            let ds = s as f32 - c.x;
            let r2 = a * ds * ds + b * ds * dt + cc * dt * dt;
            if r2 < 1.0 {
                let w = table[((r2 * WEIGHTS as f32) as usize).min(WEIGHTS - 1)];
                sum += (level.texel(s, t, wrap) - base) * w;
                total += w;
                stats.taps += 1;
            }
        }
    }
    if total > 0.0 {
        base + sum / total
    } else {
        level.bilinear(uv, wrap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: u32, h: u32) -> ImageData {
        ImageData::new(
            w,
            h,
            vec![Vec4::new(0.25, 0.5, 0.75, 1.0); (w * h) as usize],
            true,
        )
    }

    fn stripes(w: u32) -> ImageData {
        let texels = (0..w * w)
            .map(|i| Vec4::splat(((i % w) % 2) as f32))
            .collect();
        ImageData::new(w, w, texels, true)
    }

    #[test]
    fn a_flat_image_is_flat_under_every_method_and_footprint() {
        let img = flat(37, 20);
        let mut stats = FilterStats::default();
        for fp in [
            Footprint::default(),
            Footprint::isotropic(0.1),
            Footprint {
                major: Vec2::new(0.9, 0.3),
                minor: Vec2::new(-0.001, 0.003),
            },
        ] {
            for uv in [Vec2::new(0.3, 0.7), Vec2::new(-5.2, 9.9)] {
                for wrap in [WrapMode::Repeat, WrapMode::Clamp, WrapMode::Mirror] {
                    let want = img.levels[0].texels[0];
                    for got in [
                        multi_tap(&img, uv, wrap, fp, &mut stats),
                        ewa(&img, uv, wrap, fp, &mut stats),
                    ] {
                        assert_eq!(got, want, "{fp:?}");
                    }
                }
            }
        }
        assert!(stats.anisotropic > 0 && stats.taps > stats.anisotropic);
    }

    #[test]
    fn a_footprint_along_fine_stripes_averages_them_but_one_across_keeps_them() {
        // Columns alternate 0, 1: a footprint 4 texels long in v and half a texel wide in u
        // stays sharp in u, which isotropic trilinear at the long axis's level cannot.
        let img = stripes(64);
        let texel = 1.0 / 64.0;
        let uv = Vec2::new(10.5 * texel, 0.5);
        let along_v = Footprint {
            major: Vec2::new(0.0, 4.0 * texel),
            minor: Vec2::new(0.5 * texel, 0.0),
        };
        let mut stats = FilterStats::default();
        let iso = img.trilinear(uv, WrapMode::Repeat, 2.0).x;
        assert!(
            (iso - 0.5).abs() < 0.05,
            "isotropic blurs the stripes: {iso}"
        );
        for got in [
            multi_tap(&img, uv, WrapMode::Repeat, along_v, &mut stats).x,
            ewa(&img, uv, WrapMode::Repeat, along_v, &mut stats).x,
        ] {
            assert!((got - 0.0).abs() < 0.35, "keeps the column's value: {got}");
        }
        assert_eq!(stats.anisotropic, 2);
        let across = Footprint {
            major: Vec2::new(4.0 * texel, 0.0),
            minor: Vec2::new(0.0, 0.5 * texel),
        };
        for got in [
            multi_tap(&img, uv, WrapMode::Repeat, across, &mut stats).x,
            ewa(&img, uv, WrapMode::Repeat, across, &mut stats).x,
        ] {
            assert!(
                (got - 0.5).abs() < 0.1,
                "averages across the stripes: {got}"
            );
        }
    }

    #[test]
    fn taps_are_capped_and_degenerate_footprints_stay_finite() {
        let img = stripes(16);
        let mut stats = FilterStats::default();
        let needle = Footprint {
            major: Vec2::new(1000.0, 0.0),
            minor: Vec2::new(0.0, 1e-9),
        };
        let v = multi_tap(&img, Vec2::splat(0.3), WrapMode::Repeat, needle, &mut stats);
        assert!(v.is_finite());
        assert_eq!(stats.taps, u64::from(MAX_TAPS));
        for bad in [f32::NAN, f32::INFINITY, 0.0] {
            let fp = Footprint {
                major: Vec2::new(bad, 0.1),
                minor: Vec2::new(0.0, bad),
            };
            for uv in [Vec2::splat(0.2), Vec2::splat(f32::NAN), Vec2::splat(1e30)] {
                assert!(multi_tap(&img, uv, WrapMode::Mirror, fp, &mut stats).is_finite());
                assert!(ewa(&img, uv, WrapMode::Mirror, fp, &mut stats).is_finite());
            }
        }
    }
}
