//! Stage 2, check: the closed word lists of the language, in one place.
//!
//! Every block kind's property keys, the kinds after `=` in a declaration (`phong`, `sphere`,
//! `image("file")`, ...), the bare words some keys take (`wrap repeat`, `tonemap filmic`) and the
//! number units (`30deg`). The checker splits blocks and validates words with these lists, and
//! the editor grammars under `editors/` are tested against them (tests/editors_drift.rs), so a
//! key added here without a highlighting rule fails a test.

pub use super::eval::FUNCTIONS;
pub use super::transform::TRANSFORM_KEYS;
use crate::ir;

/// A closed set of words that converts to an enum: the words, and the conversions both ways.
/// Implemented only through [`words!`], so the word list the checker validates against and
/// the conversion are one table and cannot disagree.
pub trait Word: Sized + Copy + 'static {
    /// Every word, in the order the language reference lists them.
    const WORDS: &'static [&'static str];
    /// The value a word names; `None` for a word not in [`Word::WORDS`].
    fn from_word(word: &str) -> Option<Self>;
    /// The word that names this value (exhaustive: a new variant needs a word).
    fn as_word(self) -> &'static str;
}

/// Defines a `pub const` word list and the [`Word`] conversions of `$ty` from one table of
/// `"word" => Variant` pairs. `as_word` is an exhaustive match, so a variant added to the
/// enum without a word does not compile; `from_word` rejects every word not in the table
/// (the caller reports it as an unknown choice).
macro_rules! words {
    ($(#[$doc:meta])* $list:ident: $ty:ty { $($word:literal => $variant:ident,)* }) => {
        $(#[$doc])*
        pub const $list: &[&str] = &[$($word,)*];

        impl Word for $ty {
            const WORDS: &'static [&'static str] = $list;

            fn from_word(word: &str) -> Option<Self> {
                match word {
                    $($word => Some(<$ty>::$variant),)*
                    _ => None,
                }
            }

            fn as_word(self) -> &'static str {
                match self {
                    $(<$ty>::$variant => $word,)*
                }
            }
        }
    };
}

/// Unit suffixes of numbers: `30deg`, `0.5rad`.
pub const UNITS: &[&str] = &["deg", "rad"];
/// Literal words that are values wherever an expression is: `visible true`.
pub const BOOLEANS: &[&str] = &["true", "false"];

/// `camera NAME { ... }`.
pub const CAMERA_KEYS: &[&str] = &["eye", "target", "up", "fov"];
words! {
    /// `material NAME = KIND { ... }`.
    MATERIAL_KINDS: MaterialKind { "phong" => Phong, }
}
/// `material NAME = phong { ... }`.
pub const MATERIAL_KEYS: &[&str] = &[
    "diffuse",
    "specular",
    "shininess",
    "ambient",
    "normal_map",
    "normal_strength",
    "normal_green",
];
words! {
    /// `normal_green opengl`: which way a normal map's green channel points.
    GREEN_WORDS: ir::GreenConvention { "opengl" => OpenGl, "directx" => DirectX, }
}
words! {
    /// `texture NAME = KIND ...`.
    TEXTURE_KINDS: TextureKind { "image" => Image, "checker" => Checker, "constant" => Constant, }
}
/// `texture NAME = checker { ... }`.
pub const CHECKER_KEYS: &[&str] = &["even", "odd", "scale"];
/// `texture NAME = constant { ... }`.
pub const CONSTANT_TEXTURE_KEYS: &[&str] = &["color"];
/// `texture NAME = image("file") { ... }`.
pub const IMAGE_TEXTURE_KEYS: &[&str] = &["wrap", "filter", "encoding"];
words! {
    /// `wrap repeat`: texture coordinates outside [0, 1].
    WRAP_WORDS: ir::WrapMode { "repeat" => Repeat, "clamp" => Clamp, "mirror" => Mirror, }
}
words! {
    /// `filter anisotropic`: texture filtering.
    FILTER_WORDS: ir::Filter {
        "nearest" => Nearest,
        "bilinear" => Bilinear,
        "trilinear" => Trilinear,
        "anisotropic" => Anisotropic,
    }
}
words! {
    /// `encoding data`: how an image's values are read.
    ENCODING_WORDS: ir::TextureEncoding { "srgb" => Srgb, "data" => Linear, }
}
words! {
    /// `mesh NAME = KIND ...`.
    MESH_KINDS: MeshKind {
        "obj" => Obj,
        "inline" => Inline,
        "sphere" => Sphere,
        "icosphere" => Icosphere,
        "quad" => Quad,
        "box" => Box,
    }
}
/// `mesh NAME = inline { ... }`.
pub const INLINE_MESH_KEYS: &[&str] = &["positions", "normals", "uvs", "indices"];
/// `mesh NAME = sphere { ... }`.
pub const SPHERE_KEYS: &[&str] = &["radius", "segments"];
/// `mesh ball = icosphere { subdivisions 5  radius 0.6 }`.
pub const ICOSPHERE_KEYS: &[&str] = &["subdivisions", "radius"];
/// `mesh NAME = quad { ... }`.
pub const QUAD_KEYS: &[&str] = &["size"];
/// `mesh NAME = box { ... }`.
pub const BOX_KEYS: &[&str] = &["size"];
/// `object MESH { ... }`.
pub const OBJECT_KEYS: &[&str] = &["material"];
/// `mesh NAME = obj("file") { ... }`.
pub const OBJ_MESH_KEYS: &[&str] = &["material", "mtl"];
words! {
    /// `light NAME = KIND { ... }`.
    LIGHT_KINDS: LightKind { "point" => Point, "area" => Area, "environment" => Environment, }
}
/// `light NAME = point { ... }`.
pub const POINT_LIGHT_KEYS: &[&str] = &["position", "intensity"];
/// `light NAME = area { ... }`.
pub const AREA_LIGHT_KEYS: &[&str] = &["quad", "mesh", "radiance", "two_sided", "samples"];
/// `light NAME = environment { ... }`.
pub const ENVIRONMENT_LIGHT_KEYS: &[&str] = &["image", "color", "intensity", "rotate", "visible"];
/// `render { ... }`.
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
words! {
    /// `tonemap filmic`.
    TONEMAP_WORDS: ir::ToneMap { "clamp" => Clamp, "reinhard" => Reinhard, "filmic" => Filmic, }
}
words! {
    /// `samples rgss 4`: the sample pattern.
    SAMPLE_PATTERN_WORDS: ir::SamplePattern { "rgss" => RotatedGrid, "grid" => Grid, }
}
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

