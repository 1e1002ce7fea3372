//! Front end on tests/bad_scenes/*.scn: each file holds a mistake people really make. One
//! snapshot per file of the plainly rendered diagnostics (width 100, no colour), and checks over
//! the whole folder: every scene fails with at least one error, and every label's span lies
//! inside its file and covers text.

use std::path::{Path, PathBuf};

use scnc::assets::FsLoader;
use scnc::compile::{compile_file, Compiled};
use scnc::diag::render_plain_all;

/// The scene's path relative to the crate root, so names in diagnostics are stable.
fn relative(path: &Path) -> PathBuf {
    path.strip_prefix(env!("CARGO_MANIFEST_DIR"))
        .unwrap_or(path)
        .to_path_buf()
}

fn compile(path: &Path) -> Compiled {
    compile_file(&relative(path), &FsLoader::new())
}

#[test]
fn bad_scene_diagnostics() {
    insta::glob!("bad_scenes/*.scn", |path| {
        let compiled = compile(path);
        insta::assert_snapshot!(render_plain_all(
            &compiled.diagnostics,
            &compiled.sources,
            100
        ));
    });
}

#[test]
fn every_bad_scene_fails_with_well_placed_labels() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let mut count = 0;
    let mut codes = std::collections::BTreeSet::new();
    for entry in std::fs::read_dir(&dir).expect("bad_scenes folder exists") {
        let path = entry.expect("readable entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("scn") {
            continue;
        }
        count += 1;
        let compiled = compile(&path);
        assert!(compiled.scene.is_none(), "{} compiled", path.display());
        assert!(
            compiled.diagnostics.iter().any(|d| d.is_error()),
            "{} has no error",
            path.display()
        );
        for d in &compiled.diagnostics {
            codes.insert(d.code);
            assert!(d.code.as_str().starts_with("scnc::"), "{}", d.code);
            for label in d.primary.iter().chain(&d.secondary) {
                let text = &compiled.sources.get(label.span.file).text;
                assert!(
                    label.span.end as usize <= text.len() && label.span.start <= label.span.end,
                    "{}: span {:?} outside its file ({d:?})",
                    path.display(),
                    label.span
                );
                assert!(
                    text.get(label.span.range()).is_some(),
                    "{}: span {:?} splits a character",
                    path.display(),
                    label.span
                );
                if !text.trim().is_empty() {
                    let snippet = compiled.sources.snippet(label.span);
                    assert!(
                        !snippet.trim().is_empty(),
                        "{}: label `{}` points at no text ({:?})",
                        path.display(),
                        label.message,
                        label.span
                    );
                }
            }
        }
    }
    assert!(count >= 40, "only {count} bad scenes");
    assert!(
        codes.len() >= 30,
        "only {} distinct codes: {codes:?}",
        codes.len()
    );
}
