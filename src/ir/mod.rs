//! The validated scene description: the seam between the compiler and the renderer.
//!
//! `check::check` lowers the AST into a [`SceneDesc`]; `scene::build` turns it into render-ready
//! data. Everything here is plain data: every name is resolved to an index, units are normalised
//! (radians, linear RGB, world-space transforms), defaults are applied and values are validated,
//! so later stages never re-check user input except what needs I/O (files that may be missing or
//! corrupt; those errors point back at the [`AssetPath`] span). There are no expressions here:
//! `let` constants and arithmetic are folded by the checker. Declarations nothing uses are dropped
//! (and reported as warnings), so the IR holds only what the image needs.
//!
//! The types derive `Serialize` so that `scnc ir` and the insta snapshots can print them.

mod camera;
pub mod identity;
mod light;
mod material;
mod mesh;
mod render_settings;
mod shift;
mod texture;

pub use camera::Camera;
pub use light::{AreaLight, EnvSource, EnvironmentLight, Light, PointLight};
pub use material::{ColorInput, GreenConvention, Material, NormalMap, ScalarInput};
pub use mesh::{
    AssetPath, BuiltinShape, InlineMesh, Mesh, MeshSource, ObjMaterialOverride, ObjOptions,
};
pub use render_settings::{
    Output, OutputFormat, Quality, RenderSettings, SamplePattern, SettingFlags, ToneMap,
    DEFAULT_MAX_SAMPLES,
};
pub use texture::{Filter, Texture, TextureEncoding, TextureSource, WrapMode};

use glam::DMat4;
use serde::Serialize;

use crate::source::Span;

/// Index into [`SceneDesc::meshes`].
pub type MeshId = u32;
/// Index into [`SceneDesc::materials`].
pub type MaterialId = u32;
/// Index into [`SceneDesc::textures`].
pub type TextureId = u32;

/// A fully resolved scene: what `check` produces and `scene::build` consumes.
#[derive(Debug, Clone, Serialize)]
pub struct SceneDesc {
    /// Every camera declared, in declaration order (the CLI may pick any by name).
    pub cameras: Vec<Camera>,
    /// The camera `render { camera NAME }` chose, or the first one.
    pub active_camera: usize,
    /// The meshes objects and area lights use, indexed by [`MeshId`].
    pub meshes: Vec<Mesh>,
    /// The textures materials (and checker textures) use, indexed by [`TextureId`].
    pub textures: Vec<Texture>,
    /// The materials objects use, indexed by [`MaterialId`].
    pub materials: Vec<Material>,
    /// Placed instances: groups are flattened, transforms composed to world space.
    pub objects: Vec<Object>,
    /// Every light, in declaration order.
    pub lights: Vec<Light>,
    /// Image size, sampling, outputs and the rest of `render { … }`, defaults applied.
    pub render: RenderSettings,
}

/// One placement of a mesh in the world. Many objects may share one mesh without copying it.
/// Plain data (`Copy`): the incremental check moves 100,000 of them within their list.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Object {
    /// The mesh placed.
    pub mesh: MeshId,
    /// The `object`'s material: its whole surface, or an OBJ's faces that neither an MTL
    /// material nor a `material` override covers.
    pub material: MaterialId,
    /// Maps the mesh's own coordinates to world coordinates (all group transforms applied).
    /// In f64 (as the checker composed it): the build rounds it to f32 relative to an origin
    /// near the scene, so a scene far from (0, 0, 0) keeps its precision.
    pub world_from_object: DMat4,
    /// The `object` statement, for diagnostics raised while building.
    pub span: Span,
}

impl SceneDesc {
    /// The active camera; `None` only when the scene declares no camera.
    pub fn camera(&self) -> Option<&Camera> {
        self.cameras.get(self.active_camera)
    }

    /// The index in `cameras` of the camera called `name` (for `--camera NAME`).
    pub fn camera_by_name(&self, name: &str) -> Option<usize> {
        self.cameras.iter().position(|c| c.name == name)
    }
}
