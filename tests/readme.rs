//! The README stays true: it opens with the two commands (render an example, run the tests),
//! the example it renders exists, and the scene shown in it compiles clean.

use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::diag::render_plain_all;

fn readme() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md"))
        .expect("README.md exists")
}

#[test]
fn readme_opens_with_the_render_and_test_commands() {
    let text = readme();
    let block: Vec<&str> = text
        .split("```sh")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a sh block")
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect();
    assert!(
        block[0].starts_with("cargo run --release -- render examples/"),
        "{}",
        block[0]
    );
    assert!(block[1].starts_with("cargo test"), "{}", block[1]);
    let example = block[0]
        .split_whitespace()
        .find(|w| w.ends_with(".scn"))
        .expect("the render command names a scene");
    assert!(std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(example)
        .is_file());
    // .ci/run runs exactly the README's test command.
    let ci = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/.ci/run"))
        .expect(".ci/run exists");
    let last = ci
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .unwrap_or("");
    assert_eq!(last.trim(), block[1].split('#').next().unwrap_or("").trim());
}

#[test]
fn the_scene_in_the_readme_compiles_clean() {
    let text = readme();
    let scene = text
        .split("```text")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a text block with a scene");
    let compiled = compile_source("readme.scn", scene, &MemLoader::new());
    assert!(
        compiled.diagnostics.is_empty(),
        "{}",
        render_plain_all(&compiled.diagnostics, &compiled.sources, 100)
    );
}
