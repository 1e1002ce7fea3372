//! Shading layer: material inputs evaluated at a hit's UV.
//!
//! Syntax: `texture board = checker { even #ffffff  odd #202020  scale 8 }`, constants,
//! `texture wood = image("wood.png") { wrap repeat  filter trilinear }` (see `image`),
//! and `phong { diffuse board  specular 0.4  shininess 64 }`.
//!
//! A lookup takes the hit's UV and its footprint: the width of the pixel's ray cone on the
//! surface, measured in UV units (see `footprint`). A trilinear image texture turns it
//! into a mip level `log2(footprint · √(w·h))`; other textures ignore it.

use std::sync::Arc;

use glam::{Vec2, Vec3};

pub mod footprint;
pub mod image;

use self::image::ImageData;
use crate::ir::{ColorInput, Filter, ScalarInput, WrapMode};

/// A texture the renderer can evaluate.
#[derive(Debug, Clone)]
pub enum Texture {
    /// The same colour everywhere.
    Constant(Vec3),
    /// `scale` squares per unit of u and of v; the square containing (0, 0)..(1/scale, 1/scale)
    /// is `even`.
    Checker {
        /// The colour of the square at the origin and of every other one.
        even: ColorInput,
        /// The colour of the other squares.
        odd: ColorInput,
        /// Squares per unit of u and of v.
        scale: f32,
    },
    /// An image file's texels, shared (one decode per file and encoding) by every texture
    /// that names it.
    Image {
        /// The decoded texels (and their mip pyramid for trilinear filtering).
        data: Arc<ImageData>,
        /// What UVs outside [0, 1) read.
        wrap: WrapMode,
        /// How texels are blended.
        filter: Filter,
    },
}

/// Textures indexed by `ir::TextureId`; `None` for the ones the scene does not use.
#[derive(Debug, Clone, Default)]
pub struct Textures {
    /// `slots[id]` is texture `id`.
    pub slots: Vec<Option<Texture>>,
}

/// Checkers may nest (a checker of checkers); the checker stage rejects cycles, and this bound
/// keeps a cycle that slipped through from recursing forever (it evaluates to black).
const MAX_NESTING: u32 = 16;

impl Textures {
    /// The colour of `input` at `uv`; `footprint` is the pixel's width in UV units.
    pub fn color(&self, input: ColorInput, uv: Vec2, footprint: f32) -> Vec3 {
        self.color_at_depth(input, uv, footprint, 0)
    }

    /// A scalar input: a constant, or the red channel of a texture.
    pub fn scalar(&self, input: ScalarInput, uv: Vec2, footprint: f32) -> f32 {
        match input {
            ScalarInput::Constant(v) => v,
            ScalarInput::Texture(id) => {
                self.color_at_depth(ColorInput::Texture(id), uv, footprint, 0)
                    .x
            }
        }
    }

    fn color_at_depth(&self, input: ColorInput, uv: Vec2, footprint: f32, depth: u32) -> Vec3 {
        let id = match input {
            ColorInput::Constant(c) => return c,
            ColorInput::Texture(id) => id,
        };
        if depth >= MAX_NESTING {
            return Vec3::ZERO;
        }
        match self.slots.get(id as usize).and_then(Option::as_ref) {
            Some(Texture::Constant(c)) => *c,
            Some(Texture::Checker { even, odd, scale }) => {
                let cell = (uv * *scale).floor();
                let parity = (cell.x + cell.y).rem_euclid(2.0);
                let pick = if parity < 0.5 { *even } else { *odd };
                self.color_at_depth(pick, uv, footprint, depth + 1)
            }
            Some(Texture::Image { data, wrap, filter }) => {
                let lod = footprint.log2() + data.log2_size();
                data.lookup(uv, *wrap, *filter, lod).truncate()
            }
            None => Vec3::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_alternates_and_handles_negative_uv() {
        let t = Textures {
            slots: vec![Some(Texture::Checker {
                even: ColorInput::Constant(Vec3::ONE),
                odd: ColorInput::Constant(Vec3::ZERO),
                scale: 2.0,
            })],
        };
        let at = |u, v| t.color(ColorInput::Texture(0), Vec2::new(u, v), 0.0).x;
        assert_eq!(at(0.1, 0.1), 1.0);
        assert_eq!(at(0.6, 0.1), 0.0);
        assert_eq!(at(0.6, 0.6), 1.0);
        assert_eq!(at(-0.1, 0.1), 0.0);
        assert_eq!(
            t.scalar(ScalarInput::Texture(0), Vec2::new(0.1, 0.6), 0.0),
            0.0
        );
    }

    #[test]
    fn a_cycle_terminates() {
        let t = Textures {
            slots: vec![Some(Texture::Checker {
                even: ColorInput::Texture(0),
                odd: ColorInput::Texture(0),
                scale: 1.0,
            })],
        };
        assert_eq!(t.color(ColorInput::Texture(0), Vec2::ZERO, 0.0), Vec3::ZERO);
    }
}
