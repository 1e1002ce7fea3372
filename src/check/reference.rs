//! Stage 2, check: the language reference's tables as data — every block's properties (type,
//! unit, default, one-line description) and every built-in function and unit.
//!
//! This is the one copy: `grammar/README.md`'s property and function tables are rendered from it
//! ([`section_table`], [`functions_table`]; tests/frontend_reference.rs fails when the README
//! differs, and `SCNC_BLESS=1` rewrites the README's tables), the language server's hover and
//! completion show it, and a unit test holds its keys equal to the checker's key lists in
//! [`super::vocabulary`]. The rows themselves are in `reference_table.rs`.

use super::transform::TRANSFORM_KEYS;
use super::vocabulary as v;

pub use super::reference_table::{FUNCTIONS_DOC, PROPERTIES, UNITS_DOC};

/// A kind of `{ ... }` block, with the keys the checker splits it by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Block {
    /// `camera NAME { ... }`.
    Camera,
    /// `transform { ... }`.
    Transform,
    /// `material NAME = phong { ... }`.
    Phong,
    /// `texture NAME = image("file") { ... }`.
    ImageTexture,
    /// `texture NAME = checker { ... }`.
    Checker,
    /// `texture NAME = constant { ... }`.
    ConstantTexture,
    /// `mesh NAME = obj("file") { ... }`.
    ObjMesh,
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
    /// `object MESH { ... }`.
    Object,
    /// `group NAME { ... }` (nested blocks only).
    Group,
    /// `light NAME = point { ... }`.
    PointLight,
    /// `light NAME = area { ... }`.
    AreaLight,
    /// `light NAME = environment { ... }`.
    EnvironmentLight,
    /// `render { ... }`.
    Render,
}

/// One property of one block: a row of a reference table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Property {
    /// The block it belongs to.
    pub block: Block,
    /// The key as written.
    pub key: &'static str,
    /// How the key cell shows it when more than the key (`quad P0 P1 P2 P3`); empty otherwise.
    pub form: &'static str,
    /// Its type, in the reference's words (Markdown).
    pub ty: &'static str,
    /// The unit its value is in; empty when it has none.
    pub unit: &'static str,
    /// Its default, `required`, or how it is otherwise decided.
    pub default: &'static str,
    /// One line saying what it does.
    pub notes: &'static str,
}

/// One row of the function table: functions documented together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FunctionDoc {
    /// The function names.
    pub names: &'static [&'static str],
    /// How the row shows them (Markdown).
    pub forms: &'static str,
    /// What they take and give.
    pub takes: &'static str,
}

