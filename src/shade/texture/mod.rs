//! Shading layer: material inputs evaluated at a hit's UV.
//!
//! Syntax: `texture board = checker { even #ffffff  odd #202020  scale 8 }`, constants,
//! `texture wood = image("wood.png") { wrap repeat  filter anisotropic }` (see `image`),
//! and `phong { diffuse board  specular 0.4  shininess 64 }`.
//!
//! A lookup takes the hit's UV and its footprint: the ellipse of the pixel's ray cone on the
//! surface, in UV units (see `footprint`). A trilinear image texture turns its longer axis
//! into a mip level; an anisotropic one filters along it (see `anisotropic`); other textures
//! ignore it. Anisotropic lookups are counted in a [`FilterStats`] for `--stats`.

use std::sync::Arc;

use glam::{Vec2, Vec3};

pub mod anisotropic;
pub mod footprint;
pub mod image;

pub use self::anisotropic::FilterStats;
pub use self::footprint::Footprint;
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
    /// The colour of `input` at `uv`, for a pixel whose footprint there is `footprint`.
    ///
    /// A constant (most materials' inputs) is answered inline, without a call into the
    /// texture lookup: it runs for every input of every shading point.
    #[inline]
    pub fn color(
        &self,
        input: ColorInput,
        uv: Vec2,
        footprint: Footprint,
        stats: &mut FilterStats,
    ) -> Vec3 {
        match input {
            ColorInput::Constant(c) => c,
            ColorInput::Texture(_) => self.color_at_depth(input, uv, footprint, stats, 0),
        }
    }

    /// A scalar input: a constant, or the red channel of a texture.
    #[inline]
    pub fn scalar(
        &self,
        input: ScalarInput,
        uv: Vec2,
        footprint: Footprint,
        stats: &mut FilterStats,
    ) -> f32 {
        match input {
            ScalarInput::Constant(v) => v,
            ScalarInput::Texture(id) => {
                self.color_at_depth(ColorInput::Texture(id), uv, footprint, stats, 0)
                    .x
            }
        }
    }

    /// Whether any texture reads a mip pyramid: without one, no lookup needs a footprint.
    pub fn any_mip_filtered(&self) -> bool {
        self.slots.iter().flatten().any(|t| match t {
            Texture::Image { filter, .. } => filter.is_mip_filtered(),
            Texture::Constant(_) | Texture::Checker { .. } => false,
        })
    }

    fn color_at_depth(
        &self,
        input: ColorInput,
        uv: Vec2,
        footprint: Footprint,
        stats: &mut FilterStats,
        depth: u32,
    ) -> Vec3 {
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
                self.color_at_depth(pick, uv, footprint, stats, depth + 1)
            }
            Some(Texture::Image { data, wrap, filter }) => {
                data.lookup(uv, *wrap, *filter, footprint, stats).truncate()
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
        let mut stats = FilterStats::default();
        let mut at = |u, v| {
            t.color(
                ColorInput::Texture(0),
                Vec2::new(u, v),
                Footprint::default(),
                &mut stats,
            )
            .x
        };
        assert_eq!(at(0.1, 0.1), 1.0);
        assert_eq!(at(0.6, 0.1), 0.0);
        assert_eq!(at(0.6, 0.6), 1.0);
        assert_eq!(at(-0.1, 0.1), 0.0);
        let mut stats = FilterStats::default();
        let uv = Vec2::new(0.1, 0.6);
        let fp = Footprint::default();
        assert_eq!(t.scalar(ScalarInput::Texture(0), uv, fp, &mut stats), 0.0);
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
        let mut stats = FilterStats::default();
        let c = t.color(
            ColorInput::Texture(0),
            Vec2::ZERO,
            Footprint::default(),
            &mut stats,
        );
        assert_eq!(c, Vec3::ZERO);
    }
}
