//! Stage 3, scene: `ir::SceneDesc` + assets (via the `Loader`) → render-ready [`Scene`]
//! (meshes shared by instances, one acceleration structure over all of them, textures, lights
//! with their sampling tables, the camera), building only what the scene uses.
//!
//! Input syntax this stage gives meaning to: `mesh … = obj(…) | inline {…} | quad | box |
//! sphere`, `object … { mesh m  material p  transform {…} }`, `light … = point | area |
//! environment`, `texture … = image | checker | constant`, `normal_map`. Errors are [`BuildError`]s converted to
//! diagnostics labelled at the path literal or declaration in the `.scn`.

mod build;
pub mod cache;
pub mod distribution;
pub mod distribution2d;
mod env_load;
pub mod environment;
mod error;
mod facing;
pub mod image_texture;
mod inventory;
pub mod lights;
mod load;
pub mod mesh;
mod obj_parts;
pub mod shapes;
pub mod tangents;
pub mod texture;
mod texture_load;

use std::time::Duration;

use glam::{Affine3A, Mat3, Vec3, Vec4};

pub use build::{build, build_cached};
pub use cache::{BuildCache, CacheReport};
pub use environment::{EnvMap, EnvSample, Environment};
pub use error::BuildError;
pub use inventory::{Built, Features};
pub use lights::{AreaLight, Light, Lights, Picked, PointLight};
pub use mesh::{MeshPart, TriMesh};
pub use texture::{Texture, Textures};

use crate::bvh::{Accel, AccelKind, AccelStats};
use crate::diag::Diagnostic;
use crate::ir;

/// Choices the command line makes about the build.
#[derive(Debug, Clone, Copy)]
pub struct BuildOptions {
    /// `--accel none` renders with the brute-force oracle.
    pub accel: AccelKind,
    /// `--camera NAME`, resolved by the caller to an index into `SceneDesc::cameras`;
    /// `None` uses `SceneDesc::active_camera`.
    pub camera: Option<usize>,
}

impl Default for BuildOptions {
    fn default() -> BuildOptions {
        BuildOptions {
            accel: AccelKind::Bvh,
            camera: None,
        }
    }
}

/// Wall time of the build phases, for `--stats`.
#[derive(Debug, Clone, Copy, Default)]
pub struct BuildTimings {
    /// Reading and decoding files, tessellating built-in shapes, validating meshes.
    pub asset_load: Duration,
    /// Building the acceleration structure (zero when the scene has no triangles).
    pub accel_build: Duration,
    pub total: Duration,
}

/// What a hit on an instance means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Surface {
    /// Reflects light with `Scene::materials[i]`.
    Material(u32),
    /// The geometry of `Lights::lights[i]`, an area light: shows its radiance, reflects nothing.
    Emitter(u32),
}

/// One placement of a mesh. `Scene::instances[i]` is the accel's instance `i`.
#[derive(Debug, Clone, Copy)]
pub struct SceneInstance {
    pub mesh: u32,
    pub surface: Surface,
    pub world_from_object: Affine3A,
    /// The inverse transpose of the linear part: maps object normals to world normals.
    pub normal_from_object: Mat3,
    /// Where this placement's OBJ part surfaces start in `Scene::part_surfaces`
    /// (`u32::MAX`: the mesh has no parts; every triangle is `surface`).
    pub part_base: u32,
}

/// The material model the renderer evaluates (`ir::Material` without what is not supported).
#[derive(Debug, Clone)]
pub struct SurfaceMaterial {
    pub diffuse: ir::ColorInput,
    pub specular: ir::ColorInput,
    pub shininess: ir::ScalarInput,
    pub ambient: Vec3,
    /// A tangent-space normal map (applied where the mesh has UVs, hence tangents).
    pub normal_map: Option<ir::NormalMap>,
}

impl SurfaceMaterial {
    /// Whether shading it looks up any texture, its normal map included (else every input is a
    /// constant).
    pub fn is_textured(&self) -> bool {
        self.normal_map.is_some()
            || matches!(self.diffuse, ir::ColorInput::Texture(_))
            || matches!(self.specular, ir::ColorInput::Texture(_))
            || matches!(self.shininess, ir::ScalarInput::Texture(_))
    }
}

/// How shading points sample triangles of area lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightSampling {
    /// Uniform by area on the triangle: estimator `L_e·f·cos θ·cos θ_l / r² / pdf_area`.
    Area,
    /// Uniform over the spherical triangle the light subtends (Arvo 1995) when its solid angle
    /// is in a numerically safe range, by area otherwise. Lower variance for lights that are
    /// large or close (measured in `tests/render_light_sampling.rs`).
    #[default]
    SolidAngle,
}

/// Which strategies estimate the light of area lights and the environment (point lights are
/// always light-sampled: a BRDF ray cannot hit a point).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DirectStrategy {
    /// Light sampling and BRDF sampling, combined by the power heuristic.
    #[default]
    Mis,
    /// Light sampling alone (no BRDF rays).
    LightOnly,
    /// BRDF sampling alone (cosine / Phong lobe directions that reach an emitter or the sky).
    BrdfOnly,
}

/// Everything the renderer needs, ready to trace.
#[derive(Debug)]
pub struct Scene {
    /// Where the scene's (0, 0, 0) is in the world the `.scn` describes: every position here
    /// (instances, lights, the camera's eye) is relative to it (`build/origin.rs`).
    pub world_origin: glam::DVec3,
    pub camera: ir::Camera,
    pub settings: ir::RenderSettings,
    pub meshes: Vec<TriMesh>,
    pub instances: Vec<SceneInstance>,
    /// `None` when the scene has no triangles: every ray misses without any work.
    pub accel: Option<Accel>,
    pub materials: Vec<SurfaceMaterial>,
    /// Surfaces of OBJ material parts, per placement (see `SceneInstance::part_base`).
    pub part_surfaces: Vec<Surface>,
    pub textures: Textures,
    /// Per mesh: per-vertex tangents (xyz, and the bitangent's sign in w), derived from UVs
    /// only for meshes that normal-mapped objects use; empty otherwise.
    pub tangents: Vec<Vec<Vec4>>,
    pub lights: Lights,
    pub light_sampling: LightSampling,
    /// How direct light from area lights and the environment is sampled (tests switch it).
    pub strategy: DirectStrategy,
    pub timings: BuildTimings,
    /// Warnings found while building (degenerate triangles dropped, empty meshes).
    pub warnings: Vec<Diagnostic>,
}

impl Scene {
    pub fn accel_stats(&self) -> AccelStats {
        self.accel.as_ref().map(Accel::stats).unwrap_or_default()
    }

    /// Triangles over all instances (what the accel holds).
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.meshes[i.mesh as usize].triangles.len())
            .sum()
    }
}
