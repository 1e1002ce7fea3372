//! Meshes in the IR: where the triangles come from. Loading happens later, in `scene::build`.
//!
//! Syntax:
//! ```text
//! mesh tall  = obj("meshes/tall.obj")
//! mesh house = obj("house.obj") { material "roof tiles" slate  material glass clear  mtl false }
//! mesh tri   = inline { positions [(0,0,0) (1,0,0) (0,1,0)]  indices [0 1 2] }
//! mesh ball  = sphere { radius 1  segments 48 }
//! mesh gem   = icosphere { subdivisions 5  radius 0.6 }
//! mesh floor = quad { size (2, 2) }
//! mesh crate = box { size (1, 1, 1) }
//! ```

use std::path::PathBuf;

use glam::{Vec2, Vec3};
use serde::Serialize;

use crate::source::Span;

/// A file referenced by the scene, resolved relative to the `.scn` file that names it.
#[derive(Debug, Clone, Serialize)]
pub struct AssetPath {
    /// The path to read (the including file's directory joined with what was written).
    pub path: PathBuf,
    /// The string as written in the `.scn`.
    pub written: String,
    /// The string literal's span, so a later "file not found" points at it.
    pub span: Span,
}

/// A `mesh NAME = ...` declaration: where its triangles come from.
#[derive(Debug, Clone, Serialize)]
pub struct Mesh {
    /// The declared name (what `object { mesh NAME }` refers to).
    pub name: String,
    /// File, inline arrays or built-in shape.
    pub source: MeshSource,
    /// The declaration's span (diagnostics about the mesh as a whole point here).
    pub span: Span,
    /// Options of an `obj(...)` mesh; `None` when nothing was written (always for every other
    /// kind). Boxed and optional so that a mesh without them pays one word, not four; read
    /// them with [`Mesh::obj_options`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub obj: Option<Box<ObjOptions>>,
}

/// What [`Mesh::obj_options`] returns for a mesh without options.
static NO_OBJ_OPTIONS: ObjOptions = ObjOptions {
    ignore_mtl: false,
    materials: Vec::new(),
};

impl Mesh {
    /// The mesh's OBJ options (the default ones when nothing was written).
    pub fn obj_options(&self) -> &ObjOptions {
        self.obj.as_deref().unwrap_or(&NO_OBJ_OPTIONS)
    }
}

/// `obj("f.obj") { material OBJ_NAME SCN_MATERIAL ...  mtl false }`.
#[derive(Debug, Clone, Serialize, Default, PartialEq)]
pub struct ObjOptions {
    /// `mtl false`: the OBJ's material libraries are not read.
    pub ignore_mtl: bool,
    /// Faces whose `usemtl` is `obj_name` use the scene's material instead of the MTL's.
    pub materials: Vec<ObjMaterialOverride>,
}

/// One `material OBJ_NAME SCN_MATERIAL` entry of an `obj(...)` mesh.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ObjMaterialOverride {
    /// The material name as the OBJ's `usemtl` writes it.
    pub obj_name: String,
    /// The scene material that replaces it.
    pub material: super::MaterialId,
    /// The entry's span (an override no face uses is warned about here).
    pub span: Span,
}

impl ObjOptions {
    /// True when nothing was written (the IR dump leaves the options out then).
    pub fn is_default(&self) -> bool {
        *self == ObjOptions::default()
    }
}

/// Where a mesh's triangles come from.
#[derive(Debug, Clone, Serialize)]
pub enum MeshSource {
    /// A Wavefront OBJ file (triangulated on load; normals and UVs kept). Boxed, like
    /// `Inline`, so that the common built-in shapes keep the enum (and every [`Mesh`]) small.
    Obj(Box<AssetPath>),
    /// `inline { positions [...] indices [...] }`: arrays written in the scene (boxed: four
    /// `Vec`s would make every mesh of a generated scene of boxes 72 bytes larger).
    Inline(Box<InlineMesh>),
    /// `sphere`, `icosphere`, `quad` or `box`: tessellated at build time.
    Builtin(BuiltinShape),
}

/// Triangles written in the scene file. Validated: indices are in range, arrays are finite,
/// `normals` and `uvs` are empty or one per position.
#[derive(Debug, Clone, Serialize)]
pub struct InlineMesh {
    /// Vertex positions in the mesh's own space.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (not necessarily unit length), or empty for flat shading.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates, or empty.
    pub uvs: Vec<Vec2>,
    /// Triangles as three indices into `positions` (and `normals`/`uvs`).
    pub indices: Vec<[u32; 3]>,
}

/// Built-in tessellated shapes, centred at the origin in their own space.
#[derive(Debug, Clone, Copy, Serialize)]
pub enum BuiltinShape {
    /// A rectangle in the xz-plane facing +y, `size.x` by `size.y`; UVs span [0,1]².
    Quad {
        /// Extent along x and z.
        size: glam::Vec2,
    },
    /// An axis-aligned box of the given full extents; each face has its own UVs and normals.
    Box {
        /// Full extent along x, y and z.
        size: Vec3,
    },
    /// A UV sphere: `segments` around the equator, `segments / 2` rings.
    Sphere {
        /// Distance of every vertex from the centre.
        radius: f32,
        /// Vertices around the equator (at least 3).
        segments: u32,
    },
    /// A subdivided icosahedron, flat-shaded: `20 · 4^subdivisions` triangles, vertex for
    /// vertex the benchmark's `icosphere(subdivisions)` (bench/scenes/gen.py) scaled by `radius`.
    Icosphere {
        /// The circumradius: every vertex is at this distance from the centre.
        radius: f32,
        /// How many times each triangle was split into four (0 is the icosahedron).
        subdivisions: u32,
    },
}
