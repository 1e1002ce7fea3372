//! `scnc render --tile K/N` and `scnc merge` end to end, through the real binary: the merged
//! PNG and EXR are byte-identical to a direct render for N = 1, 3, 7 and 1 or 2 threads (also
//! with adaptive sampling), and merge refuses mismatched, overlapping, missing, truncated and
//! foreign files with their codes, writing nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scnc(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the scnc binary runs")
}

fn ok(args: &[&str], dir: &Path) {
    let out = scnc(args, dir);
    assert!(
        out.status.success(),
        "scnc {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `args`, expects failure, returns stderr.
fn fails(args: &[&str], dir: &Path) -> String {
    let out = scnc(args, dir);
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "scnc {args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// The cornell box, small, with an exposure and tone map the merge must carry to the PNG.
fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-cli-tiles-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let cornell =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.scn"))
            .expect("read the example");
    let small = cornell.replace(
        "render { resolution 512 x 512  samples rgss 4  output \"cornell.png\" }",
        "render { resolution 23 x 19  samples rgss 4  exposure 0.7  tonemap reinhard }",
    );
    assert_ne!(small, cornell, "the example's render block changed");
    std::fs::write(dir.join("scene.scn"), small).expect("write scene");
    dir
}

fn bytes(path: PathBuf) -> Vec<u8> {
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Renders every tile of `n` with `threads`, merges to PNG and EXR, compares with `direct.*`.
fn merged_equals_direct(dir: &Path, n: u32, threads: &str, extra: &[&str]) {
    let mut parts = Vec::new();
    for k in 0..n {
        let part = format!("part_{n}_{threads}_{k}.exr");
        let tile = format!("{k}/{n}");
        let mut args = vec![
            "render",
            "scene.scn",
            "--tile",
            &tile,
            "--threads",
            threads,
            "-o",
            &part,
        ];
        args.extend_from_slice(extra);
        ok(&args, dir);
        parts.push(part);
    }
    // Reverse order: the order of the files given does not matter.
    parts.reverse();
    for ext in ["png", "exr"] {
        let out = format!("merged.{ext}");
        let mut args = vec!["merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["-o", &out]);
        ok(&args, dir);
        assert!(
            bytes(dir.join(&out)) == bytes(dir.join(format!("direct.{ext}"))),
            "N = {n}, {threads} threads, {extra:?}: merged {ext} differs from the direct render"
        );
    }
}

#[test]
fn merged_tiles_are_the_direct_render_bit_for_bit() {
    let dir = workdir("identical");
    ok(
        &["render", "scene.scn", "--threads", "2", "-o", "direct.png"],
        &dir,
    );
    ok(
        &["render", "scene.scn", "--threads", "2", "-o", "direct.exr"],
        &dir,
    );
    for n in [1, 3, 7] {
        for threads in ["1", "2"] {
            merged_equals_direct(&dir, n, threads, &[]);
        }
    }
    // Adaptive sampling decides per pixel from that pixel's samples: tiles change nothing.
    let adaptive = ["--noise", "0.05", "--max-samples", "64"];
    let mut args = vec!["render", "scene.scn", "-o", "direct.png"];
    args.extend(adaptive);
    ok(&args, &dir);
    args[3] = "direct.exr";
    ok(&args, &dir);
    merged_equals_direct(&dir, 3, "2", &adaptive);
}

#[test]
fn tile_needs_an_exr_output_and_a_row_per_tile() {
    let dir = workdir("args");
    let err = fails(
        &["render", "scene.scn", "--tile", "0/2", "-o", "p.png"],
        &dir,
    );
    assert!(err.contains("scnc::cli::tile_not_exr"), "{err}");
    assert!(!dir.join("p.png").exists());
    let err = fails(
        &["render", "scene.scn", "--tile", "3/20", "-o", "p.exr"],
        &dir,
    );
    assert!(
        err.contains("scnc::cli::too_many_tiles") && err.contains("19 rows"),
        "{err}"
    );
    // K out of range is refused by the argument parser (exit 2).
    let out = scnc(
        &["render", "scene.scn", "--tile", "2/2", "-o", "p.exr"],
        &dir,
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn merge_refuses_what_is_not_one_image_and_writes_nothing() {
    let dir = workdir("refuse");
    for k in 0..3 {
        let (tile, part) = (format!("{k}/3"), format!("p{k}.exr"));
        ok(&["render", "scene.scn", "--tile", &tile, "-o", &part], &dir);
    }
    ok(
        &[
            "render",
            "scene.scn",
            "--tile",
            "1/3",
            "--spp",
            "9",
            "-o",
            "other1.exr",
        ],
        &dir,
    );
    ok(&["render", "scene.scn", "-o", "whole.exr"], &dir);
    let p1 = bytes(dir.join("p1.exr"));
    std::fs::write(dir.join("cut1.exr"), &p1[..p1.len() * 2 / 3]).expect("write");
    std::fs::write(dir.join("final.png"), b"previous").expect("write");
    let cases: [(&[&str], &str, &str); 5] = [
        (
            &["p0.exr", "other1.exr", "p2.exr"],
            "scnc::merge::mismatch",
            "other1.exr",
        ),
        (
            &["p0.exr", "p1.exr", "p1.exr", "p2.exr"],
            "scnc::merge::overlap",
            // The band's rows come from the cost-balanced split (they move with the BVH).
            "both cover rows",
        ),
        (&["p0.exr", "p2.exr"], "scnc::merge::missing", "1/3"),
        (
            &["p0.exr", "cut1.exr", "p2.exr"],
            "scnc::merge::unreadable",
            "cut1.exr",
        ),
        (
            &["p0.exr", "whole.exr", "p2.exr"],
            "scnc::merge::not_a_tile",
            "whole.exr",
        ),
    ];
    for (files, code, names) in cases {
        let mut args = vec!["merge"];
        args.extend_from_slice(files);
        args.extend(["-o", "final.png"]);
        let err = fails(&args, &dir);
        assert!(
            err.contains(code) && err.contains(names),
            "{files:?}: {err}"
        );
        assert_eq!(bytes(dir.join("final.png")), b"previous", "{files:?}");
    }
    let err = fails(&["merge", "p0.exr", "nope.exr", "-o", "final.png"], &dir);
    assert!(err.contains("scnc::merge::unreadable"), "{err}");
    ok(
        &["merge", "p2.exr", "p0.exr", "p1.exr", "-o", "final.png"],
        &dir,
    );
}

/// The identity ignores where the scene file lies: tiles of a textured scene rendered from two
/// working directories (so every asset's resolved path differs) merge into the direct image.
#[test]
fn tiles_from_different_working_directories_merge() {
    let dir = workdir("cwd");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = |name: &str| dir.join(name).display().to_string();
    let small = ["--resolution", "24x16", "--spp", "1"];
    let run = |cwd: &Path, scene: &str, extra: &[&str], o: &str| {
        let mut args = vec!["render", scene];
        args.extend_from_slice(&small);
        args.extend_from_slice(extra);
        args.extend(["-o", o]);
        ok(&args, cwd);
    };
    run(root, "examples/textured.scn", &[], &out("direct.png"));
    run(
        root,
        "examples/textured.scn",
        &["--tile", "0/2"],
        &out("t0.exr"),
    );
    run(
        &root.join("examples"),
        "textured.scn",
        &["--tile", "1/2"],
        &out("t1.exr"),
    );
    ok(&["merge", "t0.exr", "t1.exr", "-o", "merged.png"], &dir);
    assert!(bytes(dir.join("merged.png")) == bytes(dir.join("direct.png")));
}

/// `--stats` on a tile names its window and the whole image's size, and the windows the
/// tiles report (cut by counted cost) cover the image's rows once, in order.
#[test]
fn stats_report_each_tiles_window_and_they_cover_the_image() {
    let dir = workdir("stats");
    let mut next_row = 0;
    for k in 0..4 {
        let tile = format!("{k}/4");
        let out = scnc(
            &[
                "render",
                "scene.scn",
                "--tile",
                &tile,
                "--stats",
                "-o",
                "p.exr",
            ],
            &dir,
        );
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{err}");
        let line = err
            .lines()
            .find(|l| l.starts_with("tile "))
            .unwrap_or_else(|| panic!("no tile line in --stats:\n{err}"));
        let rows = line
            .split("rows ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|r| r.split_once(".."))
            .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
            .unwrap_or_else(|| panic!("rows in {line:?}"));
        assert!(
            line.contains(&format!("tile           {tile}: columns 0..23")),
            "{line}"
        );
        assert!(line.contains("of the 23x19 image"), "{line}");
        assert_eq!(rows.0, next_row, "{line}");
        assert!(rows.1 > rows.0, "{line}");
        next_row = rows.1;
    }
    assert_eq!(next_row, 19, "the tiles end at the last row");
    let _ = std::fs::remove_dir_all(&dir);
}
