//! Tests of the driver's pre-check (`check::PreCheck`): a compile that checks top-level
//! placements while parsing gives exactly the result of one that keeps every statement's AST
//! for the check (the IR, and every diagnostic with its span, code and message, in order).

use std::path::Path;

use super::{compile_source, Driver};
use crate::assets::{FsLoader, Loader, MemLoader};

/// The compile without the pre-check: every statement parsed, then checked.
fn plain(name: &str, text: &str, loader: &dyn Loader) -> super::Compiled {
    let mut d = Driver::new(loader);
    d.add_root(Path::new(name), name, text.as_bytes());
    d.finish()
}

fn assert_same(name: &str, text: &str, loader: &dyn Loader) {
    let early = compile_source(name, text, loader);
    let plain = plain(name, text, loader);
    assert_eq!(
        format!("{:?}", early.diagnostics),
        format!("{:?}", plain.diagnostics),
        "{name}"
    );
    assert_eq!(
        format!("{:?}", early.scene),
        format!("{:?}", plain.scene),
        "{name}"
    );
}

const MIXED: &str = "scnc 1
camera c { eye (0, 1, -5)  target (0, 0, 0) }
material red = phong { diffuse 0.5 }
texture board = checker { even #e8e8e8  odd #303030  scale 8 }
material checked = phong { diffuse board }
material red = phong { diffuse 0.3 }
material bright = phong { diffuse 2 }
material konst = phong { specular k }
mesh ball = sphere
object ball { material checked }
object ball { material bright }
object ball { material konst }
object ball { material red  transform { rotate y 30deg  translate (1, 0, 0) } }
object ball { material later }
object ball { material red  transform { translate (k, 0, 0) } }
object ball { material red  transform { translate (frame, 0, 0)  matrix [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1] } }
group g { transform { scale 2 }  object ball { material red }  group h { object ball { material red } } }
group h { object ball { material red } }
group g2 { object box { material red } }
group g3 { object ball { material red } }
object ball { material red  material red }
let k = 2
material later = phong { diffuse 0.2 }
material unused = phong { diffuse 0.1 }
mesh box = box
group g3 { object ball { material red } }
object box { material red  transform { scale 0 } }
object ball { material red }
";

#[test]
fn placements_checked_while_parsing_change_nothing() {
    let loader = MemLoader::new();
    assert_same("mixed.scn", MIXED, &loader);
    // Both kinds are there: placements checked early, and others left for the check.
    let mut d = Driver::checking(&loader, 0.0);
    d.add_root(Path::new("mixed.scn"), "mixed.scn", MIXED.as_bytes());
    let placed = d
        .pre
        .map(crate::check::PreCheck::into_placed)
        .unwrap_or_default();
    assert_eq!((placed.len(), d.statements.len()), (11, 17));
    // Cut after every line: forward references, errors and unused declarations vary.
    let lines: Vec<&str> = MIXED.lines().collect();
    for n in 1..lines.len() {
        let mut text = lines[..n].join("\n");
        text.push('\n');
        assert_same("cut.scn", &text, &loader);
        // And with each line left out in turn.
        let mut without: Vec<&str> = lines.clone();
        without.remove(n);
        assert_same("without.scn", &without.join("\n"), &loader);
    }
}

#[test]
fn every_example_and_bad_scene_compiles_as_without_the_pre_check() {
    let loader = FsLoader::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut seen = 0;
    for dir in ["examples", "tests/bad_scenes", "tests/fixtures"] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "scn") {
                let Ok(bytes) = std::fs::read(&path) else {
                    continue;
                };
                let text = String::from_utf8_lossy(&bytes);
                assert_same(&path.display().to_string(), &text, &loader);
                seen += 1;
            }
        }
    }
    assert!(seen > 20, "only {seen} scenes found");
}
