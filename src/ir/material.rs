//! Materials in the IR: the energy-normalised Phong model, with every input either a constant
//! or a texture.
//!
//! Syntax:
//! ```text
//! material shiny = phong { diffuse #808080  specular 0.4  shininess 64  ambient 0 }
//! material wood  = phong { diffuse woodtex  normal_map bumps  normal_strength 0.8 }
//! ```

use glam::Vec3;
use serde::Serialize;

use super::TextureId;
use crate::source::Span;

/// A colour-valued material input: linear RGB, or a texture looked up at the hit's UV.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum ColorInput {
    /// A linear RGB colour.
    Constant(Vec3),
    /// The texture `id`, looked up at the hit's UV.
    Texture(TextureId),
}

/// A scalar-valued material input: a constant, or a texture whose first (red) channel is used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum ScalarInput {
    /// A constant value.
    Constant(f32),
    /// The texture `id`, whose red channel is read at the hit's UV.
    Texture(TextureId),
}

/// Which way the green channel of a normal map points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum GreenConvention {
    /// +Y up (Blender, Maya, glTF, OpenGL).
    OpenGl,
    /// +Y down (3ds Max, Unreal, DirectX).
    DirectX,
}

/// A tangent-space normal map, bending the shading normal (`normal_map NAME`).
#[derive(Debug, Clone, Serialize)]
pub struct NormalMap {
    /// A data (linear) texture with tangent-space normals encoded as `n * 0.5 + 0.5`.
    pub texture: TextureId,
    /// 0 leaves the geometric/shading normal, 1 applies the map as authored.
    pub strength: f32,
    /// Which way the map's green channel points.
    pub green: GreenConvention,
}

/// Energy-normalised Phong: `f = diffuse/π + specular·(n+2)/(2π)·cos^n α`, plus a constant
/// `ambient` radiance added at every hit whatever the lights.
#[derive(Debug, Clone, Serialize)]
pub struct Material {
    /// The name after `material`.
    pub name: String,
    /// Diffuse albedo, each channel in [0, 1].
    pub diffuse: ColorInput,
    /// Specular albedo at normal incidence, each channel in [0, 1].
    pub specular: ColorInput,
    /// Phong exponent n ≥ 0.
    pub shininess: ScalarInput,
    /// Radiance added unconditionally (default 0).
    pub ambient: Vec3,
    /// The normal map; `None` when the material names none.
    pub normal_map: Option<NormalMap>,
    /// The `material` declaration, for diagnostics raised while building.
    pub span: Span,
}
