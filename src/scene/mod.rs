//! Stage 3, scene: `ir::SceneDesc` + assets (via the `Loader`) → render-ready [`Scene`]
//! (meshes shared by instances, one acceleration structure over all of them, textures, lights
//! with their sampling tables, the camera), building only what the scene uses.
//!
//! Input syntax this stage gives meaning to: `mesh … = obj(…) | inline {…} | quad | box |
//! sphere`, `object … { mesh m  material p  transform {…} }`, `light … = point | area |
//! environment`, `texture … = image | checker | constant`, `normal_map`. Errors and warnings are [`BuildError`]s
//! converted to diagnostics labelled at the path literal or declaration in the `.scn`, returned
//! beside the scene in the [`Staged`](crate::diag::Staged) shape of every stage.

mod build;
pub mod cache;
mod env_load;
mod error;
pub mod face_normals;
mod facing;
mod inventory;
mod load;
pub mod mesh;
mod obj_parts;
pub mod shapes;
pub mod tangents;
mod texture_load;

use std::time::Duration;

use glam::{Affine3A, Mat3, Vec3, Vec4};

pub use build::{build, build_cached};
pub use cache::{BuildCache, CacheReport};
pub use error::BuildError;
pub use inventory::{Built, Features};
pub use mesh::{MeshPart, TriMesh};

use crate::bvh::{Accel, AccelKind, AccelStats};
use crate::ir;
use crate::shade::{Lights, Textures};

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
    /// The whole build.
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
    /// Index into `Scene::meshes`.
    pub mesh: u32,
    /// What a hit on it means (unless its OBJ parts say otherwise).
    pub surface: Surface,
    /// Where it is placed.
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
    /// Diffuse albedo.
    pub diffuse: ir::ColorInput,
    /// Specular albedo of the Phong lobe.
    pub specular: ir::ColorInput,
    /// Phong exponent.
    pub shininess: ir::ScalarInput,
    /// Radiance added at every hit, whatever the light.
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

/// Which per-sample code renders the scene's pixels: the same bits either way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadingPath {
    /// A path specialised for the scene's features where one covers it (`render::rect_lit`),
    /// the general integrator elsewhere.
    #[default]
    Specialised,
    /// The general integrator everywhere (what tests compare the specialised paths with).
    General,
}

/// Everything the renderer needs, ready to trace.
#[derive(Debug)]
pub struct Scene {
    /// Where the scene's (0, 0, 0) is in the world the `.scn` describes: every position here
    /// (instances, lights, the camera's eye) is relative to it (`build/origin.rs`).
    pub world_origin: glam::DVec3,
    /// The camera to render from (its eye relative to `world_origin`).
    pub camera: ir::Camera,
    /// The render settings, resolved (command-line choices included) before the build.
    pub settings: ir::RenderSettings,
    /// Every mesh used, once however many instances place it.
    pub meshes: Vec<TriMesh>,
    /// Every placement of a mesh: objects, then area lights.
    pub instances: Vec<SceneInstance>,
    /// `None` when the scene has no triangles: every ray misses without any work.
    pub accel: Option<Accel>,
    /// Materials by `Surface::Material` index.
    pub materials: Vec<SurfaceMaterial>,
    /// Surfaces of OBJ material parts, per placement (see `SceneInstance::part_base`).
    pub part_surfaces: Vec<Surface>,
    /// Textures by index.
    pub textures: Textures,
    /// Per mesh: per-vertex tangents (xyz, and the bitangent's sign in w), derived from UVs
    /// only for meshes that normal-mapped objects use; empty otherwise.
    pub tangents: Vec<Vec<Vec4>>,
    /// Per mesh: its triangles' unit face normals for an unmoved placement, for the meshes
    /// some unmoved placement uses; empty otherwise (`face_normals`).
    pub face_normals: Vec<Vec<Vec3>>,
    /// The lights and their sampling tables.
    pub lights: Lights,
    /// How area lights are sampled (tests switch it).
    pub light_sampling: LightSampling,
    /// How direct light from area lights and the environment is sampled (tests switch it).
    pub strategy: DirectStrategy,
    /// Whether pixels may take a path specialised for the scene's features (tests switch it).
    pub shading_path: ShadingPath,
    /// How long the build took.
    pub timings: BuildTimings,
}

impl Scene {
    /// The acceleration structure's figures (zero without one).
    pub fn accel_stats(&self) -> AccelStats {
        self.accel.as_ref().map(Accel::stats).unwrap_or_default()
    }

    /// Memory per placement, for `--stats`: the scene's instance record plus what each
    /// placement adds to the acceleration structure (meshes are shared, not copied, in the BVH);
    /// `None` without instances.
    pub fn bytes_per_instance(&self) -> Option<f64> {
        let n = self.instances.len();
        let records = n * std::mem::size_of::<SceneInstance>();
        (n > 0).then(|| (records + self.accel_stats().instance_bytes) as f64 / n as f64)
    }

    /// Triangles over all instances (what the accel holds).
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.meshes[i.mesh as usize].triangles.len())
            .sum()
    }
}