/// The kinds of material (`material NAME = phong { ... }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MaterialKind {
    /// `phong { diffuse ... specular ... }`.
    Phong,
}

/// The kinds of texture (`texture NAME = checker { ... }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureKind {
    /// `image("file.png") { ... }`.
    Image,
    /// `checker { even ... odd ... scale ... }`.
    Checker,
    /// `constant { color ... }`.
    Constant,
}

/// The kinds of mesh (`mesh NAME = sphere { ... }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshKind {
    /// `obj("file.obj") { ... }`.
    Obj,
    /// `inline { positions ... indices ... }`.
    Inline,
    /// `sphere { radius ... segments ... }`.
    Sphere,
    /// `icosphere { subdivisions ... radius ... }`.
    Icosphere,
    /// `quad { size ... }`.
    Quad,
    /// `box { size ... }`.
    Box,
}

/// The kinds of light (`light NAME = area { ... }`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightKind {
    /// `point { position ... intensity ... }`.
    Point,
    /// `area { quad ... | mesh ...  radiance ... }`.
    Area,
    /// `environment { image(...) | color ... }`.
    Environment,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every word converts to a value that converts back to it, and nothing else converts.
    fn round_trips<T: Word + PartialEq + std::fmt::Debug>() {
        for w in T::WORDS {
            let v = T::from_word(w).unwrap_or_else(|| panic!("`{w}` converts to nothing"));
            assert_eq!(v.as_word(), *w);
        }
        assert_eq!(T::from_word("no such word"), None);
    }

    #[test]
    fn every_word_list_round_trips() {
        round_trips::<MaterialKind>();
        round_trips::<TextureKind>();
        round_trips::<MeshKind>();
        round_trips::<LightKind>();
        round_trips::<ir::GreenConvention>();
        round_trips::<ir::WrapMode>();
        round_trips::<ir::Filter>();
        round_trips::<ir::TextureEncoding>();
        round_trips::<ir::ToneMap>();
        round_trips::<ir::SamplePattern>();
    }

    #[test]
    fn quality_words_are_the_presets() {
        for w in QUALITY_WORDS {
            let q = ir::Quality::from_name(w).unwrap_or_else(|| panic!("`{w}`"));
            assert_eq!(q.name(), *w);
        }
        for q in ir::Quality::ALL {
            assert!(QUALITY_WORDS.contains(&q.name()));
        }
    }
}
