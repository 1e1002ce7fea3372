//! Language server: the kinds of `{ ... }` block, the keys each takes (the checker's word lists
//! in [`crate::check::vocabulary`], not a copy), and which kind of declared name a key's values
//! name (`object m { material NAME }` names a material).

use crate::check::vocabulary::{self as v, LightKind, MeshKind, TextureKind, Word};
use crate::syntax::DeclKind;

use super::symbols::SymbolKind;

/// What a block belongs to, which decides its keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlockKind {
    /// `camera NAME { ... }`.
    Camera,
    /// `transform { ... }`.
    Transform,
    /// `material NAME = phong { ... }`.
    Material,
    /// `texture NAME = checker { ... }`.
    CheckerTexture,
    /// `texture NAME = constant { ... }`.
    ConstantTexture,
    /// `texture NAME = image("file") { ... }`.
    ImageTexture,
    /// `mesh NAME = inline { ... }`.
    InlineMesh,
    /// `mesh NAME = sphere { ... }`.
    Sphere,
    /// `mesh NAME = icosphere { ... }`.
    Icosphere,
    /// `mesh NAME = quad { ... }`.
    Quad,
    /// `mesh NAME = box { ... }`.
    Box,
    /// `mesh NAME = obj("file") { ... }`.
    ObjMesh,
    /// `object MESH { ... }`.
    Object,
    /// `group NAME { ... }`: no keys, only `transform`, `object` and `group`.
    Group,
    /// `light NAME = point { ... }`.
    PointLight,
    /// `light NAME = area { ... }`.
    AreaLight,
    /// `light NAME = environment { ... }`.
    EnvironmentLight,
    /// `render { ... }`.
    Render,
    /// The block of a declaration whose kind is unknown (`material m = nope { ... }`).
    Unknown,
}

impl BlockKind {
    /// The block of `material`/`texture`/`mesh`/`light NAME = KIND { ... }`.
    pub fn of_decl(kind: DeclKind, ctor: &str) -> BlockKind {
        match kind {
            DeclKind::Material => match v::MaterialKind::from_word(ctor) {
                Some(v::MaterialKind::Phong) => BlockKind::Material,
                None => BlockKind::Unknown,
            },
            DeclKind::Texture => match TextureKind::from_word(ctor) {
                Some(TextureKind::Image) => BlockKind::ImageTexture,
                Some(TextureKind::Checker) => BlockKind::CheckerTexture,
                Some(TextureKind::Constant) => BlockKind::ConstantTexture,
                None => BlockKind::Unknown,
            },
            DeclKind::Mesh => match MeshKind::from_word(ctor) {
                Some(MeshKind::Obj) => BlockKind::ObjMesh,
                Some(MeshKind::Inline) => BlockKind::InlineMesh,
                Some(MeshKind::Sphere) => BlockKind::Sphere,
                Some(MeshKind::Icosphere) => BlockKind::Icosphere,
                Some(MeshKind::Quad) => BlockKind::Quad,
                Some(MeshKind::Box) => BlockKind::Box,
                None => BlockKind::Unknown,
            },
            DeclKind::Light => match LightKind::from_word(ctor) {
                Some(LightKind::Point) => BlockKind::PointLight,
                Some(LightKind::Area) => BlockKind::AreaLight,
                Some(LightKind::Environment) => BlockKind::EnvironmentLight,
                None => BlockKind::Unknown,
            },
        }
    }

    /// The property keys the checker accepts in this block.
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            BlockKind::Camera => v::CAMERA_KEYS,
            BlockKind::Transform => v::TRANSFORM_KEYS,
            BlockKind::Material => v::MATERIAL_KEYS,
            BlockKind::CheckerTexture => v::CHECKER_KEYS,
            BlockKind::ConstantTexture => v::CONSTANT_TEXTURE_KEYS,
            BlockKind::ImageTexture => v::IMAGE_TEXTURE_KEYS,
            BlockKind::InlineMesh => v::INLINE_MESH_KEYS,
            BlockKind::Sphere => v::SPHERE_KEYS,
            BlockKind::Icosphere => v::ICOSPHERE_KEYS,
            BlockKind::Quad => v::QUAD_KEYS,
            BlockKind::Box => v::BOX_KEYS,
            BlockKind::ObjMesh => v::OBJ_MESH_KEYS,
            BlockKind::Object => v::OBJECT_KEYS,
            BlockKind::PointLight => v::POINT_LIGHT_KEYS,
            BlockKind::AreaLight => v::AREA_LIGHT_KEYS,
            BlockKind::EnvironmentLight => v::ENVIRONMENT_LIGHT_KEYS,
            BlockKind::Render => v::RENDER_KEYS,
            BlockKind::Group | BlockKind::Unknown => &[],
        }
    }

    /// The kind of declared name the `index`-th value (from 0) of `key` names in this block, if
    /// it names one: what the checker resolves it in.
    pub fn expected(self, key: &str, index: usize) -> Option<Expected> {
        let kind = match (self, key, index) {
            (BlockKind::Object, "material", _) | (BlockKind::ObjMesh, "material", 1) => {
                SymbolKind::Material
            }
            (BlockKind::AreaLight, "mesh", _) => SymbolKind::Mesh,
            (BlockKind::Render, "camera", _) => SymbolKind::Camera,
            (BlockKind::Material, "normal_map", _) => SymbolKind::Texture,
            // A colour or number, or a texture: a constant of that name wins (`texture_ref`).
            (BlockKind::Material, "diffuse" | "specular" | "shininess", _) => {
                return Some(Expected::ConstantOrTexture)
            }
            _ => return None,
        };
        Some(Expected::Name(kind))
    }
}

/// Whether `word` is a keyword: one that starts a statement (the grammar's list), or
/// `transform`.
pub fn is_keyword(word: &str) -> bool {
    crate::syntax::scan::STATEMENT_KEYWORDS.contains(&word) || word == "transform"
}

/// What a bare name in a value position refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expected {
    /// A declared name of this kind only.
    Name(SymbolKind),
    /// A constant if one has the name, else a texture.
    ConstantOrTexture,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declarations_pick_their_block_and_keys() {
        assert_eq!(
            BlockKind::of_decl(DeclKind::Mesh, "obj"),
            BlockKind::ObjMesh
        );
        assert_eq!(
            BlockKind::of_decl(DeclKind::Light, "nope"),
            BlockKind::Unknown
        );
        assert!(BlockKind::Render.keys().contains(&"camera"));
        assert_eq!(
            BlockKind::ObjMesh.expected("material", 1),
            Some(Expected::Name(SymbolKind::Material))
        );
        assert_eq!(BlockKind::ObjMesh.expected("material", 0), None);
    }
}
