//! Textures in the IR: image files, procedural checkers and constants.
//!
//! Syntax:
//! ```text
//! texture wood  = image("wood.png") { wrap repeat  filter trilinear }
//! texture bumps = image("bumps.png") { encoding data }
//! texture board = checker { even #ffffff  odd #202020  scale 8 }
//! ```

use glam::Vec3;
use serde::Serialize;

use super::{AssetPath, ColorInput};
use crate::source::Span;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum WrapMode {
    Repeat,
    Clamp,
    Mirror,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Filter {
    Nearest,
    Bilinear,
    /// Bilinear within two mip levels chosen from the pixel footprint; only this mode builds a
    /// mip pyramid.
    Trilinear,
}

/// How an image's stored values map to linear values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TextureEncoding {
    /// Colour: 8/16-bit values are sRGB-decoded to linear (float images are already linear).
    Srgb,
    /// Data (normal maps, masks): values read raw.
    Linear,
}

#[derive(Debug, Clone, Serialize)]
pub enum TextureSource {
    Image {
        file: AssetPath,
        encoding: TextureEncoding,
        wrap: WrapMode,
        filter: Filter,
    },
    /// Alternating squares in UV space: `scale` squares per unit of u and of v.
    Checker {
        even: ColorInput,
        odd: ColorInput,
        scale: f32,
    },
    Constant(Vec3),
}

#[derive(Debug, Clone, Serialize)]
pub struct Texture {
    pub name: String,
    pub source: TextureSource,
    pub span: Span,
}
