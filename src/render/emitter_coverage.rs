//! Stage 4: how much of each pixel an area light's outline covers, for adaptive renders.
//!
//! A pixel that sees the light's edge as a sliver a percent of its area wide (a ceiling pixel
//! beside cornell's light) gets a bright sample once in a hundred; until the first one comes,
//! its samples all agree and its error estimate says "done", though the pixel is off by its
//! whole value (cornell 48×48 at 10% and 5%: five such pixels stopped black after 88 and 168
//! samples, against references of 0.12–0.13, and carried 37% and 49% of the image's squared
//! error, which the reported figure cannot see; docs/quality.md). The geometry says what the
//! samples cannot: each light triangle facing the camera is projected onto the film and
//! clipped against every pixel square it touches, which gives the share `c` of the pixel the
//! light can cover (an upper bound: occluders are ignored). Until a sample has seen the light,
//! such a pixel takes at least `6/c` samples ([`EXPECTED_HITS`]: it cannot miss a share `c` that
//! often by chance), unless `c` times the light's luminance is already within the target of the
//! pixel's mean ([`SliverRule`]). The flat `8/target` minimum of emitter pixels
//! (`estimate::emitter_min_samples`) stays beside it: it guards the light edge's absolute
//! error, this rule the slivers that minimum is too small to find.
//!
//! Decided from geometry and the pixel's own samples only, so the image does not depend on
//! threads or tiles; fixed-count renders never build it.

use std::collections::HashMap;

use glam::{Vec2, Vec3};

use super::camera::PinholeCamera;
use super::emitter_pixels::EmitterPixels;
use crate::scene::Scene;
use crate::shade::color::luminance;
use crate::shade::Light;

/// Per pixel a light covers: the share of its area area lights can cover, and the dimmest such
/// light's luminance. Empty when no pixel is marked by [`EmitterPixels`] (whose budget keeps
/// the covered pixels a few percent of the image).
#[derive(Debug, Clone, Default)]
pub struct EmitterCoverage {
    width: u32,
    /// Row-major pixel index → (covered share of the pixel, 0..=1; luminance of the dimmest
    /// light covering it).
    pixels: HashMap<u64, (f32, f32)>,
}

impl EmitterCoverage {
    /// The coverage of the pixels `marked` holds (its budget bounds the work: a light too
    /// large on the film to mark is not covered either).
    pub fn find(scene: &Scene, camera: &PinholeCamera, marked: &EmitterPixels) -> Self {
        let (width, height) = (scene.settings.width, scene.settings.height);
        if marked.boosted() == 0 {
            return EmitterCoverage::default();
        }
        let mut out = EmitterCoverage {
            width,
            pixels: HashMap::new(),
        };
        for light in &scene.lights.lights {
            let Light::Area(area) = light else { continue };
            let luminance = luminance(area.radiance);
            for (triangle, normal) in area.triangles.iter().zip(&area.normals) {
                let facing = (camera.eye() - triangle[0]).dot(*normal) > 0.0;
                if !(facing || area.two_sided) {
                    continue;
                }
                let Some(film) = project(camera, triangle) else {
                    continue;
                };
                out.add(&film, luminance, (width, height));
            }
        }
        out
    }

    fn add(&mut self, film: &[Vec2; 3], luminance: f32, (width, height): (u32, u32)) {
        let lo = film[0].min(film[1]).min(film[2]).max(Vec2::ZERO);
        let hi = film[0].max(film[1]).max(film[2]);
        let x1 = (hi.x.ceil().max(0.0) as u32).min(width);
        let y1 = (hi.y.ceil().max(0.0) as u32).min(height);
        for y in lo.y.floor() as u32..y1 {
            for x in lo.x.floor() as u32..x1 {
                let share = clipped_area(film, Vec2::new(x as f32, y as f32));
                if share <= 0.0 {
                    continue;
                }
                let i = u64::from(y) * u64::from(self.width) + u64::from(x);
                let (c, l) = self.pixels.entry(i).or_insert((0.0, f32::INFINITY));
                *c = (*c + share).min(1.0);
                *l = l.min(luminance);
            }
        }
    }

