//! Front end on examples/*.scn: every example checks clean (no diagnostics at all) and its IR
//! is snapshotted. Inline mesh arrays are summarised (count + FNV hash of their JSON) to keep the
//! snapshots small; everything else is shown as `scnc ir` prints it.

use std::path::Path;

use scnc::assets::FsLoader;
use scnc::compile::compile_file;
use scnc::diag::render_plain_all;
use serde_json::Value;

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Replaces every array in an `Inline` mesh with `{count, fnv}`.
fn summarise(v: &mut Value) {
    match v {
        Value::Object(map) => {
            if let Some(Value::Object(inline)) = map.get_mut("Inline") {
                for (_, arr) in inline.iter_mut() {
                    if let Value::Array(items) = arr {
                        let text = serde_json::to_string(items).expect("JSON values serialise");
                        *arr = serde_json::json!({
                            "count": items.len(),
                            "fnv": format!("{:016x}", fnv1a(text.as_bytes())),
                        });
                    }
                }
            }
            map.values_mut().for_each(summarise);
        }
        Value::Array(items) => items.iter_mut().for_each(summarise),
        _ => {}
    }
}

#[test]
fn examples_compile_clean_and_match_their_ir() {
    insta::glob!("../examples", "*.scn", |path| {
        let rel = path
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap_or(path);
        let compiled = compile_file(rel, &FsLoader::new());
        assert!(
            compiled.diagnostics.is_empty(),
            "{}:\n{}",
            rel.display(),
            render_plain_all(&compiled.diagnostics, &compiled.sources, 100)
        );
        let scene = compiled.scene.expect("a clean compile has a scene");
        let mut json = serde_json::to_value(&scene).expect("the IR serialises");
        summarise(&mut json);
        insta::assert_json_snapshot!(json);
    });
}

#[test]
fn cornell_matches_the_benchmark_geometry() {
    let compiled = compile_file(Path::new("examples/cornell.scn"), &FsLoader::new());
    let scene = compiled.scene.expect("cornell compiles");
    assert_eq!(scene.render.width, 512);
    assert_eq!(scene.render.height, 512);
    // 7 surfaces + the light's quad.
    assert_eq!(scene.meshes.len(), 8);
    assert_eq!(scene.objects.len(), 7);
    let triangles: usize = scene
        .meshes
        .iter()
        .map(|m| match &m.source {
            scnc::ir::MeshSource::Inline(i) => i.indices.len(),
            _ => 0,
        })
        .sum();
    // 5 walls x 2 + 2 blocks x 10 + light 2.
    assert_eq!(triangles, 32);
    let cam = scene.camera().expect("has a camera");
    assert!((cam.fov_y_rad.to_degrees() - 39.3077).abs() < 1e-4);
    let scnc::ir::Light::Area(light) = &scene.lights[0] else {
        panic!("the cornell light is an area light")
    };
    assert!(!light.two_sided);
    let scnc::ir::MeshSource::Inline(quad) = &scene.meshes[light.mesh as usize].source else {
        panic!("the light is a quad")
    };
    let p = &quad.positions;
    let normal = (p[1] - p[0]).cross(p[2] - p[0]);
    assert!(
        normal.y < 0.0 && normal.x == 0.0 && normal.z == 0.0,
        "{normal}"
    );
}