impl Block {
    /// Every block kind, in reference order.
    pub const ALL: &'static [Block] = &[
        Block::Camera,
        Block::Transform,
        Block::Phong,
        Block::ImageTexture,
        Block::Checker,
        Block::ConstantTexture,
        Block::ObjMesh,
        Block::InlineMesh,
        Block::Sphere,
        Block::Icosphere,
        Block::Quad,
        Block::Box,
        Block::Object,
        Block::Group,
        Block::PointLight,
        Block::AreaLight,
        Block::EnvironmentLight,
        Block::Render,
    ];

    /// The checker's keys of this block ([`super::vocabulary`]).
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            Block::Camera => v::CAMERA_KEYS,
            Block::Transform => TRANSFORM_KEYS,
            Block::Phong => v::MATERIAL_KEYS,
            Block::ImageTexture => v::IMAGE_TEXTURE_KEYS,
            Block::Checker => v::CHECKER_KEYS,
            Block::ConstantTexture => v::CONSTANT_TEXTURE_KEYS,
            Block::ObjMesh => v::OBJ_MESH_KEYS,
            Block::InlineMesh => v::INLINE_MESH_KEYS,
            Block::Sphere => v::SPHERE_KEYS,
            Block::Icosphere => v::ICOSPHERE_KEYS,
            Block::Quad => v::QUAD_KEYS,
            Block::Box => v::BOX_KEYS,
            Block::Object => v::OBJECT_KEYS,
            Block::Group => &[],
            Block::PointLight => v::POINT_LIGHT_KEYS,
            Block::AreaLight => v::AREA_LIGHT_KEYS,
            Block::EnvironmentLight => v::ENVIRONMENT_LIGHT_KEYS,
            Block::Render => v::RENDER_KEYS,
        }
    }

    /// The blocks that may be nested in this one (`transform`, `object`, `group`).
    pub fn nested(self) -> &'static [&'static str] {
        match self {
            Block::Camera | Block::Object | Block::AreaLight => &["transform"],
            Block::Group => &["transform", "object", "group"],
            _ => &[],
        }
    }

    /// Which keys may be given more than once.
    pub fn repeatable(self) -> &'static [&'static str] {
        match self {
            Block::Transform => TRANSFORM_KEYS,
            Block::ObjMesh => &["material"],
            Block::Render => &["output"],
            _ => &[],
        }
    }

    /// The reference section (a `##` heading of grammar/README.md) that documents it.
    pub fn section(self) -> &'static str {
        match self {
            Block::Camera => "camera",
            Block::Transform => "transform",
            Block::Phong => "material",
            Block::ImageTexture | Block::Checker | Block::ConstantTexture => "texture",
            Block::ObjMesh
            | Block::InlineMesh
            | Block::Sphere
            | Block::Icosphere
            | Block::Quad
            | Block::Box => "mesh",
            Block::Object | Block::Group => "object",
            Block::PointLight | Block::AreaLight | Block::EnvironmentLight => "light",
            Block::Render => "render",
        }
    }

    /// The kind word after `=` that opens it (`sphere`); empty for blocks without one.
    pub fn kind(self) -> &'static str {
        match self {
            Block::Phong => "phong",
            Block::ImageTexture => "image",
            Block::Checker => "checker",
            Block::ConstantTexture => "constant",
            Block::ObjMesh => "obj",
            Block::InlineMesh => "inline",
            Block::Sphere => "sphere",
            Block::Icosphere => "icosphere",
            Block::Quad => "quad",
            Block::Box => "box",
            Block::PointLight => "point",
            Block::AreaLight => "area",
            Block::EnvironmentLight => "environment",
            Block::Camera | Block::Transform | Block::Object | Block::Group | Block::Render => "",
        }
    }

    /// How the block is named in prose: "a sphere mesh".
    pub fn what(self) -> &'static str {
        match self {
            Block::Camera => "a camera",
            Block::Transform => "a transform",
            Block::Phong => "a phong material",
            Block::ImageTexture => "an image texture",
            Block::Checker => "a checker texture",
            Block::ConstantTexture => "a constant texture",
            Block::ObjMesh => "an obj mesh",
            Block::InlineMesh => "an inline mesh",
            Block::Sphere => "a sphere mesh",
            Block::Icosphere => "an icosphere mesh",
            Block::Quad => "a quad mesh",
            Block::Box => "a box mesh",
            Block::Object => "an object",
            Block::Group => "a group",
            Block::PointLight => "a point light",
            Block::AreaLight => "an area light",
            Block::EnvironmentLight => "an environment light",
            Block::Render => "the render settings",
        }
    }

    /// The block a statement opens: its keyword (`mesh`) and the kind word after `=` (`sphere`;
    /// empty for `camera`, `object`, `group`, `render`, `transform`).
    pub fn of_statement(keyword: &str, kind: &str) -> Option<Block> {
        let simple = match keyword {
            "camera" => Some(Block::Camera),
            "object" => Some(Block::Object),
            "group" => Some(Block::Group),
            "render" => Some(Block::Render),
            "transform" => Some(Block::Transform),
            _ => None,
        };
        if simple.is_some() {
            return simple;
        }
        let section = match keyword {
            "material" => "material",
            "texture" => "texture",
            "mesh" => "mesh",
            "light" => "light",
            _ => return None,
        };
        Block::ALL
            .iter()
            .copied()
            .find(|b| b.section() == section && b.kind() == kind && !kind.is_empty())
    }

    /// Every documented property of this block, in reference order.
    pub fn properties(self) -> impl Iterator<Item = &'static Property> {
        PROPERTIES.iter().filter(move |p| p.block == self)
    }

    /// The documented property `key` of this block.
    pub fn property(self, key: &str) -> Option<&'static Property> {
        self.properties().find(|p| p.key == key)
    }
}

impl Property {
    /// The key cell of its table row: the form, or the key in backticks.
    pub fn key_cell(&self) -> String {
        if self.form.is_empty() {
            format!("`{}`", self.key)
        } else {
            self.form.to_string()
        }
    }

