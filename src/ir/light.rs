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

#[derive(Debug, Clone, Serialize)]
pub enum Light {
    Point(PointLight),
    Area(AreaLight),
    Environment(EnvironmentLight),
}

/// An isotropic point light. Irradiance at distance r, angle θ: `intensity · cos θ / r²`.
#[derive(Debug, Clone, Serialize)]
pub struct PointLight {
    pub name: String,
    /// World position, in f64 until the build (see `Object::world_from_object`).
    pub position: DVec3,
    /// Radiant intensity (W/sr per channel, linear RGB).
    pub intensity: Vec3,
    pub span: Span,
}

/// A diffuse emitter: every triangle of `mesh`, placed by `world_from_object`, emits `radiance`
/// from its front face (the side its counter-clockwise winding faces), or both if `two_sided`.
#[derive(Debug, Clone, Serialize)]
pub struct AreaLight {
    pub name: String,
    pub mesh: MeshId,
    /// In f64 until the build (see `Object::world_from_object`).
    pub world_from_object: DMat4,
    /// Emitted radiance (linear RGB), non-negative.
    pub radiance: Vec3,
    pub two_sided: bool,
    /// Shadow rays per shading point and pixel sample, ≥ 1.
    pub samples: u32,
    pub span: Span,
}

#[derive(Debug, Clone, Serialize)]
pub enum EnvSource {
    Constant(Vec3),
    /// Equirectangular map: row 0 is +y (up); u = φ / 2π with direction
    /// (sin θ cos φ, cos θ, sin θ sin φ).
    Image(AssetPath),
}

#[derive(Debug, Clone, Serialize)]
pub struct EnvironmentLight {
    pub name: String,
    pub source: EnvSource,
    /// Multiplies the radiance of the source.
    pub intensity: f32,
    /// Rotation of the map about +y, radians.
    pub rotation_y_rad: f32,
    /// Whether camera rays that escape show the environment (otherwise black).
    pub visible: bool,
    pub span: Span,
}
