//! Stage 5, film: the rendered image as linear RGB radiance, and its output files.
//!
//! Syntax: `render { output "cornell.png"  exposure 0  tonemap filmic }`. [`write()`] picks the
//! format from the extension: `.png` (8-bit sRGB after exposure and tone mapping), `.exr`
//! (linear float OpenEXR), `.hdr` (Radiance RGBE), `.pfm` (portable float map). Writes are
//! atomic: a temporary file in the target's directory, fsync, rename over the target.

pub mod compare;
mod encode;
mod exr_header;
pub mod merge;
pub mod tile;
pub mod tonemap;
mod write;

use glam::Vec3;

/// PNG bytes in memory (the preview server serves them).
pub use encode::png as encode_png;
pub use write::{
    format_for_path, write, write_atomic_with, write_image, Durability, WriteError, WriteSettings,
};

/// Linear RGB radiance per pixel, row-major, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    pixels: Vec<Vec3>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Film {
        Film {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Every pixel, row-major from the top.
    pub fn pixels(&self) -> &[Vec3] {
        &self.pixels
    }

    /// The pixel at column `x`, row `y` (0, 0 = top-left); black outside the image.
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        if x < self.width && y < self.height {
            self.pixels[y as usize * self.width as usize + x as usize]
        } else {
            Vec3::ZERO
        }
    }

    /// Sets the pixel at column `x`, row `y` (ignored outside the image).
    pub fn set(&mut self, x: u32, y: u32, value: Vec3) {
        if x < self.width && y < self.height {
            self.pixels[y as usize * self.width as usize + x as usize] = value;
        }
    }

    /// Mean radiance over the image.
    pub fn mean(&self) -> Vec3 {
        if self.pixels.is_empty() {
            return Vec3::ZERO;
        }
        self.pixels.iter().copied().sum::<Vec3>() / self.pixels.len() as f32
    }
}
