//! The scene's identity: a stable hash of the validated IR and the resolved render settings,
//! stamped into every tile of `scnc render --tile K/N` so that `scnc merge` only assembles
//! tiles of one and the same image.
//!
//! Input: an [`ir::SceneDesc`](super::SceneDesc) after `RenderSettings::resolve` (so
//! `--spp`, `--resolution`, `--quality`, `--noise` are in it), plus the command-line choices
//! the IR does not hold (the camera index `--camera` picked, `--accel`). Output: an
//! [`Identity`], 128 bits printed as `scnc-id1-` and 32 hex digits.
//!
//! Definition (version 1): the IR serialised as JSON (as `scnc ir` prints it, compact), with
//! every `span` removed (byte offsets change when a comment does), every asset's resolved
//! `path` removed (it depends on where the scene file lies; the path as `written` in the
//! scene stays) and `render.outputs` removed (where the image goes is not what it is); then
//! `{"accel":…,"camera":…,"ir":…,"scnc":"<crate version>"}` with keys sorted, hashed with
//! 128-bit FNV-1a. Numbers print as their shortest round-trip decimal, so equal floats give
//! equal text on every machine. Not covered: the bytes of textures and OBJ files (an asset
//! changed on one machine but not another is not detected; the farm must share files).
//! The thread count is not an input: it never changes the image.

use std::fmt;

use serde_json::Value;

use super::SceneDesc;

/// The identity of a scene and its settings (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Identity(pub u128);

impl fmt::Display for Identity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{PREFIX}{:032x}", self.0)
    }
}

const PREFIX: &str = "scnc-id1-";

impl Identity {
    /// Parses the text [`Display`](fmt::Display) prints.
    pub fn parse(text: &str) -> Option<Identity> {
        let hex = text.strip_prefix(PREFIX)?;
        if hex.len() != 32 {
            return None;
        }
        u128::from_str_radix(hex, 16).ok().map(Identity)
    }
}

/// The identity of `desc` (render settings resolved) rendered from camera `camera` with the
/// acceleration structure named `accel`.
pub fn identity(desc: &SceneDesc, camera: usize, accel: &str) -> Identity {
    let mut ir = serde_json::to_value(desc).unwrap_or(Value::Null);
    strip(&mut ir);
    if let Some(render) = ir.get_mut("render").and_then(Value::as_object_mut) {
        render.remove("outputs");
    }
    let mut canonical = serde_json::Map::new();
    canonical.insert("accel".into(), Value::from(accel));
    canonical.insert("camera".into(), Value::from(camera));
    canonical.insert("ir".into(), ir);
    canonical.insert("scnc".into(), Value::from(env!("CARGO_PKG_VERSION")));
    Identity(fnv1a_128(Value::Object(canonical).to_string().as_bytes()))
}

/// Removes spans and resolved asset paths, sorting every object's keys on the way (the JSON
/// text must not depend on serde_json's map order).
fn strip(value: &mut Value) {
    match value {
        Value::Object(map) => {
            map.remove("span");
            if map.contains_key("written") {
                map.remove("path");
            }
            let mut entries: Vec<(String, Value)> = std::mem::take(map).into_iter().collect();
            entries.sort_by(|a, b| a.0.cmp(&b.0));
            for (key, mut v) in entries {
                strip(&mut v);
                map.insert(key, v);
            }
        }
        Value::Array(items) => items.iter_mut().for_each(strip),
        _ => {}
    }
}

/// 128-bit FNV-1a (offset basis and prime from the FNV reference).
fn fnv1a_128(bytes: &[u8]) -> u128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;
    bytes
        .iter()
        .fold(OFFSET, |h, &b| (h ^ u128::from(b)).wrapping_mul(PRIME))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::MemLoader;
    use crate::compile::compile_source;

    const SCENE: &str = "scnc 1
camera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }
camera side { eye (5, 1, 0)  target (0, 1, 0)  fov 40deg }
material grey = phong { diffuse 0.5 }
mesh ball = sphere { radius 1 }
object ball { material grey }
render { resolution 32 x 24  samples 4  output \"a.png\" }
";

    fn id_of(src: &str, camera: usize) -> Identity {
        let compiled = compile_source("scene.scn", src, &MemLoader::new());
        let desc = compiled.scene.expect("scene compiles");
        identity(&desc, camera, "bvh")
    }

    #[test]
    fn fnv_reference_values() {
        assert_eq!(fnv1a_128(b""), 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d);
        assert_eq!(fnv1a_128(b"a"), 0xd228_cb69_6f1a_8caf_7891_2b70_4e4a_8964);
    }

    #[test]
    fn ignores_comments_spans_and_output_paths() {
        let base = id_of(SCENE, 0);
        let moved = format!(
            "// a comment shifts every span\n{}",
            SCENE.replace("a.png", "b.exr")
        );
        assert_eq!(id_of(&moved, 0), base);
        assert_eq!(Identity::parse(&base.to_string()), Some(base));
    }

    #[test]
    fn changes_with_what_the_image_depends_on() {
        let base = id_of(SCENE, 0);
        assert_ne!(id_of(SCENE, 1), base, "camera");
        assert_ne!(id_of(&SCENE.replace("32 x 24", "32 x 25"), 0), base);
        assert_ne!(id_of(&SCENE.replace("samples 4", "samples 9"), 0), base);
        assert_ne!(
            id_of(&SCENE.replace("diffuse 0.5", "diffuse 0.50001"), 0),
            base
        );
        let exposed = SCENE.replace("samples 4", "samples 4  exposure 1");
        assert_ne!(id_of(&exposed, 0), base);
    }
}
