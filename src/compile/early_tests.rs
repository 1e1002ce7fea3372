//! Tests of the driver's pre-check (`check::PreCheck`): a compile that checks top-level
//! statements while parsing gives exactly the result of one that keeps every statement's AST
//! for the check (the IR, and every diagnostic with its span, code and message, in order), with
//! and without `--frame` and `--define` overrides.

use std::path::Path;

use super::{Driver, Overrides};
use crate::assets::{FsLoader, Loader, MemLoader};

/// The compile with the pre-check (as `compile_with`, from text).
fn early(name: &str, text: &str, loader: &dyn Loader, overrides: &Overrides) -> super::Compiled {
    let mut d = Driver::checking(loader, overrides);
    d.add_root(Path::new(name), name, text.as_bytes());
    for (name, value) in std::mem::take(&mut d.pending_defines) {
        d.add_define(&name, &value);
    }
    d.finish()
}

/// The compile without the pre-check: every statement parsed, then checked.
fn plain(name: &str, text: &str, loader: &dyn Loader, overrides: &Overrides) -> super::Compiled {
    let mut d = Driver::new(loader);
    d.frame = overrides.frame;
    d.add_root(Path::new(name), name, text.as_bytes());
    for (name, value) in &overrides.defines {
        d.add_define(name, value);
    }
    d.finish()
}

fn assert_same(name: &str, text: &str, loader: &dyn Loader) {
    assert_same_with(name, text, loader, &Overrides::default());
}

fn assert_same_with(name: &str, text: &str, loader: &dyn Loader, overrides: &Overrides) {
    let early = early(name, text, loader, overrides);
    let plain = plain(name, text, loader, overrides);
    assert_eq!(
        format!("{:?}", early.diagnostics),
        format!("{:?}", plain.diagnostics),
        "{name} {overrides:?}"
    );
    assert_eq!(
        format!("{:?}", early.scene),
        format!("{:?}", plain.scene),
        "{name} {overrides:?}"
    );
}

/// How many statements the pre-check took, and how many it left for the check.
fn taken_and_kept(text: &str, overrides: &Overrides) -> (usize, usize) {
    let loader = MemLoader::new();
    let mut d = Driver::checking(&loader, overrides);
    d.add_root(Path::new("count.scn"), "count.scn", text.as_bytes());
    let placed = d
        .pre
        .map(crate::check::PreCheck::into_placed)
        .unwrap_or_default();
    (placed.len(), d.statements.len())
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
    assert_eq!(taken_and_kept(MIXED, &Overrides::default()), (14, 14));
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

/// `let`s before and after their uses, redefined, in error, poisoned then declared again,
/// naming later ones; meshes and materials built from them.
const LETS: &str = "scnc 1
camera c { eye (0, 1, -5)  target (0, 0, 0) }
let k = 2
let dims = (k, 1, 0.5)
let tint = rgb(0.5, 0.25, k / 8)
let angle = 30deg * k
material red = phong { diffuse tint  specular (0.1 * k) }
mesh crate = box { size dims }
mesh ball = sphere { radius (k / 4)  segments (8 * k) }
object crate { material red  transform { rotate y angle  translate (k, frame, 0) } }
group g { transform { scale k }  object ball { material red  transform { translate dims } } }
object ball { material red  transform { translate (late, 0, 0) } }
mesh early_late = box { size late }
let late = 3
let k = 5
object crate { material red  transform { translate (k, late, 0) } }
let bad = 1 / 0
let again = bad + 1
let bad = 4
object crate { material red  transform { translate (bad, again, k) } }
let after = k + late
mesh tall = box { size (1, after, 1) }
object tall { material red  transform { translate (after, 0, 0) } }
let frame = 1
let uses_later = later_still * 2
let later_still = 1
object ball { material red  transform { scale uses_later } }
";

#[test]
fn constants_evaluated_while_parsing_change_nothing() {
    let loader = MemLoader::new();
    let overrides = [
        Overrides::default(),
        Overrides {
            frame: 7.5,
            defines: vec![],
        },
        Overrides {
            frame: 2.0,
            defines: vec![
                ("k".into(), "3".into()),
                ("angle".into(), "k * 10deg".into()),
            ],
        },
        // The wrong type, a value naming a later constant, one no `let` uses, a syntax error.
        Overrides {
            frame: 0.0,
            defines: vec![("k".into(), "(1, 2)".into())],
        },
        Overrides {
            frame: 0.0,
            defines: vec![("dims".into(), "(late, 1, 1)".into())],
        },
        Overrides {
            frame: 0.0,
            defines: vec![
                ("nothing".into(), "1".into()),
                ("tint".into(), "#ff8800".into()),
            ],
        },
        Overrides {
            frame: 0.0,
            defines: vec![("k".into(), "(1, ".into())],
        },
    ];
    for o in &overrides {
        assert_same_with("lets.scn", LETS, &loader, o);
    }
    // The constants before the first `let` in error are evaluated early, and what uses only
    // them is taken; what names a later or failed constant is left for the check.
    assert_eq!(taken_and_kept(LETS, &Overrides::default()), (11, 16));
    // A define that does not parse stops every early `let` (and what uses one).
    assert_eq!(taken_and_kept(LETS, &overrides[6]), (0, 27));
    // Cut after every line, and each line left out in turn, under two of the overrides.
    let lines: Vec<&str> = LETS.lines().collect();
    for n in 1..lines.len() {
        let mut text = lines[..n].join("\n");
        text.push('\n');
        let mut without: Vec<&str> = lines.clone();
        without.remove(n);
        let without = without.join("\n");
        for o in &overrides[..3] {
            assert_same_with("cut.scn", &text, &loader, o);
            assert_same_with("without.scn", &without, &loader, o);
        }
    }
}
