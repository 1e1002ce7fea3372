//! `scnc render --quality / --spp / --noise / --max-samples / --variance-out` and the scene's
//! `render { quality …  noise …  max_samples … }`, through the real binary: presets set the
//! sample counts with the documented precedence, bad values are diagnostics (clap errors for
//! flags, with did-you-mean; check errors for the scene), adaptive sampling reports what it
//! achieved, and the variance image is written.

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

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A fresh directory holding a copy of examples/cornell.scn.
fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-cli-quality-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.scn"),
        dir.join("cornell.scn"),
    )
    .expect("copy the example");
    dir
}

/// The cornell box with its `render { }` block replaced by `render`.
fn scene_with_render(dir: &Path, name: &str, render: &str) -> String {
    let text = std::fs::read_to_string(dir.join("cornell.scn")).expect("read");
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("render {"))
        .collect();
    let file = format!("{name}.scn");
    std::fs::write(dir.join(&file), format!("{}\n{render}\n", kept.join("\n"))).expect("write");
    file
}

/// `--stats`' `image … N spp` figure.
fn spp_of(o: &Output) -> u32 {
    let err = stderr(o);
    let line = err
        .lines()
        .find(|l| l.starts_with("image "))
        .unwrap_or_else(|| panic!("no image line in {err}"));
    let words: Vec<&str> = line.split_whitespace().collect();
    let at = words.iter().position(|w| *w == "spp,").expect("spp");
    words[at - 1].parse().expect("a count")
}

fn render(dir: &Path, scene: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        scene,
        "-o",
        "out.pfm",
        "--resolution",
        "8x8",
        "--stats",
    ];
    args.extend_from_slice(extra);
    scnc(&args, dir)
}

