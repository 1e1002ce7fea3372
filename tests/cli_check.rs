//! `scnc check` end to end: it reports the build stage's problems too (a missing OBJ, a light
//! facing away from the scene) in the same single list as the compile's, exits 1 only on
//! errors, and `--compile-only` reads nothing but the scene.

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
    let dir = std::env::temp_dir().join(format!("scnc-cli-check-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

const SCENE: &str = "scnc 1
camera c { eye (0, 1, -4)  target (0, 0, 0)  fov 40deg }
material m = phong { diffuse 0.5 }
mesh floor = quad { size (4, 4) }
mesh prop = obj(\"props/chair.obj\")
object floor { material m }
object prop { material m }
light up = area { quad (-1, 3, -1) (-1, 3, 1) (1, 3, 1) (1, 3, -1)  radiance rgb(5, 5, 5) }
";

fn codes(out: &Output) -> Vec<String> {
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    json["diagnostics"]
        .as_array()
        .expect("a list")
        .iter()
        .map(|d| d["code"].as_str().unwrap_or_default().to_string())
        .collect()
}

#[test]
fn check_reports_build_problems_in_one_list() {
    let dir = workdir("build");
    std::fs::write(dir.join("s.scn"), SCENE).expect("write");
    let json = ["--diagnostic-format", "json"];

    // The OBJ is missing: an error at its path, exit 1; the light's warning is reported in the
    // same run.
    let out = scnc(&[&["check", "s.scn"][..], &json].concat(), &dir);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        codes(&out),
        ["scnc::build::missing_file", "scnc::build::light_faces_away"]
    );

    // With the OBJ there, only the warning about the light remains: exit 0.
    std::fs::create_dir_all(dir.join("props")).expect("dir");
    std::fs::write(
        dir.join("props/chair.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .expect("write");
    let out = scnc(&[&["check", "s.scn"][..], &json].concat(), &dir);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(codes(&out), ["scnc::build::light_faces_away"]);

    // Compile only: the OBJ is not read, so its absence is not seen.
    std::fs::remove_file(dir.join("props/chair.obj")).expect("remove");
    let out = scnc(
        &[&["check", "s.scn", "--compile-only"][..], &json].concat(),
        &dir,
    );
    assert_eq!(out.status.code(), Some(0));
    assert!(codes(&out).is_empty(), "{:?}", codes(&out));
    let _ = std::fs::remove_dir_all(&dir);
}
