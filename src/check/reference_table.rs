//! Stage 2, check: the rows of the language reference's tables (see `reference.rs`, which
//! renders them into grammar/README.md and serves them to the language server).
//!
//! One row per property: `"key" "form"` (the key cell when it shows more than the key), then
//! type, unit, default and a one-line description, all Markdown as the README shows them. A row
//! whose key is a nested block (`transform`) documents where that block may stand.

use super::reference::{Block, FunctionDoc, Property};

macro_rules! properties {
    ($($block:ident { $($key:literal $form:literal => $ty:literal, $unit:literal, $default:literal, $notes:literal;)* })*) => {
        /// Every property of every block, grouped by block in reference order.
        pub const PROPERTIES: &[Property] = &[$($(Property {
            block: Block::$block,
            key: $key,
            form: $form,
            ty: $ty,
            unit: $unit,
            default: $default,
            notes: $notes,
        },)*)*];
    };
}

properties! {
    Camera {
        "eye" "" => "3-vector", "scene units", "required (or `transform`)", "camera position";
        "target" "" => "3-vector", "scene units", "required (or `transform`)", "point looked at; must differ from `eye`";
        "up" "" => "3-vector", "", "`(0, 1, 0)`", "must not be parallel to the view direction";
        "fov" "" => "angle", "`deg` or `rad`", "`40deg`", "vertical field of view, in (0deg, 180deg) exclusive";
        "transform" "`transform { }`" => "block", "", "", "instead of eye/target/up: the camera sits at its local origin looking down local +z with +y up";
    }
    Transform {
        "translate" "`translate (x, y, z)`" => "3-vector", "scene units", "", "moves by the vector";
        "rotate" "`rotate AXIS ANGLE`" => "axis and angle", "`deg` or `rad`", "", "AXIS is `x`, `y`, `z` or a 3-vector (normalised); right-handed about the axis";
        "scale" "`scale s` or `scale (sx, sy, sz)`" => "number or 3-vector", "", "", "scales about the origin; no factor may be 0";
        "look_at" "`look_at EYE TARGET UP`" => "three 3-vectors", "scene units", "", "local +z towards TARGET, +y towards UP, origin at EYE";
        "matrix" "`matrix [m00 m01 m02 m03  m10 ...  m33]`" => "array of 16 numbers", "", "", "row-major, invertible";
    }
    Phong {
        "diffuse" "" => "colour or texture name", "", "`0.5`", "albedo, each channel in [0, 1]";
        "specular" "" => "colour or texture name", "", "`0`", "albedo at normal incidence, in [0, 1]";
        "shininess" "" => "number or texture name", "", "`32`", "Phong exponent n ≥ 0 (texture: red channel)";
        "ambient" "" => "colour", "W/(m²·sr)", "`0`", "radiance added unconditionally";
        "normal_map" "" => "texture name", "", "none", "tangent-space normals (use `encoding data`; a warning otherwise)";
        "normal_strength" "" => "number", "", "`1`", "0 = no effect, 1 = as authored (0..16)";
        "normal_green" "" => "`opengl` \\| `directx`", "", "`opengl`", "direction of the green channel";
    }
    ImageTexture {
        "wrap" "" => "`repeat` \\| `clamp` \\| `mirror`", "", "`repeat`", "what lies outside UV [0, 1]";
        "filter" "" => "`nearest` \\| `bilinear` \\| `trilinear` \\| `anisotropic`", "", "`anisotropic`", "how texels are filtered (below)";
        "encoding" "" => "`srgb` (colour) \\| `data` (linear)", "", "`srgb`", "how the image's values are read";
    }
    Checker {
        "even" "" => "colour", "", "`0.8`", "colour of the even squares";
        "odd" "" => "colour", "", "`0.2`", "colour of the odd squares";
        "scale" "" => "number > 0", "squares per UV unit", "`4`", "how fine the board is";
    }
    ConstantTexture {
        "color" "" => "colour", "", "`0.5`", "the colour everywhere";
    }
    ObjMesh {
        "material" "" => "OBJ material name (string or name), then a material", "", "none", "repeatable: faces with that `usemtl` use the scene's material instead";
        "mtl" "" => "`true` \\| `false`", "", "`true`", "`false`: the OBJ's `mtllib` files are not read";
    }
    InlineMesh {
        "positions" "" => "array of `(x, y, z)`", "scene units", "required", "the vertices";
        "normals" "" => "array of `(x, y, z)`", "", "none", "one per position, or none";
        "uvs" "" => "array of `(u, v)`", "", "none", "one per position, or none";
        "indices" "" => "array of whole numbers", "", "required", "three per triangle, each < number of positions; `(a b c)` grouping allowed";
    }
    Sphere {
        "radius" "" => "number > 0", "scene units", "`1`", "UV sphere centred at the origin";
        "segments" "" => "whole number 3..=4096", "", "`32`", "around the equator; `segments/2` rings";
    }
    Icosphere {
        "subdivisions" "" => "whole number 0..=8", "", "`3`", "`20 · 4^subdivisions` flat-shaded triangles: the icosahedron split that many times, vertex for vertex the benchmark's `icosphere(N)` (no normals, no UVs)";
        "radius" "" => "number > 0", "scene units", "`1`", "every vertex at this distance from the centre";
    }
    Quad {
        "size" "" => "2-vector or number > 0", "scene units", "`(1, 1)`", "in the xz-plane facing +y, centred";
    }
    Box {
        "size" "" => "3-vector or number > 0", "scene units", "`(1, 1, 1)`", "full extents, centred";
    }
    Object {
        "material" "`material NAME`" => "material name", "", "required", "how the mesh is shaded (OBJ materials aside)";
        "transform" "`transform { }`" => "block", "", "identity", "places the mesh";
    }
    PointLight {
        "position" "" => "3-vector", "scene units", "required", "where the light is";
        "intensity" "" => "colour", "W/sr", "`1`", "radiant intensity per channel";
    }
    AreaLight {
        "quad" "`quad P0 P1 P2 P3`" => "four 3-vectors", "scene units", "one of quad/mesh", "emits from the counter-clockwise side of P0→P1→P2";
        "mesh" "`mesh NAME`" => "mesh name", "", "one of quad/mesh", "every triangle emits";
        "transform" "`transform { }`" => "block", "", "identity", "places the shape";
        "radiance" "" => "colour", "W/(m²·sr)", "required", "emitted radiance, non-negative";
        "two_sided" "" => "boolean", "", "`false`", "whether the back side emits too";
        "samples" "" => "whole number 1..=1024", "", "`1`", "shadow rays per shading point";
    }
    EnvironmentLight {
        "image" "`image(\"file\")`" => "file", "", "one of image/color", "equirectangular, row 0 = up (+y)";
        "color" "" => "colour", "W/(m²·sr)", "one of image/color", "constant sky";
        "intensity" "" => "number ≥ 0", "", "`1`", "multiplies the source";
        "rotate" "" => "angle", "`deg` or `rad`", "`0deg`", "about +y";
        "visible" "" => "boolean", "", "`true`", "whether camera rays see it";
    }
    Render {
        "resolution" "" => "`W x H`", "pixels", "`640 x 480`", "each side 1..=16384";
        "samples" "" => "`[rgss \\| grid] N`", "samples per pixel", "`rgss 4`", "N a perfect square (1, 4, 9, 16, ...) ≤ 65536; `rgss` = rotated grid";
        "light_samples" "" => "whole number", "", "`1`", "1..=1024; multiplies each area light's `samples`";
        "seed" "" => "whole number", "", "`0`", "the seed of every random sequence";
        "camera" "" => "camera name", "", "first camera", "the camera rendered from";
        "output" "" => "`\"file.ext\"`", "", "none (the CLI decides)", "repeatable; format from the extension: `.png` (8-bit sRGB, tone mapped), `.exr`, `.hdr`, `.pfm` (linear)";
        "exposure" "" => "number", "stops", "`0`", "radiance × 2^exposure before tone mapping (−64..64)";
        "tonemap" "" => "`clamp` \\| `reinhard` \\| `filmic`", "", "`filmic`", "how radiance maps to display values";
        "quality" "" => "`draft` \\| `preview` \\| `final`", "", "none", "a preset: `draft` = 1 spp × 4 light samples, `preview` = 16 spp, `final` = 256 spp (light_samples 1); an explicit `samples` / `light_samples` in the block wins, in any order (docs/quality.md)";
        "noise" "" => "number", "relative standard error", "none (fixed count)", "adaptive sampling: each pixel is sampled in batches of 16 until the relative standard error of its mean luminance is at most this (0.0001..=1; `0.01` = 1%)";
        "max_samples" "" => "whole number", "samples per pixel", "`4096`", "16..=1048576; the cap of adaptive sampling per pixel (rounded up to whole batches of 16)";
    }
}

