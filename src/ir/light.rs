//! Lights in the IR: point, area (any mesh) and environment.
//!
//! Syntax:
//! ```text
//! light bulb    = point { position (0, 4, 0)  intensity rgb(10, 10, 10) }
//! light ceiling = area { quad (343, 548.7, 227) (343, 548.7, 332) (213, 548.7, 332) (213, 548.7, 227)
//!                        radiance rgb(17, 12, 4)  two_sided false  samples 4 }
//! light panel   = area { mesh panel  transform { translate (0, 3, 0) }  radiance 5 }
//! light sky     = environment { image("sky.hdr")  intensity 1  rotate 90deg  visible true }
//! ```

use glam::{DMat4, DVec3, Vec3};
use serde::Serialize;

use super::{AssetPath, MeshId};
use crate::source::Span;

/// One `light` declaration, by kind.
#[derive(Debug, Clone, Serialize)]
pub enum Light {
    /// `point { … }`: all its power leaves one world-space point.
    Point(PointLight),
    /// `area { … }`: a `quad` or a mesh that emits.
    Area(AreaLight),
    /// `environment { … }`: radiance from infinitely far away, seen by rays that leave the scene.
    Environment(EnvironmentLight),
}

/// An isotropic point light. Irradiance at distance r, angle θ: `intensity · cos θ / r²`.
#[derive(Debug, Clone, Serialize)]
pub struct PointLight {
    /// The name after `light`.
    pub name: String,
    /// World-space position, in f64 until the build (see `Object::world_from_object`).
    pub position: DVec3,
    /// Radiant intensity (W/sr per channel, linear RGB).
    pub intensity: Vec3,
    /// The `light` declaration, for diagnostics raised while building.
    pub span: Span,
}

/// A diffuse emitter: every triangle of `mesh`, placed by `world_from_object`, emits `radiance`
/// from its front face (the side its counter-clockwise winding faces), or both if `two_sided`.
#[derive(Debug, Clone, Serialize)]
pub struct AreaLight {
    /// The name after `light`.
    pub name: String,
    /// The emitting mesh (a `quad` is lowered to a mesh of two triangles).
    pub mesh: MeshId,
    /// Maps the mesh's object space to world space (the light's `transform`), in f64 until
    /// the build (see `Object::world_from_object`).
    pub world_from_object: DMat4,
    /// Emitted radiance (linear RGB), non-negative.
    pub radiance: Vec3,
    /// Whether the back face emits too (`two_sided true`).
    pub two_sided: bool,
    /// Shadow rays per shading point and pixel sample, ≥ 1.
    pub samples: u32,
    /// The `light` declaration, for diagnostics raised while building.
    pub span: Span,
}

/// Where an environment's radiance comes from, before `intensity` scales it.
#[derive(Debug, Clone, Serialize)]
pub enum EnvSource {
    /// The same radiance (linear RGB) from every direction.
    Constant(Vec3),
    /// Equirectangular map: row 0 is +y (up); u = φ / 2π with direction
    /// (sin θ cos φ, cos θ, sin θ sin φ).
    Image(AssetPath),
}

/// Light from infinitely far away: the radiance of rays that leave the scene.
#[derive(Debug, Clone, Serialize)]
pub struct EnvironmentLight {
    /// The name after `light`.
    pub name: String,
    /// A constant radiance or an equirectangular image.
    pub source: EnvSource,
    /// Multiplies the radiance of the source.
    pub intensity: f32,
    /// Rotation of the map about +y, radians.
    pub rotation_y_rad: f32,
    /// Whether camera rays that escape show the environment (otherwise black).
    pub visible: bool,
    /// The `light` declaration, for diagnostics raised while building.
    pub span: Span,
}
