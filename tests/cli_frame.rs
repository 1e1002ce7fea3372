//! The predefined constant `frame` and `scnc render --frame F`: `frame` is 0 by default, takes
//! the flag's value in any expression (so the IR and the image change with it), and cannot be
//! redefined with `let`; `--frames` numbers its files; `--define NAME=VALUE` replaces a `let`
//! with a value of the same type.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::diag::Code;

const TURNTABLE: &str = "scnc 1
camera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }
material grey = phong { diffuse 0.5 }
let side = 1
mesh box = box { size (side, side, side) }
object box { material grey  transform { rotate y (frame * 10deg)  translate (frame * 0.05, 1, 0) } }
light sun = point { position (3, 4, -3)  intensity rgb(20, 20, 20) }
render { resolution 24 x 16  samples 1 }
";

fn scnc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the scnc binary runs")
}

fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-cli-frame-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("turn.scn"), TURNTABLE).expect("write scene");
    dir
}

fn render(dir: &Path, extra: &[&str], out: &str) -> Vec<u8> {
    let mut args = vec!["render", "turn.scn", "-o", out];
    args.extend_from_slice(extra);
    let o = scnc(&args, dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read(dir.join(out)).expect("image written")
}

#[test]
fn frame_flag_sets_the_constant_and_defaults_to_zero() {
    let dir = workdir("flag");
    let default = render(&dir, &[], "d.pfm");
    assert_eq!(render(&dir, &["--frame", "0"], "f0.pfm"), default);
    let f9 = render(&dir, &["--frame", "9"], "f9.pfm");
    assert_ne!(f9, default, "frame 9 turns and moves the box");
    assert_eq!(render(&dir, &["--frame", "9"], "f9b.pfm"), f9);
    let neg = render(&dir, &["--frame", "-3"], "fm3.pfm");
    assert_ne!(neg, default);
    let bad = scnc(
        &["render", "turn.scn", "--frame", "inf", "-o", "x.png"],
        &dir,
    );
    assert_eq!(bad.status.code(), Some(2), "a non-finite frame is refused");
}

#[test]
fn frame_is_reserved_and_a_number() {
    let loader = MemLoader::new();
    let compiled = compile_source("s.scn", &format!("{TURNTABLE}let frame = 2\n"), &loader);
    let codes: Vec<Code> = compiled.diagnostics.iter().map(|d| d.code).collect();
    assert!(codes.contains(&Code::CheckReservedName), "{codes:?}");
    let compiled = compile_source(
        "s.scn",
        &format!("{TURNTABLE}let a = frame + 1deg\n"),
        &loader,
    );
    let codes: Vec<Code> = compiled.diagnostics.iter().map(|d| d.code).collect();
    assert!(codes.contains(&Code::CheckBadOperands), "{codes:?}");
}

#[test]
fn frames_number_the_files_equal_single_frames_and_reuse_meshes() {
    let dir = workdir("frames");
    let o = scnc(
        &["render", "turn.scn", "--frames", "0..4:2", "-o", "f_##.pfm"],
        &dir,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    for f in ["f_00.pfm", "f_02.pfm", "f_04.pfm"] {
        assert!(dir.join(f).exists(), "{f}: {err}");
    }
    assert!(!dir.join("f_01.pfm").exists());
    assert_eq!(
        std::fs::read(dir.join("f_02.pfm")).expect("frame 2"),
        render(&dir, &["--frame", "2"], "single2.pfm")
    );
    // The box turns (its BVH placement changes) but its mesh is built once.
    let line = err
        .lines()
        .find(|l| l.starts_with("frame 2:"))
        .expect("frame 2 line");
    assert!(!line.contains("meshes") && line.contains("bvh"), "{line}");
    let o = scnc(
        &["render", "turn.scn", "--frames", "0..1", "-o", "f.png"],
        &dir,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("scnc::cli::frames_without_pattern"), "{err}");
    assert!(!dir.join("f.png").exists());
}

/// Tiles of frames: `--frames` with `--tile` numbers each tile file; tiles of one frame merge
/// into that frame's direct render, tiles of two frames are refused (their identities differ).
#[test]
fn tiles_of_frames_merge_per_frame() {
    let dir = workdir("tiles");
    for k in 0..2 {
        let (tile, out) = (format!("{k}/2"), format!("t{k}_#.exr"));
        let o = scnc(
            &[
                "render", "turn.scn", "--frames", "0..1", "--tile", &tile, "-o", &out,
            ],
            &dir,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let o = scnc(&["merge", "t0_1.exr", "t1_1.exr", "-o", "m1.png"], &dir);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(dir.join("m1.png")).expect("merged"),
        render(&dir, &["--frame", "1"], "d1.png")
    );
    let o = scnc(&["merge", "t0_0.exr", "t1_1.exr", "-o", "bad.png"], &dir);
    assert!(String::from_utf8_lossy(&o.stderr).contains("scnc::merge::mismatch"));
    assert!(!dir.join("bad.png").exists());
}

#[test]
fn define_replaces_a_let_of_the_same_type() {
    let dir = workdir("define");
    let default = render(&dir, &[], "d.pfm");
    assert_eq!(render(&dir, &["--define", "side=1"], "same.pfm"), default);
    assert_eq!(
        render(&dir, &["--define", "side=0.5 + 0.5"], "expr.pfm"),
        default
    );
    assert_ne!(render(&dir, &["--define", "side=1.5"], "big.pfm"), default);
    for (value, code, says) in [
        ("sid=2", "scnc::cli::unknown_define", "did you mean `side`?"),
        ("side=2deg", "scnc::cli::define_type", "an angle"),
        ("side=(1,", "scnc::syntax::", "--define side"),
    ] {
        let o = scnc(
            &["render", "turn.scn", "--define", value, "-o", "bad.png"],
            &dir,
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{value}: {err}");
        assert!(err.contains(code) && err.contains(says), "{value}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!dir.join("bad.png").exists());
    let o = scnc(
        &["render", "turn.scn", "--define", "side", "-o", "bad.png"],
        &dir,
    );
    assert_eq!(o.status.code(), Some(2), "NAME=VALUE is required");
}

/// `scnc ir` and `scnc check` take `--frame` and `--define` as `scnc render` does: the IR
/// changes with them, and a bad define is the same diagnostic.
#[test]
fn ir_and_check_take_frame_and_define() {
    let dir = workdir("ir-check");
    let ir = |extra: &[&str]| -> String {
        let mut args = vec!["ir", "turn.scn"];
        args.extend_from_slice(extra);
        let o = scnc(&args, &dir);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let default = ir(&[]);
    assert_eq!(ir(&["--frame", "0", "--define", "side=1"]), default);
    assert_ne!(ir(&["--frame", "3"]), default, "frame moves the box");
    assert_ne!(ir(&["--define", "side=2"]), default, "side resizes the box");
    assert_eq!(ir(&["--frame", "3"]), ir(&["--frame", "3.0"]));
    for command in ["ir", "check"] {
        let o = scnc(&[command, "turn.scn", "--define", "side=2deg"], &dir);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{command}: {err}");
        assert!(err.contains("scnc::cli::define_type"), "{command}: {err}");
    }
    let o = scnc(
        &["check", "turn.scn", "--frame", "2", "--define", "side=3"],
        &dir,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = scnc(&["watch", "--help"], &dir);
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(
        help.contains("--frame") && help.contains("--define"),
        "{help}"
    );
}
