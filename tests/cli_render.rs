//! `scnc render` end to end, through the real binary: it writes the image the extension asks
//! for, reports bad arguments and unwritable outputs as diagnostics (exit 1, no panic), and a
//! failed write leaves the previous image untouched.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scnc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the scnc binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh directory holding a copy of examples/cornell.scn.
fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-cli-render-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.scn"),
        dir.join("cornell.scn"),
    )
    .expect("copy the example");
    dir
}

#[test]
fn renders_png_and_linear_formats_by_extension() {
    let dir = workdir("formats");
    for (out, magic) in [
        ("a.png", &b"\x89PNG"[..]),
        ("a.pfm", b"PF"),
        ("a.hdr", b"#?RADIANCE"),
        ("a.exr", b"\x76\x2f\x31\x01"),
    ] {
        let o = scnc(
            &[
                "render",
                "cornell.scn",
                "-o",
                out,
                "--resolution",
                "16x16",
                "--spp",
                "1",
            ],
            &dir,
        );
        assert!(o.status.success(), "{out}: {}", stderr(&o));
        let bytes = std::fs::read(dir.join(out)).expect("output written");
        assert!(
            bytes.starts_with(magic),
            "{out} does not start with its format's magic bytes"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn stats_report_every_phase_and_the_ray_counts() {
    let dir = workdir("stats");
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "-o",
            "s.png",
            "--resolution",
            "16x16",
            "--spp",
            "4",
            "--stats",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    for needle in [
        "parse+check",
        "asset load",
        "bvh build",
        "render",
        "write",
        "camera",
        "shadow",
        "Mrays/s",
        "Mrays/CPU-s",
        "render cpu",
        "nodes",
        "leaves",
        "peak memory",
    ] {
        assert!(err.contains(needle), "--stats lacks `{needle}`:\n{err}");
    }
    // Four samples per pixel, more where the light may be seen (reported on its own line).
    let light_pixels = err
        .lines()
        .find_map(|l| l.strip_prefix("light pixels"))
        .and_then(|l| {
            let words: Vec<&str> = l.split_whitespace().collect();
            let took = words.iter().position(|w| *w == "took")?;
            Some((
                words[0].parse::<u32>().ok()?,
                words[took + 1].parse::<u32>().ok()?,
            ))
        });
    let (boosted, spp) = light_pixels.expect("cornell's light is in view");
    let camera = 16 * 16 * 4 + boosted * (spp - 4);
    assert!(err.contains(&format!("{camera} camera")), "{err}");
    // What was built (only what the Cornell box needs), and the per-sample path counters.
    for needle in [
        "built",
        "meshes",
        "light table",
        "0 textured, 0 specular, 0 environment; 0 NaN/inf samples dropped",
    ] {
        assert!(err.contains(needle), "--stats lacks `{needle}`:\n{err}");
    }
    assert!(
        !err.contains("textures ") && !err.contains("environment map"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_unwritable_output_is_a_diagnostic_and_the_previous_image_survives() {
    let dir = workdir("unwritable");
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "-o",
            "keep.png",
            "--resolution",
            "8x8",
            "--spp",
            "1",
        ],
        &dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(dir.join("keep.png")).expect("first image");
    // A directory where the image should go cannot be replaced by a file.
    std::fs::create_dir_all(dir.join("taken.png")).expect("dir");
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "-o",
            "taken.png",
            "--resolution",
            "8x8",
        ],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("scnc::write"), "{}", stderr(&o));
    // Into a missing directory: the same.
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "-o",
            "no/such/dir/x.png",
            "--resolution",
            "8x8",
        ],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    // An unknown extension is refused before rendering, and the old image is untouched.
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "-o",
            "keep.gif",
            "--resolution",
            "8x8",
        ],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(dir.join("keep.png")).expect("still there"),
        before
    );
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_and_bad_scenes_exit_1_with_diagnostics() {
    let dir = workdir("bad");
    let o = scnc(
        &[
            "render",
            "cornell.scn",
            "--camera",
            "mian",
            "--resolution",
            "8x8",
        ],
        &dir,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("did you mean `main`"), "{}", stderr(&o));
    let o = scnc(&["render", "cornell.scn", "--resolution", "0x8"], &dir);
    assert!(!o.status.success());
    std::fs::write(
        dir.join("broken.scn"),
        "scnc 1\ncamera c { eye (0,0,0) target (0,0,1) fov 40 }\n",
    )
    .expect("write");
    let o = scnc(&["render", "broken.scn"], &dir);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("angle"), "{}", stderr(&o));
    assert!(!dir.join("broken.png").exists());
    let o = scnc(&["render", "missing.scn"], &dir);
    assert_eq!(o.status.code(), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}
