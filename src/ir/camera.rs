//! Camera in the IR: a pin-hole camera placed in world space.
//!
//! Syntax: `camera main { eye (0, 1, -5)  target (0, 1, 0)  up (0, 1, 0)  fov 40deg }`
//! or `camera main { transform { ... }  fov 40deg }` (the camera sits at its local origin, looks
//! down its local +z with +y up). The checker turns both forms into the same orthonormal frame.

use glam::{DVec3, Vec3};
use serde::Serialize;

use crate::source::Span;

/// A pin-hole camera. `forward`, `up` and `right` are unit vectors and mutually orthogonal
/// (the checker guarantees it: `up` is re-orthogonalised against `forward`).
#[derive(Debug, Clone, Serialize)]
pub struct Camera {
    /// The name after `camera`, which `--camera` selects by.
    pub name: String,
    /// Position of the pin-hole, world space, in f64: the build places the scene relative to
    /// an origin near it, so a scene far from (0, 0, 0) keeps its precision.
    pub eye: DVec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Unit up vector, orthogonal to `forward`.
    pub up: Vec3,
    /// Unit right vector: `forward × up`, so the image's +x maps to it.
    pub right: Vec3,
    /// Vertical field of view in radians, in (0, π).
    pub fov_y_rad: f32,
    /// The `camera` declaration, for diagnostics raised while building.
    pub span: Span,
}
