//! Diagnostic rendering (plain, fancy, JSON) across files, and the batched fast path of the
//! parser on files larger than one batch.

use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::diag::{render_fancy, render_json, render_plain};

fn cycle() -> scnc::compile::Compiled {
    let mut loader = MemLoader::new();
    loader.insert("dir/b.scn", b"scnc 1\ninclude \"../a.scn\"\n".to_vec());
    loader.insert("a.scn", b"scnc 1\ninclude \"dir/b.scn\"\n".to_vec());
    compile_source("a.scn", "scnc 1\ninclude \"dir/b.scn\"\n", &loader)
}

#[test]
fn include_cycle_is_rendered_in_every_format_with_both_files() {
    let c = cycle();
    let d = c
        .diagnostics
        .iter()
        .find(|d| d.code == "scnc::include::cycle")
        .expect("cycle reported");
    let plain = render_plain(d, &c.sources, 100);
    assert!(plain.contains("--> dir/b.scn:2:9"), "{plain}");
    assert!(plain.contains("::: a.scn:2:9"), "{plain}");
    let fancy = render_fancy(d, &c.sources, false);
    assert!(fancy.contains("scnc::include::cycle"), "{fancy}");
    assert!(
        fancy.contains("dir/b.scn") && fancy.contains("a.scn"),
        "{fancy}"
    );
    assert!(
        !fancy.contains('\u{1b}'),
        "no colour codes when colour is off"
    );
    let json: serde_json::Value =
        serde_json::from_str(&render_json(&c.diagnostics, &c.sources)).expect("valid JSON");
    let labels = &json["diagnostics"][0]["labels"];
    assert_eq!(labels[0]["file"], "dir/b.scn");
    assert_eq!(labels[1]["file"], "a.scn");
    assert_eq!(labels[1]["primary"], false);
}

#[test]
fn plain_rendering_clips_long_lines_to_the_width() {
    let long = format!("scnc 1\nlet a = {}1 + \"x\"\n", "1 + ".repeat(60));
    let c = compile_source("long.scn", &long, &MemLoader::new());
    let d = c
        .diagnostics
        .iter()
        .find(|d| d.code == "scnc::check::bad_operands")
        .expect("type error");
    let text = render_plain(d, &c.sources, 40);
    for line in text.lines() {
        let Some((_, body)) = line.split_once(" | ") else {
            continue;
        };
        let shown = if body.contains('^') {
            // Spaces and carets; the label text follows.
            body.trim_end_matches(|c: char| c != '^').len()
        } else {
            body.chars().count()
        };
        assert!(shown <= 40, "{line}\n{text}");
    }
}

#[test]
fn large_files_parse_in_batches_with_exact_positions() {
    let mut text =
        String::from("scnc 1\ncamera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }\n");
    text.push_str("material grey = phong { diffuse 0.5 }\nmesh ball = sphere { }\n");
    for i in 0..4000 {
        text.push_str(&format!(
            "object ball {{ material grey  transform {{ translate ({i}, 0, 0) }} }}\n"
        ));
    }
    assert!(text.len() > 3 * 64 * 1024);
    let c = compile_source("big.scn", &text, &MemLoader::new());
    let scene = c.scene.as_ref().expect("valid");
    assert_eq!(scene.objects.len(), 4000);
    assert_eq!(scene.objects[3999].world_from_object.w_axis.x, 3999.0);
    // An error far into the file, and a statement split over lines, still work.
    let broken = text.replacen("translate (3500, 0, 0)", "translate (3500, 0, 0deg)", 1)
        + "let split = 1 +\n  2\n";
    let c = compile_source("big.scn", &broken, &MemLoader::new());
    let d = c
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .expect("the angle inside a vector is an error");
    let span = d.primary.as_ref().expect("labelled").span;
    assert_eq!(c.sources.snippet(span), "0deg");
    assert_eq!(c.diagnostics.iter().filter(|d| d.is_error()).count(), 1);
}
