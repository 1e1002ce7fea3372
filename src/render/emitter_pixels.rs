//! Stage 4: the pixels that may see an area light, which a fixed-count render samples more.
//!
//! An emitter seen directly is the image's brightest, sharpest feature: on cornell the light is
//! 10× brighter than the walls around it, and the pixels its outline crosses (0.6% of the
//! image) hold 95% of the squared error of a 16-spp render against a converged reference
//! (docs/speed.md). Their error is the coverage of a very bright edge by a few sub-pixel
//! positions, which only more camera samples reduce, while everywhere else the stratified light
//! samples already converge quickly. So before the render, each area light's triangles are
//! projected onto the image; the pixels their bounding rectangles touch (one pixel of margin)
//! take [`SIDE_FACTOR`]² times the samples (a finer rotated grid of the same pattern), within a
//! budget: the extra samples may add at most [`MAX_EXTRA_SHARE`] of the image's own, else the
//! factor shrinks, down to none. Camera samples that hit the emitter cost no shading, so the
//! extra work is mostly the surfaces just around the light.
//!
//! The choice depends only on the scene's geometry and the camera, never on a sample: every
//! pixel's estimate stays an unbiased mean of its own samples, tiles and thread counts give the
//! same bits, and a pixel that sees no emitter is rendered exactly as before. Adaptive renders
//! (`noise`) measure, within the same mark, how much of each pixel the light covers
//! (`emitter_coverage`: a sliver of the light's edge that a pixel's first samples all miss
//! would otherwise stop it dark); one-sample renders stay point-sampled.

use glam::Vec3;

use super::camera::PinholeCamera;
use super::window::PixelWindow;
use crate::scene::Scene;
use crate::shade::Light;

/// Side of the boosted pixels' sub-pixel grid, as a multiple of the image's.
pub const SIDE_FACTOR: u32 = 4;

/// The extra samples may add at most this share of the image's own samples.
pub const MAX_EXTRA_SHARE: f64 = 0.5;

/// Pixels that may see an area light, and how much finer they are sampled.
#[derive(Debug, Clone, Default)]
pub struct EmitterPixels {
    width: u32,
    /// One bit per pixel of the whole image, row-major.
    bits: Vec<u64>,
    /// How many pixels are marked.
    marked: u64,
    /// The grid side multiple the marked pixels use (1: no boost).
    factor: u32,
}

impl EmitterPixels {
    /// No pixel is boosted.
    pub fn none() -> EmitterPixels {
        EmitterPixels {
            factor: 1,
            ..EmitterPixels::default()
        }
    }

    /// The pixels of a `width` × `height` image that `camera` sees the scene's area lights
    /// through, for a render of `side`² samples per pixel.
    pub fn find(scene: &Scene, camera: &PinholeCamera, side: u32) -> EmitterPixels {
        let (width, height) = (scene.settings.width, scene.settings.height);
        let has_area_light = scene
            .lights
            .lights
            .iter()
            .any(|l| matches!(l, Light::Area(_)));
        if side < 2 || !has_area_light || width == 0 || height == 0 {
            return EmitterPixels::none();
        }
        let words = (width as usize * height as usize).div_ceil(64);
        let mut out = EmitterPixels {
            width,
            bits: vec![0; words],
            marked: 0,
            factor: 1,
        };
        let full = PixelWindow::full(width, height);
        let pixels = u64::from(width) * u64::from(height);
        // Once no factor fits the budget, marking more (a large emissive mesh in view) is
        // wasted work: stop.
        let triangles = scene.lights.lights.iter().flat_map(|l| match l {
            Light::Area(area) => area.triangles.as_slice(),
            Light::Point(_) => &[],
        });
        for triangle in triangles {
            if let Some(rect) = projected_rect(camera, triangle, full) {
                out.mark(rect);
                if affordable_factor(out.marked, pixels) == 1 {
                    return EmitterPixels::none();
                }
            }
        }
        out.factor = affordable_factor(out.marked, pixels);
        if out.factor == 1 {
            return EmitterPixels::none();
        }
        out
    }

    fn mark(&mut self, r: PixelWindow) {
        for y in r.y0..r.y1 {
            for x in r.x0..r.x1 {
                let i = y as usize * self.width as usize + x as usize;
                let (word, bit) = (i / 64, 1u64 << (i % 64));
                if self.bits[word] & bit == 0 {
                    self.bits[word] |= bit;
                    self.marked += 1;
                }
            }
        }
    }

    /// The grid side multiple for pixel (`x`, `y`) of the image: [`SIDE_FACTOR`] (or less,
    /// within the budget) where an emitter may be seen, else 1.
    #[inline]
    pub fn factor_at(&self, x: u32, y: u32) -> u32 {
        if self.factor == 1 {
            return 1;
        }
        let i = y as usize * self.width as usize + x as usize;
        match self.bits.get(i / 64) {
            Some(word) if word & (1u64 << (i % 64)) != 0 => self.factor,
            _ => 1,
        }
    }

    /// The grid side multiple of the boosted pixels (1 when none is boosted).
    pub fn factor(&self) -> u32 {
        self.factor
    }

    /// How many pixels are boosted (0 when the factor is 1).
    pub fn boosted(&self) -> u64 {
        if self.factor == 1 {
            0
        } else {
            self.marked
        }
    }
}

/// The largest side multiple (from [`SIDE_FACTOR`] down) whose extra samples on `marked` of
/// `pixels` stay within [`MAX_EXTRA_SHARE`]; 1 when none does.
fn affordable_factor(marked: u64, pixels: u64) -> u32 {
    (2..=SIDE_FACTOR)
        .rev()
        .find(|f| (marked * u64::from(f * f - 1)) as f64 <= MAX_EXTRA_SHARE * pixels as f64)
        .unwrap_or(1)
}

/// The pixels (with one of margin) covered by the bounding rectangle of `triangle`'s
/// projection, clipped to `image`; `None` when it is off the image or a corner is not in front
/// of the camera (then the triangle is simply not boosted: any choice is unbiased).
fn projected_rect(
    camera: &PinholeCamera,
    triangle: &[Vec3; 3],
    image: PixelWindow,
) -> Option<PixelWindow> {
    let mut lo = glam::Vec2::splat(f32::INFINITY);
    let mut hi = glam::Vec2::splat(f32::NEG_INFINITY);
    for &corner in triangle {
        let p = camera.project(corner)?;
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let clip = |v: f32, max: u32| v.clamp(0.0, max as f32) as u32;
    let (x0, y0) = (clip(lo.x - 1.0, image.x1), clip(lo.y - 1.0, image.y1));
    let (x1, y1) = (clip(hi.x + 2.0, image.x1), clip(hi.y + 2.0, image.y1));
    (x0 < x1 && y0 < y1).then_some(PixelWindow { x0, y0, x1, y1 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_shrinks_to_fit_the_budget() {
        let pixels = 100 * 100;
        assert_eq!(affordable_factor(0, pixels), SIDE_FACTOR);
        // 4² − 1 = 15 extra samples each: 333 pixels fit in half the image's samples.
        assert_eq!(affordable_factor(333, pixels), 4);
        assert_eq!(affordable_factor(334, pixels), 3);
        assert_eq!(affordable_factor(625, pixels), 3);
        assert_eq!(affordable_factor(1667, pixels), 1);
    }
}
