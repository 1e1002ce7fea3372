//! One end-to-end test with a real client: headless Neovim (Debian's `neovim`, installed by
//! `.ci/run`) opens a copy of examples/include_demo.scn, attaches `scnc lsp` (this build), and
//! tests/lsp_neovim.lua records a diagnostic, a hover, a go-to-definition (into the included
//! file) and a formatting request, which are asserted here. Skipped, loudly, only when `nvim`
//! is not installed. Neovim is killed after 60 s, so the test cannot hang.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create");
    for entry in std::fs::read_dir(from).expect("read_dir") {
        let path = entry.expect("entry").path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).expect("copy");
        }
    }
}

#[test]
fn neovim_shows_diagnostics_hover_definition_and_formats() {
    let nvim_present = Command::new("nvim")
        .arg("--version")
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !nvim_present {
        eprintln!(
            "SKIPPED: nvim is not installed (apt-get install neovim); no Neovim end-to-end test"
        );
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("scnc-lsp-neovim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::copy(
        root.join("examples/include_demo.scn"),
        dir.join("scene.scn"),
    )
    .expect("copy");
    copy_dir(&root.join("examples/lib"), &dir.join("lib"));
    let out = dir.join("results.json");

    let mut nvim = Command::new("nvim")
        .args(["--headless", "--clean", "-n", "-u", "NONE", "-c"])
        .arg(format!(
            "luafile {}",
            root.join("tests/lsp_neovim.lua").display()
        ))
        .env("SCNC_BIN", env!("CARGO_BIN_EXE_scnc"))
        .env("SCNC_SCENE", dir.join("scene.scn"))
        .env("SCNC_OUT", &out)
        .env("XDG_STATE_HOME", &dir)
        .env("XDG_DATA_HOME", &dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .spawn()
        .expect("nvim starts");
    let deadline = Instant::now() + Duration::from_secs(60);
    while nvim.try_wait().expect("wait").is_none() {
        if Instant::now() > deadline {
            let _ = nvim.kill();
            let _ = nvim.wait();
            panic!("Neovim did not finish within 60 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let text = std::fs::read_to_string(&out).expect("the Lua script wrote its results");
    let results: Value = serde_json::from_str(&text).expect("JSON results");
    assert!(results.get("error").is_none(), "{results:#}");

    // The unknown name on the line Neovim appended (0-based line 16).
    let d = &results["diagnostic"];
    assert_eq!(d["code"], "scnc::check::unknown_name", "{results:#}");
    assert_eq!(
        (d["lnum"].as_u64(), d["col"].as_u64()),
        (Some(16), Some(11)),
        "{results:#}"
    );

    let hover = results["hover"]["value"].as_str().expect("a hover");
    assert!(
        hover.starts_with("`fov` in a camera\n\ntype: angle"),
        "{hover}"
    );

    assert_eq!(results["definition_provider"], true, "{results:#}");
    definition_is_the_included_declaration(&results["definition"], &dir);

    let scene = std::fs::read_to_string(dir.join("scene.scn")).expect("the scene");
    let want = scnc::fmt::format(
        scnc::source::FileId(0),
        &format!("{scene}let broken=nope\n"),
    )
    .value
    .expect("the edited scene parses");
    assert_eq!(results["formatted"], want.as_str());
    assert!(want.ends_with("let broken = nope\n"));
    std::fs::remove_dir_all(&dir).ok();
}

/// `matte`, used in the scene, is declared in the included lib/materials.scn.
fn definition_is_the_included_declaration(definition: &Value, dir: &Path) {
    let target = definition["uri"].as_str().expect("a definition");
    assert!(target.ends_with("/lib/materials.scn"), "{definition}");
    let lib = std::fs::read_to_string(dir.join("lib/materials.scn")).expect("the library");
    let line = lib
        .lines()
        .position(|l| l.starts_with("material matte"))
        .expect("matte is declared");
    assert_eq!(definition["range"]["start"]["line"], line, "{definition}");
}
