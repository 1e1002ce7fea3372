//! Stage 2, check: the closed word lists of the language, in one place.
//!
//! Every block kind's property keys, the kinds after `=` in a declaration (`phong`, `sphere`,
//! `image("file")`, ...), the bare words some keys take (`wrap repeat`, `tonemap filmic`) and the
//! number units (`30deg`). The checker splits blocks and validates words with these lists, and
//! the editor grammars under `editors/` are tested against them (tests/editors_drift.rs), so a
//! key added here without a highlighting rule fails a test.

pub use super::eval::FUNCTIONS;
pub use super::transform::TRANSFORM_KEYS;

/// Unit suffixes of numbers: `30deg`, `0.5rad`.
pub const UNITS: &[&str] = &["deg", "rad"];
/// Literal words that are values wherever an expression is: `visible true`.
pub const BOOLEANS: &[&str] = &["true", "false"];

pub const CAMERA_KEYS: &[&str] = &["eye", "target", "up", "fov"];
pub const MATERIAL_KINDS: &[&str] = &["phong"];
pub const MATERIAL_KEYS: &[&str] = &[
    "diffuse",
    "specular",
    "shininess",
    "ambient",
    "normal_map",
    "normal_strength",
    "normal_green",
];
pub const GREEN_WORDS: &[&str] = &["opengl", "directx"];
pub const TEXTURE_KINDS: &[&str] = &["image", "checker", "constant"];
pub const CHECKER_KEYS: &[&str] = &["even", "odd", "scale"];
pub const CONSTANT_TEXTURE_KEYS: &[&str] = &["color"];
pub const IMAGE_TEXTURE_KEYS: &[&str] = &["wrap", "filter", "encoding"];
pub const WRAP_WORDS: &[&str] = &["repeat", "clamp", "mirror"];
pub const FILTER_WORDS: &[&str] = &["nearest", "bilinear", "trilinear"];
pub const ENCODING_WORDS: &[&str] = &["srgb", "data"];
pub const MESH_KINDS: &[&str] = &["obj", "inline", "sphere", "icosphere", "quad", "box"];
pub const INLINE_MESH_KEYS: &[&str] = &["positions", "normals", "uvs", "indices"];
pub const SPHERE_KEYS: &[&str] = &["radius", "segments"];
/// `mesh ball = icosphere { subdivisions 5  radius 0.6 }`.
pub const ICOSPHERE_KEYS: &[&str] = &["subdivisions", "radius"];
pub const QUAD_KEYS: &[&str] = &["size"];
pub const BOX_KEYS: &[&str] = &["size"];
pub const OBJECT_KEYS: &[&str] = &["material"];
pub const OBJ_MESH_KEYS: &[&str] = &["material", "mtl"];
pub const LIGHT_KINDS: &[&str] = &["point", "area", "environment"];
pub const POINT_LIGHT_KEYS: &[&str] = &["position", "intensity"];
pub const AREA_LIGHT_KEYS: &[&str] = &["quad", "mesh", "radiance", "two_sided", "samples"];
pub const ENVIRONMENT_LIGHT_KEYS: &[&str] = &["image", "color", "intensity", "rotate", "visible"];
pub const RENDER_KEYS: &[&str] = &[
    "resolution",
    "samples",
    "light_samples",
    "seed",
    "camera",
    "output",
    "exposure",
    "tonemap",
    "quality",
    "noise",
    "max_samples",
];
pub const TONEMAP_WORDS: &[&str] = &["clamp", "reinhard", "filmic"];
pub const SAMPLE_PATTERN_WORDS: &[&str] = &["rgss", "grid"];
/// `render { quality preview }`: the presets (`ir::Quality`).
pub const QUALITY_WORDS: &[&str] = crate::ir::Quality::NAMES;

/// Every block's property keys (a key may belong to several blocks).
pub const PROPERTY_KEYS: &[&[&str]] = &[
    CAMERA_KEYS,
    TRANSFORM_KEYS,
    MATERIAL_KEYS,
    CHECKER_KEYS,
    CONSTANT_TEXTURE_KEYS,
    IMAGE_TEXTURE_KEYS,
    INLINE_MESH_KEYS,
    SPHERE_KEYS,
    ICOSPHERE_KEYS,
    QUAD_KEYS,
    BOX_KEYS,
    OBJECT_KEYS,
    OBJ_MESH_KEYS,
    POINT_LIGHT_KEYS,
    AREA_LIGHT_KEYS,
    ENVIRONMENT_LIGHT_KEYS,
    RENDER_KEYS,
];
/// Every kind written after `=` in a declaration.
pub const KINDS: &[&[&str]] = &[MATERIAL_KINDS, TEXTURE_KINDS, MESH_KINDS, LIGHT_KINDS];
/// Every bare word a key takes as its value.
pub const WORDS: &[&[&str]] = &[
    GREEN_WORDS,
    WRAP_WORDS,
    FILTER_WORDS,
    ENCODING_WORDS,
    TONEMAP_WORDS,
    SAMPLE_PATTERN_WORDS,
    QUALITY_WORDS,
];