    /// Its documentation in Markdown (hover and completion): type, unit, default, description.
    pub fn markdown(&self) -> String {
        let mut facts = vec![format!("type: {}", self.ty)];
        if !self.unit.is_empty() {
            facts.push(format!("unit: {}", self.unit));
        }
        if !self.default.is_empty() {
            facts.push(format!("default: {}", self.default));
        }
        let mut out = format!(
            "{} in {}\n\n{}",
            self.key_cell(),
            self.block.what(),
            facts.join(" · ")
        );
        if !self.notes.is_empty() {
            out.push_str("\n\n");
            out.push_str(self.notes);
        }
        out
    }
}

/// The documentation of a built-in function.
pub fn function_doc(name: &str) -> Option<&'static FunctionDoc> {
    FUNCTIONS_DOC.iter().find(|f| f.names.contains(&name))
}

/// The documentation of a unit suffix (`deg`).
pub fn unit_doc(unit: &str) -> Option<&'static str> {
    UNITS_DOC.iter().find(|(u, _)| *u == unit).map(|(_, d)| *d)
}

/// The Markdown property table of one section of grammar/README.md (`camera`, `light`, ...):
/// a `Kind` column when the section has several block kinds.
pub fn section_table(section: &str) -> String {
    let blocks: Vec<Block> = Block::ALL
        .iter()
        .copied()
        .filter(|b| b.section() == section && b.properties().next().is_some())
        .collect();
    let with_kind = blocks.len() > 1;
    let mut out = String::new();
    if with_kind {
        out.push_str("| Kind | Key | Type | Unit | Default | Notes |\n|---|---|---|---|---|---|\n");
    } else {
        out.push_str("| Key | Type | Unit | Default | Notes |\n|---|---|---|---|---|\n");
    }
    for block in blocks {
        for (i, p) in block.properties().enumerate() {
            if with_kind {
                let kind = if i == 0 {
                    kind_cell(block)
                } else {
                    String::new()
                };
                out.push_str(&format!("| {kind} "));
            }
            out.push_str(&format!(
                "| {} | {} | {} | {} | {} |\n",
                p.key_cell(),
                p.ty,
                p.unit,
                p.default,
                p.notes
            ));
        }
    }
    out
}

/// The Kind cell of a block's first row: `image("file")` for a kind called with a file.
fn kind_cell(block: Block) -> String {
    match block {
        Block::ImageTexture | Block::ObjMesh => format!("`{}(\"file\")`", block.kind()),
        _ => format!("`{}`", block.kind()),
    }
}

/// The Markdown function table of grammar/README.md.
pub fn functions_table() -> String {
    let mut out = String::from("| Function | Takes → gives |\n|---|---|\n");
    for f in FUNCTIONS_DOC {
        out.push_str(&format!("| {} | {} |\n", f.forms, f.takes));
    }
    out
}

/// Every section of grammar/README.md with a property table.
pub const SECTIONS: &[&str] = &[
    "camera",
    "transform",
    "material",
    "texture",
    "mesh",
    "object",
    "light",
    "render",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn documented_keys_are_the_checkers_keys() {
        for block in Block::ALL {
            let documented: Vec<&str> = block
                .properties()
                .map(|p| p.key)
                .filter(|k| !block.nested().contains(k))
                .collect();
            assert_eq!(documented, block.keys(), "{block:?}");
        }
    }

    #[test]
    fn every_function_and_unit_is_documented_once() {
        let mut documented: Vec<&str> = FUNCTIONS_DOC
            .iter()
            .flat_map(|f| f.names)
            .copied()
            .collect();
        documented.sort_unstable();
        let mut functions = super::super::FUNCTIONS.to_vec();
        functions.sort_unstable();
        assert_eq!(documented, functions);
        let units: Vec<&str> = UNITS_DOC.iter().map(|(u, _)| *u).collect();
        assert_eq!(units, v::UNITS);
    }

    #[test]
    fn statements_open_their_blocks() {
        assert_eq!(Block::of_statement("mesh", "sphere"), Some(Block::Sphere));
        assert_eq!(Block::of_statement("camera", ""), Some(Block::Camera));
        assert_eq!(Block::of_statement("mesh", ""), None);
        assert_eq!(Block::of_statement("light", "phong"), None);
        for b in Block::ALL {
            let keyword = match b.section() {
                "object" if *b == Block::Group => "group",
                s => s,
            };
            assert_eq!(Block::of_statement(keyword, b.kind()), Some(*b));
        }
    }
}
