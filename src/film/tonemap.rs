//! Stage 5: exposure, tone mapping and the sRGB transfer curve, for 8-bit output only (the
//! float formats store linear radiance untouched).
//!
//! Syntax: `render { exposure -1  tonemap clamp | reinhard | filmic }`. Per channel:
//! `x' = tonemap(x · 2^exposure)`, then `srgb_encode(x')`, then rounded to 8 bits.
//!
//! | curve    | x = 0 | x = 1  | x → ∞ | formula                                           |
//! |----------|-------|--------|-------|---------------------------------------------------|
//! | clamp    | 0     | 1      | 1     | min(max(x, 0), 1)                                 |
//! | reinhard | 0     | 0.5    | → 1   | x / (1 + x)                                       |
//! | filmic   | 0     | 0.8038 | 1     | ACES fit (Narkowicz 2015) x(2.51x+0.03)/(x(2.43x+0.59)+0.14), clamped to [0, 1] |

use glam::Vec3;

use crate::ir::ToneMap;

/// Clamps to [0, 1].
pub fn clamp(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// Reinhard: x / (1 + x) (1 at infinity).
pub fn reinhard(x: f32) -> f32 {
    let x = x.max(0.0);
    if x.is_infinite() {
        1.0
    } else {
        x / (1.0 + x)
    }
}

/// Narkowicz's fit of the ACES filmic curve.
pub fn filmic(x: f32) -> f32 {
    let x = x.max(0.0);
    if x > 1e10 {
        return 1.0;
    }
    let (a, b, c, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
    ((x * (a * x + b)) / (x * (c * x + d) + e)).clamp(0.0, 1.0)
}

/// `curve` at `x` (0 for NaN).
pub fn apply(curve: ToneMap, x: f32) -> f32 {
    if x.is_nan() {
        return 0.0;
    }
    match curve {
        ToneMap::Clamp => clamp(x),
        ToneMap::Reinhard => reinhard(x),
        ToneMap::Filmic => filmic(x),
    }
}

/// The sRGB transfer curve (IEC 61966-2-1) for a linear value in [0, 1].
pub fn srgb_encode(linear: f32) -> f32 {
    let x = linear.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// One pixel, radiance → 8-bit sRGB.
pub fn to_srgb8(radiance: Vec3, exposure: f32, curve: ToneMap) -> [u8; 3] {
    let scale = exposure.exp2();
    radiance
        .to_array()
        .map(|c| (srgb_encode(apply(curve, c * scale)) * 255.0 + 0.5).clamp(0.0, 255.0) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    const CURVES: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Filmic];

    #[test]
    fn curves_are_monotone_and_bounded() {
        for curve in CURVES {
            let mut prev = 0.0;
            for i in 0..20_000 {
                let x = i as f32 * 0.001;
                let y = apply(curve, x);
                assert!(y >= prev && (0.0..=1.0).contains(&y), "{curve:?} at {x}");
                prev = y;
            }
        }
    }

    #[test]
    fn documented_values() {
        for curve in CURVES {
            assert_eq!(apply(curve, 0.0), 0.0);
            assert_eq!(apply(curve, -3.0), 0.0);
            assert_eq!(apply(curve, f32::NAN), 0.0);
            assert!((apply(curve, 1e12) - 1.0).abs() < 1e-6, "{curve:?}");
            assert!(
                (apply(curve, f32::INFINITY) - 1.0).abs() < 1e-6,
                "{curve:?}"
            );
        }
        assert_eq!(clamp(1.0), 1.0);
        assert_eq!(reinhard(1.0), 0.5);
        assert!((filmic(1.0) - 2.54 / 3.16).abs() < 1e-6);
        assert!((reinhard(1000.0) - 1000.0 / 1001.0).abs() < 1e-6);
    }

    #[test]
    fn srgb_known_values() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.18) - 0.461_356).abs() < 1e-4);
        assert!((srgb_encode(0.002) - 0.025_84).abs() < 1e-6);
        assert_eq!(
            to_srgb8(Vec3::new(0.0, 0.5, 1.0), 0.0, ToneMap::Clamp),
            [0, 188, 255]
        );
        // One stop of exposure doubles the radiance before the curve.
        assert_eq!(
            to_srgb8(Vec3::splat(0.25), 1.0, ToneMap::Clamp),
            to_srgb8(Vec3::splat(0.5), 0.0, ToneMap::Clamp)
        );
    }
}
