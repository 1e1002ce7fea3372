//! Shading layer: the environment map's texel grid in angles, for the per-sample work of
//! `env_map` without libm's trigonometry.
//!
//! A texel row spans `θ ∈ [π r / H, π (r + 1) / H)`, a column `φ ∈ [2π c / W, 2π (c + 1) / W)`
//! (`env_map`'s convention). The sines and cosines of every row and column edge are tabulated
//! once; then
//! - a point inside a texel is `θ_r + δ` with `δ` under one texel: its sine and cosine come from
//!   the edge's by the angle-addition formulas and short Taylor series of `δ` (exact to f32
//!   rounding while a texel spans at most [`MAX_STEP`] rad; coarser maps call `sin_cos`);
//! - the texel of a direction starts from a polynomial `acos` / `atan2` (error under 1e-4 rad)
//!   and is settled against the tabulated edges (`cos θ` against the rows' cosines, the sign of
//!   `sin(φ − φ_c)` against the columns'), so it is the texel whose edges bound the direction.
//!
//! Measured in docs/speed.md (env-bench: libm's `sincosf`, `acosf`, `atanf` were 5% of the
//! render).

use std::f32::consts::PI;

use glam::Vec3;

/// The largest texel span (rad) for which the series are used.
pub const MAX_STEP: f32 = 0.1;

/// Sines and cosines of the row and column edges of a `width × height` map.
#[derive(Debug, Clone)]
pub struct TexelGrid {
    width: usize,
    height: usize,
    /// `(sin θ, cos θ)` at `θ = π r / H`, `r = 0 ..= H`.
    rows: Vec<(f32, f32)>,
    /// `(sin φ, cos φ)` at `φ = 2π c / W`, `c = 0 ..= W`.
    cols: Vec<(f32, f32)>,
}

/// `(sin δ, cos δ)` for `|δ| ≤ MAX_STEP`.
#[inline]
fn small_sin_cos(d: f32) -> (f32, f32) {
    let d2 = d * d;
    let sin = d * (1.0 - d2 / 6.0 * (1.0 - d2 / 20.0));
    let cos = 1.0 - d2 / 2.0 * (1.0 - d2 / 12.0 * (1.0 - d2 / 30.0));
    (sin, cos)
}

/// `acos x` for `x ∈ [−1, 1]`, within 1e-4 rad (Abramowitz & Stegun 4.4.45).
#[inline]
fn rough_acos(x: f32) -> f32 {
    let a = x.abs();
    let p = (1.0 - a).max(0.0).sqrt()
        * (1.570_728_8 + a * (-0.212_114_4 + a * (0.074_261 - a * 0.018_729_3)));
    if x >= 0.0 {
        p
    } else {
        PI - p
    }
}

/// `atan2(y, x)` in `[0, 2π)`, within 1e-4 rad.
#[inline]
fn rough_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = (ax.min(ay), ax.max(ay));
    let t = if hi > 0.0 { lo / hi } else { 0.0 };
    let t2 = t * t;
    let mut a = t
        * (0.999_866
            + t2 * (-0.330_299_5 + t2 * (0.180_141 + t2 * (-0.085_133 + t2 * 0.020_835_1))));
    if ay > ax {
        a = PI / 2.0 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 {
        a = 2.0 * PI - a;
    }
    a
}

impl TexelGrid {
    /// The edge tables of a `width × height` map (both at least 1).
    pub fn new(width: usize, height: usize) -> TexelGrid {
        let (width, height) = (width.max(1), height.max(1));
        let at = |angle: f64| (angle.sin() as f32, angle.cos() as f32);
        TexelGrid {
            width,
            height,
            rows: (0..=height)
                .map(|r| at(std::f64::consts::PI * r as f64 / height as f64))
                .collect(),
            cols: (0..=width)
                .map(|c| at(std::f64::consts::TAU * c as f64 / width as f64))
                .collect(),
        }
    }