#[test]
fn presets_set_the_sample_count_and_explicit_counts_win() {
    let dir = workdir("presets");
    for (flags, spp) in [
        (&["--quality", "draft"][..], 1),
        (&["--quality", "preview"], 16),
        (&["--quality", "final"], 256),
        (&["--quality", "final", "--spp", "4"], 4),
    ] {
        let o = render(&dir, "cornell.scn", flags);
        assert!(o.status.success(), "{flags:?}: {}", stderr(&o));
        assert_eq!(spp_of(&o), spp, "{flags:?}");
    }
    // In the scene: an explicit `samples` beats the preset whichever comes first; the command
    // line beats both.
    let a = scene_with_render(&dir, "a", "render { quality final  samples 9 }");
    let b = scene_with_render(&dir, "b", "render { samples 9  quality draft }");
    let c = scene_with_render(&dir, "c", "render { quality preview }");
    assert_eq!(spp_of(&render(&dir, &a, &[])), 9);
    assert_eq!(spp_of(&render(&dir, &b, &[])), 9);
    assert_eq!(spp_of(&render(&dir, &c, &[])), 16);
    assert_eq!(spp_of(&render(&dir, &a, &["--quality", "draft"])), 1);
    // The draft preset's light samples reach the IR.
    let d = scene_with_render(&dir, "d", "render { quality draft }");
    let ir = scnc(&["ir", &d], &dir);
    let json: serde_json::Value = serde_json::from_str(&stdout(&ir)).expect("IR is JSON");
    assert_eq!(json["render"]["light_samples"], 4, "{}", stdout(&ir));
    assert_eq!(json["render"]["quality"], "Draft");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_presets_and_bad_counts_are_diagnostics() {
    let dir = workdir("bad");
    let o = render(&dir, "cornell.scn", &["--quality", "fnial"]);
    assert_eq!(o.status.code(), Some(2), "clap usage error");
    assert!(stderr(&o).contains("'final'"), "{}", stderr(&o));
    let s = scene_with_render(&dir, "s", "render { quality fnial }");
    let o = scnc(&["check", &s], &dir);
    assert_eq!(o.status.code(), Some(1));
    let all = stdout(&o) + &stderr(&o);
    assert!(all.contains("unknown quality preset `fnial`"), "{all}");
    assert!(all.contains("did you mean `final`?"), "{all}");
    for spp in ["0", "100000", "-1", "lots"] {
        let o = render(&dir, "cornell.scn", &["--spp", spp]);
        assert_eq!(o.status.code(), Some(2), "--spp {spp}: {}", stderr(&o));
    }
    for noise in ["0", "1.5", "nan", "-0.01", "1%"] {
        let flag = format!("--noise={noise}");
        let o = render(&dir, "cornell.scn", &[&flag]);
        assert_eq!(o.status.code(), Some(2), "--noise {noise}");
        assert!(stderr(&o).contains("--noise"), "{}", stderr(&o));
    }
    let o = render(&dir, "cornell.scn", &["--noise", "0.1", "--spp", "4"]);
    assert_eq!(o.status.code(), Some(2), "--noise conflicts with --spp");
    let o = render(&dir, "cornell.scn", &["--max-samples", "8"]);
    assert_eq!(o.status.code(), Some(2), "--max-samples below one batch");
    let o = render(&dir, "cornell.scn", &["--variance-out", "v.png"]);
    assert_eq!(o.status.code(), Some(2), "a PNG cannot hold the variance");
    let s = scene_with_render(&dir, "n", "render { noise 0  max_samples 3 }");
    let o = scnc(&["check", &s], &dir);
    assert_eq!(o.status.code(), Some(1));
    let all = stdout(&o) + &stderr(&o);
    assert!(
        all.contains("noise") && all.contains("max_samples"),
        "{all}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn adaptive_sampling_reports_what_it_achieved() {
    let dir = workdir("adaptive");
    let o = render(
        &dir,
        "cornell.scn",
        &["--noise", "0.02", "--max-samples", "64"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    // Once in the summary, once in --stats.
    assert_eq!(
        err.matches("noise: target 2.00%, achieved RMS").count(),
        2,
        "{err}"
    );
    // 64 rounded up to whole batches: two of 2 (the first round), then four of 16.
    assert!(err.contains("hit max_samples 68"), "{err}");
    let spp = spp_of(&o);
    assert!(
        (2..=68).contains(&spp),
        "mean samples {spp} outside [the first batch, max]"
    );
    // The scene's own target, and --spp turning it off.
    let s = scene_with_render(&dir, "s", "render { noise 0.5  max_samples 256 }");
    let o = render(&dir, &s, &[]);
    assert!(
        stderr(&o).contains("noise: target 50.00%"),
        "{}",
        stderr(&o)
    );
    let o = render(&dir, &s, &["--spp", "4"]);
    assert!(!stderr(&o).contains("noise: target"), "{}", stderr(&o));
    assert_eq!(spp_of(&o), 4);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Reads a PFM's header and float values.
fn read_pfm(bytes: &[u8]) -> (u32, u32, Vec<f32>) {
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        let start = at;
        while !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        fields.push(String::from_utf8_lossy(&bytes[start..at]).into_owned());
        at += 1;
    }
    assert_eq!(fields[0], "PF");
    let (w, h): (u32, u32) = (fields[1].parse().unwrap(), fields[2].parse().unwrap());
    let little = fields[3].starts_with('-');
    let values = bytes[at..]
        .chunks_exact(4)
        .map(|c| {
            let b = [c[0], c[1], c[2], c[3]];
            if little {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
        })
        .collect();
    (w, h, values)
}

#[test]
fn the_variance_image_is_written_beside_the_picture() {
    let dir = workdir("variance");
    let o = render(
        &dir,
        "cornell.scn",
        &["--spp", "16", "--variance-out", "err.pfm"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (w, h, values) = read_pfm(&std::fs::read(dir.join("err.pfm")).expect("written"));
    assert_eq!((w, h, values.len()), (8, 8, 8 * 8 * 3));
    assert!(values.iter().all(|v| v.is_finite() && *v >= 0.0));
    assert!(values.iter().any(|v| *v > 0.0), "some pixel has noise");
    // More samples, smaller standard error (the mean over the image, 16 → 256 spp: about 4×).
    let o = render(
        &dir,
        "cornell.scn",
        &["--spp", "256", "--variance-out", "err256.pfm"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, _, more) = read_pfm(&std::fs::read(dir.join("err256.pfm")).expect("written"));
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    assert!(
        mean(&more) < 0.5 * mean(&values),
        "{} vs {}",
        mean(&more),
        mean(&values)
    );
    let o = render(&dir, "cornell.scn", &["--variance-out", "err.exr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let exr = std::fs::read(dir.join("err.exr")).expect("written");
    assert!(exr.starts_with(b"\x76\x2f\x31\x01"));
    let _ = std::fs::remove_dir_all(&dir);
}
