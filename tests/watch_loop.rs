//! `scnc watch` end to end (issue 6): edits, rename-over saves, broken edits and recovery,
//! asset changes confirmed by content, the build cache, files that appear later, Ctrl-C.

mod watch_common;

use watch_common::{is_png, scene, scene_dir, TempDir, Watch, QUIET, TRI_OBJ};

#[test]
fn an_edit_produces_a_new_image() {
    let dir = scene_dir("edit");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.ready();
    let last = w.seen.last().cloned().unwrap_or_default();
    assert_eq!(
        (last["width"].as_u64(), last["spp"].as_u64()),
        (Some(32), Some(4))
    );
    assert!(is_png(&dir.path("out.png")));
    let before = dir.read("out.png");

    dir.write("scene.scn", &scene(2.5));
    w.expect("compiled");
    let pass1 = w.expect("pass");
    assert_eq!(pass1["spp"], 1, "the first pass is the preview");
    w.expect_where("pass", |e| e["final"] == true);
    let after = dir.read("out.png");
    assert!(is_png(&dir.path("out.png")));
    assert_ne!(before, after, "the camera moved, so the image must change");
}

#[test]
fn an_atomic_rename_save_recompiles_exactly_once() {
    let dir = scene_dir("rename");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.ready();
    dir.write_by_rename("scene.scn", &scene(2.0));
    w.expect("compiled");
    w.expect_none("compiled", QUIET);
    // Writing the image (a temp file renamed over out.png) is not a change either.
    assert!(w
        .seen
        .iter()
        .any(|e| e["event"] == "pass" && e["final"] == true));
}

#[test]
fn a_broken_edit_keeps_the_last_image_and_the_fix_recovers() {
    let dir = scene_dir("broken");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.ready();
    let good = dir.read("out.png");

    dir.write(
        "scene.scn",
        &scene(1.0).replace("material white }", "material whyte }"),
    );
    let err = w.expect("error");
    let d = &err["diagnostics"][0];
    assert_eq!(d["code"], "scnc::check::unknown_material", "{err}");
    assert_eq!(d["labels"][0]["line"], 6, "{err}");
    assert!(
        err["text"].as_str().unwrap_or("").contains("whyte"),
        "{err}"
    );
    w.expect_none("pass", QUIET);
    assert_eq!(
        dir.read("out.png"),
        good,
        "the last good image stays on disk"
    );

    dir.write("scene.scn", &scene(3.0));
    let c = w.expect("compiled");
    // The broken compile never reached the build: the meshes are still cached.
    assert_eq!(c["meshes_reused"], 2, "{c}");
    w.expect_where("pass", |e| e["final"] == true);
    assert_ne!(dir.read("out.png"), good);
}

/// Saves `text` in place as `fs::write` and many editors do (truncate, write), in two pieces
/// with `pause` between them: a writer slowed down by a loaded machine. The first piece ends
/// inside a statement's braces, so a compile of the half-written file is an error.
fn save_in_place_slowly(path: &std::path::Path, text: &str, pause: std::time::Duration) {
    use std::io::Write;
    let half = text.len() / 2;
    let cut = half + text[half..].find('{').map_or(0, |i| i + 1);
    let mut f = std::fs::File::create(path).expect("open for writing");
    f.write_all(&text.as_bytes()[..cut]).expect("write");
    f.flush().expect("flush");
    std::thread::sleep(pause);
    f.write_all(&text.as_bytes()[cut..]).expect("write");
}

#[test]
fn a_slow_in_place_save_is_compiled_once_when_written_not_half_written() {
    let dir = scene_dir("slowsave");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.ready();
    // Longer than the batching's quiet time (40 ms) many times over, shorter than the wait
    // for the writer to close the file (2 s).
    let pause = std::time::Duration::from_millis(400);
    let text = scene(2.0).replace("translate (0, 0, 1)", "translate (0, 0, 1.5)");
    save_in_place_slowly(&dir.path("scene.scn"), &text, pause);
    let c = w.expect("compiled");
    assert_eq!(c["warnings"], 0, "{c}");
    w.expect_none("compiled", QUIET);
    let errors: Vec<_> = w.seen.iter().filter(|e| e["event"] == "error").collect();
    assert!(
        errors.is_empty(),
        "a half-written file was compiled: {errors:#?}"
    );
    assert!(w
        .seen
        .iter()
        .any(|e| e["event"] == "pass" && e["final"] == true));
}

