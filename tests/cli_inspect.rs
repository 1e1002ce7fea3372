//! `scnc inspect FILE.obj [--json] [--strict]` end to end: the summary's figures, the material
//! mapping, warnings with the MTL/OBJ line, exit codes (0 loads, 1 cannot or `--strict` with
//! warnings), and `--strict` on `scnc check` for a scene whose OBJ has a missing MTL.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scnc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the scnc binary runs")
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-cli-inspect-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

const HOUSE: &str = "mtllib house.mtl\nv 0 0 0\nv 2 0 0\nv 2 0 3\nv 0 0 3\nv 0 1 0\n\
usemtl walls\nf 1 2 3 4\nusemtl lamp\nf 1 2 5\nl 1 5\n";
const MTL: &str =
    "newmtl walls\nKd 0.6 0.5 0.4\nKs 0.2\nNs 40\nd 0.9\nnewmtl lamp\nKd 0 0 0\nKe 5 4 3\n";

#[test]
fn json_summary_has_the_figures_and_the_mapping() {
    let dir = workdir("json");
    std::fs::write(dir.join("house.obj"), HOUSE).expect("write");
    std::fs::write(dir.join("house.mtl"), MTL).expect("write");
    let out = scnc(&["inspect", "house.obj", "--json"], &dir);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j = json(&out);
    assert_eq!(j["triangles"], 3);
    assert!(
        (j["area"].as_f64().expect("area") - 7.0).abs() < 1e-5,
        "{}",
        j["area"]
    );
    assert_eq!(j["bounds"]["min"], serde_json::json!([0.0, 0.0, 0.0]));
    assert_eq!(j["bounds"]["max"], serde_json::json!([2.0, 1.0, 3.0]));
    let mats = j["materials"].as_array().expect("materials");
    assert_eq!(mats.len(), 2);
    assert_eq!(
        (mats[0]["name"].as_str(), mats[0]["triangles"].as_u64()),
        (Some("walls"), Some(2))
    );
    assert_eq!(mats[0]["maps_to"]["kind"], "phong");
    assert_eq!(mats[0]["maps_to"]["shininess"], 40.0);
    assert_eq!(mats[0]["defined_in"]["line"], 1);
    assert_eq!(mats[1]["maps_to"]["kind"], "area_light");
    let codes: Vec<&str> = j["warnings"]
        .as_array()
        .expect("warnings")
        .iter()
        .map(|w| w["code"].as_str().unwrap_or_default())
        .collect();
    assert_eq!(
        codes,
        ["scnc::obj::lines_skipped", "scnc::obj::unsupported_mtl"]
    );
    assert_eq!(j["warnings"][1]["line"], 5);
    assert_eq!(j["warnings"][1]["file"], "house.mtl");
    // The same warnings are diagnostics on stderr, with the MTL line.
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("house.mtl:5:1") && err.contains("d 0.9"),
        "{err}"
    );

    let strict = scnc(&["inspect", "house.obj", "--json", "--strict"], &dir);
    assert_eq!(strict.status.code(), Some(1));
}

#[test]
fn human_output_and_broken_files() {
    let dir = workdir("human");
    std::fs::write(dir.join("ok.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").expect("write");
    let out = scnc(&["inspect", "ok.obj"], &dir);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("triangles  1") && text.contains("area       0.5"),
        "{text}"
    );

    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").expect("write");
    let out = scnc(&["inspect", "bad.obj"], &dir);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("index_out_of_range") && err.contains("bad.obj:4:1"),
        "{err}"
    );
    assert!(out.stdout.is_empty());

    let out = scnc(&["inspect", "absent.obj"], &dir);
    assert_eq!(out.status.code(), Some(1));
    // Binary junk never panics: it loads (with warnings) or fails with a diagnostic.
    std::fs::write(
        dir.join("junk.obj"),
        [0u8, 159, 146, 150, 255, 10, 102, 32, 1],
    )
    .expect("write");
    let out = scnc(&["inspect", "junk.obj"], &dir);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn strict_check_fails_on_a_missing_mtl() {
    let dir = workdir("strict");
    std::fs::write(
        dir.join("s.scn"),
        "scnc 1\ncamera c { eye (0, 1, -4)  target (0, 0, 0)  fov 40deg }\n\
         material m = phong { diffuse 0.5 }\nmesh t = obj(\"t.obj\")\nobject t { material m }\n\
         light p = point { position (0, 3, 0)  intensity rgb(5, 5, 5) }\n",
    )
    .expect("write");
    std::fs::write(
        dir.join("t.obj"),
        "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .expect("write");
    let out = scnc(&["check", "s.scn"], &dir);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("missing_mtl") && err.contains("t.obj:1:1") && err.contains("s.scn:4"),
        "{err}"
    );
    let out = scnc(&["check", "s.scn", "--strict"], &dir);
    assert_eq!(out.status.code(), Some(1));
}