    /// The map-space unit direction `(sin θ cos φ, cos θ, sin θ sin φ)` of point `(fx, fy)` ∈
    /// [0, 1]² of texel (`col`, `row`).
    pub fn direction(&self, col: usize, row: usize, fx: f32, fy: f32) -> Vec3 {
        let step_theta = PI / self.height as f32;
        let step_phi = 2.0 * PI / self.width as f32;
        let (sin_theta, cos_theta) = match self.rows.get(row) {
            Some(&(s0, c0)) if step_theta <= MAX_STEP => {
                let (s, c) = small_sin_cos(fy * step_theta);
                (s0 * c + c0 * s, c0 * c - s0 * s)
            }
            _ => ((row as f32 + fy) * step_theta).sin_cos(),
        };
        let (sin_phi, cos_phi) = match self.cols.get(col) {
            Some(&(s0, c0)) if step_phi <= MAX_STEP => {
                let (s, c) = small_sin_cos(fx * step_phi);
                (s0 * c + c0 * s, c0 * c - s0 * s)
            }
            _ => ((col as f32 + fx) * step_phi).sin_cos(),
        };
        Vec3::new(sin_theta * cos_phi, cos_theta, sin_theta * sin_phi)
    }

    /// The texel (`col`, `row`) of map-space unit direction `m`, and its `sin θ`.
    pub fn texel_of(&self, m: Vec3) -> (usize, usize, f32) {
        let (w, h) = (self.width, self.height);
        let cos_theta = m.y.clamp(-1.0, 1.0);
        let guess = rough_acos(cos_theta) / PI * h as f32;
        let mut row = (guess.max(0.0) as usize).min(h - 1);
        // Row `r` holds `cos θ ∈ (cos θ_{r+1}, cos θ_r]`.
        for _ in 0..3 {
            if row > 0 && cos_theta > self.rows[row].1 {
                row -= 1;
            } else if row + 1 < h && cos_theta <= self.rows[row + 1].1 {
                row += 1;
            } else {
                break;
            }
        }
        let col = if m.x == 0.0 && m.z == 0.0 {
            0
        } else if w < 8 {
            // Columns wider than 45°: the sign test below needs narrower ones.
            let mut phi = m.z.atan2(m.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            ((phi / (2.0 * PI) * w as f32) as usize).min(w - 1)
        } else {
            let guess = rough_atan2(m.z, m.x) / (2.0 * PI) * w as f32;
            let mut col = (guess.max(0.0) as usize).min(w - 1);
            // φ ≥ φ_c where sin(φ − φ_c) ≥ 0 (the guess is within a texel of φ).
            let at_or_past = |c: usize| {
                let (s, co) = self.cols[c];
                m.z * co - m.x * s >= 0.0
            };
            for _ in 0..3 {
                if !at_or_past(col) {
                    col = (col + w - 1) % w;
                } else if at_or_past(col + 1) {
                    col = (col + 1) % w;
                } else {
                    break;
                }
            }
            col
        };
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        (col, row, sin_theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rough_inverses_are_within_a_ten_thousandth() {
        for k in 0..=20_000 {
            let x = -1.0 + 2.0 * k as f32 / 20_000.0;
            assert!((rough_acos(x) - x.acos()).abs() < 1e-4, "acos {x}");
            let a = k as f32 / 20_000.0 * 2.0 * PI;
            let (s, c) = a.sin_cos();
            let mut exact = s.atan2(c);
            if exact < 0.0 {
                exact += 2.0 * PI;
            }
            let d = (rough_atan2(s, c) - exact).abs();
            assert!(d < 1e-4 || (2.0 * PI - d) < 1e-4, "atan2 at {a}: {d}");
        }
    }

    #[test]
    fn points_of_a_texel_map_back_to_it_and_match_libm() {
        for (w, h) in [(1024, 512), (64, 32), (8, 4), (3, 1)] {
            let grid = TexelGrid::new(w, h);
            for row in 0..h {
                for col in (0..w).step_by((w / 64).max(1)) {
                    for (fx, fy) in [(0.5, 0.5), (0.01, 0.99), (0.99, 0.02)] {
                        let d = grid.direction(col, row, fx, fy);
                        let theta = PI * (row as f32 + fy) / h as f32;
                        let phi = 2.0 * PI * (col as f32 + fx) / w as f32;
                        let exact = Vec3::new(
                            theta.sin() * phi.cos(),
                            theta.cos(),
                            theta.sin() * phi.sin(),
                        );
                        assert!(
                            (d - exact).abs().max_element() < 2e-6,
                            "{w}x{h} {col} {row}"
                        );
                        let (c, r, s) = grid.texel_of(d);
                        // Away from the poles' singular column.
                        if d.x.abs() + d.z.abs() > 1e-3 {
                            assert_eq!((c, r), (col, row), "{w}x{h} {fx} {fy}");
                        } else {
                            assert_eq!(r, row);
                        }
                        assert!((s - theta.sin()).abs() < 2e-3);
                    }
                }
            }
        }
    }
}