/// Every built-in function, by rows of the reference's function table.
pub const FUNCTIONS_DOC: &[FunctionDoc] = &[
    FunctionDoc {
        names: &["sin", "cos", "tan"],
        forms: "`sin(a)`, `cos(a)`, `tan(a)`",
        takes: "angle → number",
    },
    FunctionDoc {
        names: &["sqrt", "abs"],
        forms: "`sqrt(x)`, `abs(x)`",
        takes: "number → number (`abs` also angle → angle)",
    },
    FunctionDoc {
        names: &["min", "max", "pow"],
        forms: "`min(x, y)`, `max(x, y)`, `pow(x, y)`",
        takes: "numbers → number",
    },
    FunctionDoc {
        names: &["radians"],
        forms: "`radians(x)`",
        takes: "number of degrees → angle",
    },
    FunctionDoc {
        names: &["degrees"],
        forms: "`degrees(a)`",
        takes: "angle → number of degrees",
    },
    FunctionDoc {
        names: &["normalize", "length"],
        forms: "`normalize(v)`, `length(v)`",
        takes: "2- or 3-vector → vector / number",
    },
    FunctionDoc {
        names: &["dot"],
        forms: "`dot(u, v)`",
        takes: "two vectors of the same size → number",
    },
    FunctionDoc {
        names: &["cross"],
        forms: "`cross(u, v)`",
        takes: "two 3-vectors → 3-vector",
    },
    FunctionDoc {
        names: &["rgb", "linear"],
        forms: "`rgb(r, g, b)`, `linear(r, g, b)`",
        takes: "numbers (linear) → colour; one number → grey",
    },
    FunctionDoc {
        names: &["srgb"],
        forms: "`srgb(r, g, b)`",
        takes: "numbers (sRGB-encoded, 0..1) → colour decoded to linear; one number → grey",
    },
];

/// Every unit suffix of numbers, with what it means.
pub const UNITS_DOC: &[(&str, &str)] = &[
    ("deg", "degrees: an angle, normalised to radians (× π/180)"),
    ("rad", "radians: an angle, kept as written"),
];
