//! Textures in the IR: image files, procedural checkers and constants.
//!
//! Syntax:
//! ```text
//! texture wood  = image("wood.png") { wrap repeat  filter anisotropic }
//! texture bumps = image("bumps.png") { encoding data }
//! texture board = checker { even #ffffff  odd #202020  scale 8 }
//! ```

use glam::Vec3;
use serde::Serialize;

use super::{AssetPath, ColorInput};
use crate::source::Span;

/// How an image texture is addressed outside `[0, 1]` UV (`wrap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum WrapMode {
    /// Tiles: u and u + 1 read the same texel.
    Repeat,
    /// The edge texels extend outwards.
    Clamp,
    /// Tiles, flipping every other copy so that copies meet without a seam.
    Mirror,
}

/// How an image texture interpolates its texels (`filter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Filter {
    /// The one texel the UV falls in, full resolution.
    Nearest,
    /// The four nearest texels of the full-resolution image, weighted by distance.
    Bilinear,
    /// Bilinear within two mip levels chosen from the pixel footprint's longer axis; builds a
    /// mip pyramid.
    Trilinear,
    /// The default: trilinear taps spread along the footprint's major axis where it is
    /// anisotropic (a surface seen at a grazing angle), one trilinear lookup where it is not;
    /// builds a mip pyramid.
    Anisotropic,
}

impl Filter {
    /// Whether this filter reads a mip pyramid (and so needs the pixel's footprint).
    pub fn is_mip_filtered(self) -> bool {
        matches!(self, Filter::Trilinear | Filter::Anisotropic)
    }
}

/// How an image's stored values map to linear values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TextureEncoding {
    /// Colour: 8/16-bit values are sRGB-decoded to linear (float images are already linear).
    Srgb,
    /// Data (normal maps, masks): values read raw.
    Linear,
}

/// What a texture's values come from.
#[derive(Debug, Clone, Serialize)]
pub enum TextureSource {
    /// `image("file") { … }`: an image file.
    Image {
        /// The image file, with the span of its path literal.
        file: AssetPath,
        /// How stored values become linear ones.
        encoding: TextureEncoding,
        /// Addressing outside `[0, 1]` UV.
        wrap: WrapMode,
        /// Interpolation, and whether mipmaps are built.
        filter: Filter,
    },
    /// Alternating squares in UV space: `scale` squares per unit of u and of v.
    Checker {
        /// Colour (or texture) of squares where `floor(u·scale) + floor(v·scale)` is even.
        even: ColorInput,
        /// Colour (or texture) of squares where `floor(u·scale) + floor(v·scale)` is odd.
        odd: ColorInput,
        /// Squares per unit of u and of v.
        scale: f32,
    },
    /// `constant { color … }`: one linear RGB colour everywhere.
    Constant(Vec3),
}

/// A `texture` declaration.
#[derive(Debug, Clone, Serialize)]
pub struct Texture {
    /// The name after `texture`.
    pub name: String,
    /// What its values come from.
    pub source: TextureSource,
    /// The `texture` declaration, for diagnostics raised while building.
    pub span: Span,
}