#[test]
fn an_obj_content_change_rerenders_but_a_touch_does_not() {
    let dir = scene_dir("obj");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.ready();

    // Same bytes written again: events arrive, the content hash says nothing changed.
    dir.write("meshes/tri.obj", TRI_OBJ);
    w.expect_none("compiled", QUIET);

    dir.write("meshes/tri.obj", &TRI_OBJ.replace("v 0 2 0", "v 0 3 0"));
    let c = w.expect("compiled");
    assert_eq!(c["meshes_loaded"], 1, "only the OBJ is reloaded: {c}");
    assert_eq!(c["meshes_reused"], 1, "{c}");
    assert_eq!(c["rebuilt"], serde_json::json!(["meshes", "bvh"]), "{c}");
    w.expect_where("pass", |e| e["final"] == true);
}

#[test]
fn a_camera_only_edit_does_not_rebuild_meshes_or_bvh() {
    let dir = scene_dir("camera");
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    let c0 = w.ready();
    assert_eq!(c0["rebuilt"], serde_json::json!(["meshes", "bvh"]), "{c0}");

    dir.write("scene.scn", &scene(1.7));
    let c = w.expect("compiled");
    assert_eq!(c["rebuilt"], serde_json::json!([]), "{c}");
    assert_eq!(
        (c["meshes_loaded"].as_u64(), c["meshes_reused"].as_u64()),
        (Some(0), Some(2))
    );

    // Moving an object rebuilds the BVH but reloads nothing; the front end's result (an
    // incremental re-check of that object) is announced before the build.
    dir.write(
        "scene.scn",
        &scene(1.7).replace("translate (0, 0, 1)", "translate (0, 0, 2)"),
    );
    let k = w.expect("checked");
    assert_eq!(k["warnings"], 0, "{k}");
    assert!(k["compile_ms"].as_f64().is_some(), "{k}");
    let c = w.expect("compiled");
    assert_eq!(c["rebuilt"], serde_json::json!(["bvh"]), "{c}");
}

#[test]
fn an_include_created_later_fixes_the_build() {
    let dir = TempDir::new("include");
    let text = scene(1.0).replace(
        "material white = phong { diffuse rgb(0.8, 0.8, 0.8)  specular 0 }\n",
        "include \"lib/materials.scn\"\n",
    );
    dir.write("scene.scn", &text);
    dir.write("meshes/tri.obj", TRI_OBJ);
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    let err = w.expect("error");
    assert_eq!(
        err["diagnostics"][0]["code"], "scnc::include::not_found",
        "{err}"
    );
    w.expect("watching");
    // The directory does not exist either: the file is polled until it appears.
    dir.write(
        "lib/materials.scn",
        "scnc 1\nmaterial white = phong { diffuse rgb(0.8, 0.8, 0.8)  specular 0 }\n",
    );
    w.expect("compiled");
    w.expect_where("pass", |e| e["final"] == true);
    assert!(is_png(&dir.path("out.png")));
}

#[test]
fn a_new_edit_cancels_the_render_in_flight() {
    let dir = scene_dir("cancel");
    // 256 spp at 320x240: the final pass takes far longer than the preview passes.
    let heavy = |eye: f32| {
        scene(eye).replace(
            "resolution 32 x 24  samples rgss 4",
            "resolution 320 x 240  samples rgss 256",
        )
    };
    dir.write("scene.scn", &heavy(1.0));
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.expect("watching");
    w.expect_where("pass", |e| e["spp"] == 1);
    dir.write("scene.scn", &heavy(2.0));
    w.expect("compiled");
    let finals = w.seen.iter().filter(|e| e["final"] == true).count();
    assert_eq!(finals, 0, "the 256-spp pass was cancelled: {:#?}", w.seen);
    // The new render starts over from the preview pass.
    let next = w.expect("pass");
    assert_eq!(next["spp"], 1, "{next}");
}

#[test]
#[cfg(unix)]
fn ctrl_c_stops_cleanly_leaving_no_temporary_files() {
    let dir = scene_dir("ctrlc");
    // Large enough that the render is in flight when the signal arrives.
    dir.write(
        "scene.scn",
        &scene(1.0).replace(
            "resolution 32 x 24  samples rgss 4",
            "resolution 320 x 240  samples rgss 64",
        ),
    );
    let mut w = Watch::start(&dir, "scene.scn", &["--no-serve"]);
    w.expect("watching");
    w.expect("pass");
    let status = std::process::Command::new("kill")
        .args(["-INT", &w.pid().to_string()])
        .status()
        .expect("run kill");
    assert!(status.success());
    w.expect("stopped");
    assert!(w.wait_exit(), "exit status 0 after Ctrl-C");
    let names: Vec<String> = std::fs::read_dir(&dir.0)
        .expect("list dir")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
    assert!(is_png(&dir.path("out.png")));
}