    /// The share of pixel (`x`, `y`) area lights can cover and their least luminance; `None`
    /// where none can.
    pub fn at(&self, x: u32, y: u32) -> Option<(f32, f32)> {
        let i = u64::from(y) * u64::from(self.width) + u64::from(x);
        self.pixels.get(&i).copied().filter(|&(c, _)| c > 0.0)
    }
}

/// The triangle's corners on the film, `None` if one is not in front of the camera.
fn project(camera: &PinholeCamera, triangle: &[Vec3; 3]) -> Option<[Vec2; 3]> {
    Some([
        camera.project(triangle[0])?,
        camera.project(triangle[1])?,
        camera.project(triangle[2])?,
    ])
}

/// Area of the triangle `film` inside the unit square at `corner` (Sutherland–Hodgman).
fn clipped_area(film: &[Vec2; 3], corner: Vec2) -> f32 {
    let mut poly: Vec<Vec2> = film.iter().map(|p| *p - corner).collect();
    // Each edge of the unit square as (axis, bound, keep below).
    for (axis, bound, below) in [
        (0, 0.0, false),
        (0, 1.0, true),
        (1, 0.0, false),
        (1, 1.0, true),
    ] {
        let inside = |p: Vec2| (p[axis] <= bound) == below || p[axis] == bound;
        let mut out = Vec::with_capacity(poly.len() + 2);
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            if inside(a) {
                out.push(a);
            }
            if inside(a) != inside(b) {
                let t = (bound - a[axis]) / (b[axis] - a[axis]);
                out.push(a + (b - a) * t);
            }
        }
        poly = out;
        if poly.len() < 3 {
            return 0.0;
        }
    }
    let twice: f32 = (0..poly.len())
        .map(|i| poly[i].perp_dot(poly[(i + 1) % poly.len()]))
        .sum();
    twice.abs() / 2.0
}

/// Samples the light's covered share must expect to have hit before a pixel that has seen no
/// bright sample may stop: no hit in `6/c` samples happens with probability about `e⁻⁶`
/// (0.25%) if the light really covers `c`. With the rule of three (`3/c`, 5%), one of cornell's
/// ceiling pixels (1% covered, reference 0.134) still stopped black at 2% in one of four seeds
/// (docs/quality.md).
pub const EXPECTED_HITS: f64 = 6.0;

/// Whether a pixel that may see a sliver of light must sample on: it has seen no sample as
/// bright as half the light, has fewer than `3/c` samples, and the light's covered share
/// could still move its mean by more than the target.
#[derive(Debug, Clone, Copy)]
pub struct SliverRule {
    /// Share of the pixel the light can cover.
    pub share: f64,
    /// Luminance of the dimmest light covering it.
    pub luminance: f64,
}

impl SliverRule {
    /// Whether the pixel must go on after `n` samples with mean luminance `mean` and
    /// brightest sample `brightest`, at relative `target`.
    pub fn holds(&self, n: u32, mean: f64, brightest: f64, target: f64) -> bool {
        let seen = brightest >= 0.5 * self.luminance;
        let matters = self.share * self.luminance > target * mean.max(super::estimate::REL_FLOOR);
        !seen && matters && (n as f64) * self.share < EXPECTED_HITS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipped_areas_of_known_triangles() {
        let t = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(0.0, 2.0),
        ];
        assert!((clipped_area(&t, Vec2::ZERO) - 1.0).abs() < 1e-6);
        assert!((clipped_area(&t, Vec2::new(1.0, 0.0)) - 0.5).abs() < 1e-6);
        assert!((clipped_area(&t, Vec2::new(1.0, 1.0))).abs() < 1e-6);
        let sliver = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(0.0, 0.02),
        ];
        assert!((clipped_area(&sliver, Vec2::ZERO) - 0.01).abs() < 1e-6);
    }

    #[test]
    fn the_rule_lets_go_once_the_light_is_seen_or_cannot_matter() {
        let r = SliverRule {
            share: 0.01,
            luminance: 12.0,
        };
        assert!(r.holds(88, 0.0, 0.0, 0.1));
        assert!(r.holds(300, 0.0, 0.0, 0.1));
        assert!(!r.holds(600, 0.0, 0.0, 0.1));
        assert!(!r.holds(88, 0.0, 12.0, 0.1));
        // 0.12 of light against a mean of 10: within 10%.
        assert!(!r.holds(88, 10.0, 0.5, 0.1));
    }
}
