//! An audit of the incremental front end (`compile::Incremental`): on one representative scene
//! (lets named by objects and one nothing names, cameras, the render block, meshes, a texture,
//! materials, objects, groups, point, environment and area lights, an include read last, and a
//! comment), every kind of one-line edit a user makes is applied to every kind of statement,
//! at the first, a middle and the last statement of its kind (insertions at the file's start,
//! middle and end): a statement of each kind inserted, a line deleted, commented out,
//! uncommented, duplicated, a digit of its value changed, its name changed. Each edit starts
//! from a memo of the scene before it (a full compile) and must give what a fresh
//! `compile_with` gives (sources, diagnostics, IR to the bit), whichever path it takes.
//!
//! The path each edit took is recorded, and the set of edits that go to the full compile must
//! be exactly [`STILL_FULL`]: an edit made incremental fails the test until it is taken off the
//! list (so the list, and the table in docs/watch.md's step 11 that copies it, stays true), and
//! an edit that falls back to the full compile fails it too. `cargo test --test
//! incremental_audit -- --nocapture` prints the table.

use scnc::assets::MemLoader;
use scnc::compile::{compile_with, Incremental, Overrides, Reuse};
use scnc::source::SourceMap;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

const ROOT: &str = "scenes/edit.scn";

/// The included file (read last, as an exporter's parts file is).
const PARTS: &str = "scnc 1\nmaterial extra = phong { diffuse #fff }\n\
                     object ball { material extra  transform { translate (2, k, 7) } }\n";

/// Another file an include may be pointed at.
const MORE: &str = "scnc 1\nobject box1 { material m2  transform { translate (4, 1, 3) } }\n";

/// The scene audited: one statement a line.
fn scene() -> String {
    let mut s = String::from(
        "scnc 1\n// a generated scene\nlet k = 2\nlet unused = 7\nlet lift = k + 1\n\
         camera main { eye (0, 5, -20)  target (0, 0, 0)  fov 40deg }\n\
         camera side { eye (10, 5, 0)  target (0, 0, 0)  fov 30deg }\n\
         render { resolution 8 x 6  camera main }\n\
         mesh box1 = box { size (1, 2, 1) }\nmesh ball = icosphere { radius 1  subdivisions 1 }\n\
         mesh spare = box { size 1 }\n\
         texture board = checker { even #e8e8e8  odd #303030  scale 8 }\n\
         material floor = phong { diffuse board  specular 0.2 }\n",
    );
    for m in 0..4 {
        s.push_str(&format!(
            "material m{m} = phong {{ diffuse rgb(0.{m}, 0.5, 0.2)  specular 0.1 }}\n"
        ));
    }
    s.push_str("object box1 { material floor  transform { scale (9, 0.1, 9) } }\n");
    for i in 0..12 {
        let mesh = ["box1", "ball"][i % 2];
        let y = ["k", "lift", "1"][i % 3];
        s.push_str(&format!(
            "object {mesh} {{ material m{}  transform {{ rotate y {}deg  translate ({i}.5, {y}, {}) }} }}\n",
            i % 4,
            i * 7,
            i % 5
        ));
        if i % 4 == 1 {
            s.push_str(&format!(
                "group g{i} {{ transform {{ translate (0, {i}, 0) }}  object ball {{ material m1 }}  group h{i} {{ object box1 {{ material m2 }} }} }}\n"
            ));
        }
    }
    s.push_str(
        "light sun = point { position (0, 10, 0)  intensity 100 }\n\
         light sky = environment { color rgb(0.1, 0.2, 0.3) }\n\
         light strip = area { mesh spare  transform { translate (0, 4, 0) }  radiance 2 }\n\
         include \"parts.scn\"\n",
    );
    s
}

/// The kind of a statement line, as the audit's table names it.
fn kind(line: &str) -> Option<&'static str> {
    let word = line.split_whitespace().next()?;
    Some(match word {
        "let" => "let",
        "camera" => "camera",
        "render" => "render",
        "mesh" => "mesh",
        "texture" => "texture",
        "material" => "material",
        "object" => "object",
        "group" => "group",
        "light" => "light",
        "include" => "include",
        _ if word.starts_with("//") => "comment",
        _ => return None,
    })
}

/// A new statement of each kind, to insert (names no statement declares).
const NEW: &[(&str, &str)] = &[
    ("let", "let fresh = 3\n"),
    (
        "camera",
        "camera fresh { eye (1, 2, 3)  target (0, 0, 0) }\n",
    ),
    ("mesh", "mesh fresh = box { size 2 }\n"),
    (
        "texture",
        "texture fresh = checker { even #fff  odd #000  scale 2 }\n",
    ),
    ("material", "material fresh = phong { diffuse #123 }\n"),
    (
        "object",
        "object ball { material m1  transform { translate (1, k, 1) } }\n",
    ),
    ("group", "group fresh { object ball { material m2 } }\n"),
    (
        "light",
        "light fresh = point { position (1, 2, 3)  intensity 5 }\n",
    ),
    ("include", "include \"more.scn\"\n"),
    ("comment", "// a note\n"),
];

fn loader(text: &str) -> MemLoader {
    let mut loader = MemLoader::new();
    loader.insert(ROOT, text.to_string());
    loader.insert("scenes/parts.scn", PARTS.to_string());
    loader.insert("scenes/more.scn", MORE.to_string());
    loader
}

/// `before` compiled in full, then `after` compiled incrementally and compared with a fresh
/// compile of it; whether the edit took the fast path.
fn audit_one(label: &str, before: &str, after: &str) -> bool {
    let path = Path::new(ROOT);
    let mut inc = Incremental::new(Overrides::default());
    let _ = inc.compile(path, &loader(before), &mut SourceMap::new());
    let loaded = loader(after);
    let mut sources = SourceMap::new();
    let got = inc.compile(path, &loaded, &mut sources);
    let mut full_sources = SourceMap::new();
    let want = compile_with(path, &loaded, &mut full_sources, &Overrides::default());
    let label = format!("{label} ({:?})", inc.reuse);
    assert_eq!(
        format!("{:#?}", got.diagnostics),
        format!("{:#?}", want.diagnostics),
        "{label}: diagnostics differ on\n{after}"
    );
    assert_eq!(
        serde_json::to_string(&got.value.as_deref()).expect("IR serialises"),
        serde_json::to_string(&want.value.as_ref()).expect("IR serialises"),
        "{label}: IR differs on\n{after}"
    );
    assert_eq!(
        format!("{:?}", got.value.as_deref()),
        format!("{:?}", want.value.as_ref()),
        "{label}: IR differs (all bits) on\n{after}"
    );
    let texts = |m: &SourceMap| -> Vec<(String, String)> {
        m.files()
            .map(|(_, f)| (f.name.clone(), f.text.to_string()))
            .collect()
    };
    assert_eq!(texts(&sources), texts(&full_sources), "{label}: sources");
    assert_ne!(inc.reuse, Reuse::Unchanged, "{label}: no edit");
    matches!(inc.reuse, Reuse::Statements { .. })
}

/// The last digit of `line` changed (or `None` when it has none).
fn value_edited(line: &str) -> Option<String> {
    let at = line.rfind(|c: char| c.is_ascii_digit())?;
    let digit = line.as_bytes()[at] - b'0';
    let new = char::from(b'0' + if digit == 9 { 8 } else { digit + 1 });
    Some(format!("{}{new}{}", &line[..at], &line[at + 1..]))
}

/// `line` with its declared name given a `2` (or `None` when it declares none).
fn renamed(line: &str) -> Option<String> {
    let mut words = line.split_whitespace();
    let kind = words.next()?;
    if !matches!(
        kind,
        "let" | "camera" | "mesh" | "texture" | "material" | "group" | "light"
    ) {
        return None;
    }
    let name = words.next()?;
    let at = line.find(name)? + name.len();
    Some(format!("{}2{}", &line[..at], &line[at..]))
}

/// One audited edit: the table's row (statement kind), column (edit) and place, and the texts
/// before and after it.
struct Case {
    kind: &'static str,
    edit: &'static str,
    place: &'static str,
    before: String,
    after: String,
}

fn cases() -> Vec<Case> {
    let base = scene();
    let lines: Vec<&str> = base.split_inclusive('\n').collect();
    let join = |parts: &[&str]| parts.concat();
    let mut cases = Vec::new();
    let mut by_kind: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    for (i, line) in lines.iter().enumerate() {
        if let Some(k) = kind(line) {
            by_kind.entry(k).or_default().push(i);
        }
    }
    for (&k, at) in &by_kind {
        let k: &'static str = NEW
            .iter()
            .map(|(n, _)| *n)
            .chain(["render"])
            .find(|n| *n == k)
            .expect("every kind is listed");
        let mut places = vec![
            ("first", at[0]),
            ("middle", at[at.len() / 2]),
            ("last", at[at.len() - 1]),
        ];
        places.dedup_by_key(|p| p.1);
        for (place, i) in places {
            let line = lines[i];
            let with = |new: &str| -> String {
                let mut v = lines.clone();
                v[i] = new;
                join(&v)
            };
            let mut push = |edit, before: String, after: String| {
                cases.push(Case {
                    kind: k,
                    edit,
                    place,
                    before,
                    after,
                })
            };
            push("delete", base.clone(), with(""));
            if k != "comment" {
                let commented = format!("// {line}");
                push("comment out", base.clone(), with(&commented));
                push("uncomment", with(&commented), base.clone());
            }
            push("duplicate", base.clone(), with(&format!("{line}{line}")));
            if let Some(v) = value_edited(line) {
                push("value", base.clone(), with(&v));
            } else if k == "include" {
                push("value", base.clone(), with("include \"more.scn\"\n"));
            } else if k == "comment" {
                push(
                    "value",
                    base.clone(),
                    with("// a generated scene, edited\n"),
                );
            }
            if let Some(r) = renamed(line) {
                push("rename", base.clone(), with(&r));
            }
        }
    }
    let middle = lines.len() / 2;
    for &(k, new) in NEW {
        for (place, i) in [("start", 1), ("middle", middle), ("end", lines.len())] {
            let mut v = lines.clone();
            v.insert(i, new);
            cases.push(Case {
                kind: k,
                edit: "insert",
                place,
                before: base.clone(),
                after: join(&v),
            });
        }
    }
    cases
}

/// The one-line edits that still go to the full compile, as `kind edit place`. Each is named
/// with why in docs/watch.md (step 11 and the fifteenth session's table). Empty since the
/// eighteenth session (`include insert start` and `include insert middle`, a file read before
/// another, renumber the later files' ids).
const STILL_FULL: &[&str] = &[];

#[test]
fn every_one_line_edit_compiles_as_a_fresh_compile_does_and_the_full_ones_are_listed() {
    let mut table: BTreeMap<(&str, &str), Vec<(&str, bool)>> = BTreeMap::new();
    let mut full = BTreeSet::new();
    for case in cases() {
        let label = format!("{} {} {}", case.kind, case.edit, case.place);
        let fast = audit_one(&label, &case.before, &case.after);
        if !fast {
            full.insert(label);
        }
        table
            .entry((case.kind, case.edit))
            .or_default()
            .push((case.place, fast));
    }
    let edits: usize = table.values().map(Vec::len).sum();
    println!("{edits} one-line edits, {} full compiles", full.len());
    println!("| statement | edit | incremental | full compile |\n|---|---|---|---|");
    for ((kind, edit), places) in &table {
        let list = |want: bool| -> String {
            let p: Vec<&str> = places
                .iter()
                .filter(|(_, f)| *f == want)
                .map(|(p, _)| *p)
                .collect();
            if p.is_empty() {
                "—".into()
            } else {
                p.join(", ")
            }
        };
        println!("| {kind} | {edit} | {} | {} |", list(true), list(false));
    }
    let listed: BTreeSet<String> = STILL_FULL.iter().map(|s| s.to_string()).collect();
    let newly_fast: Vec<&String> = listed.difference(&full).collect();
    let newly_full: Vec<&String> = full.difference(&listed).collect();
    assert!(
        newly_fast.is_empty() && newly_full.is_empty(),
        "now incremental (take off STILL_FULL): {newly_fast:#?}\nnow full (put on STILL_FULL): {newly_full:#?}"
    );
}

/// The new fast paths one after another on one memo (each edit from the last one's memo, not
/// from a full compile), every result compared with a fresh compile: a named `let` removed
/// (its readers then fail) and the scene edited on; lines commented out and uncommented; a
/// declaration's line duplicated in a scene with an include and the copy edited and removed.
#[test]
fn the_fifteenth_session_paths_chain_as_a_full_compile_does() {
    let path = Path::new(ROOT);
    let mut text = scene();
    let mut inc = Incremental::new(Overrides::default());
    let _ = inc.compile(path, &loader(&text), &mut SourceMap::new());
    let material = "material m2 = phong { diffuse rgb(0.2, 0.5, 0.2)  specular 0.1 }\n";
    let object =
        "object ball { material m1  transform { rotate y 7deg  translate (1.5, lift, 1) } }\n";
    let edits: &[(&str, String)] = &[
        ("let k = 2\n", "// let k = 2\n".into()),
        ("translate (2.5, 1, 2)", "translate (2.5, 1, 3)".into()),
        ("// let k = 2\n", "let k = 2\n".into()),
        ("let lift = k + 1\n", String::new()),
        ("translate (3.5, k, 3)", "translate (3.5, k, 2)".into()),
        (object, format!("// {object}")),
        (material, format!("{material}{material}")),
        (
            "rgb(0.2, 0.5, 0.2)  specular 0.1 }\nmaterial m2",
            "rgb(0.2, 0.5, 0.3)  specular 0.1 }\nmaterial m2".into(),
        ),
        (&format!("// {object}"), object.to_string()),
        ("let k = 2\n", String::new()),
        ("material m3", "// material m3".into()),
        ("translate (3.5, k, 2)", "translate (3.5, k, 1)".into()),
        ("// material m3", "material m3".into()),
        ("let unused = 7\n", "// let unused = 7\n".into()),
        // The included file read twice; the last include commented out (its name still in
        // the comment and in the other include: not a removal of the file).
        ("light sun", "include \"parts.scn\"\nlight sun".into()),
        (
            "2 }\ninclude \"parts.scn\"",
            "2 }\n// include \"parts.scn\"".into(),
        ),
        (
            "2 }\n// include \"parts.scn\"",
            "2 }\ninclude \"parts.scn\"".into(),
        ),
    ];
    let mut fast = 0;
    for (from, to) in edits {
        let edited = text.replacen(from, to, 1);
        assert_ne!(edited, text, "{from}");
        text = edited;
        let loaded = loader(&text);
        let mut sources = SourceMap::new();
        let got = inc.compile(path, &loaded, &mut sources);
        let want = compile_with(path, &loaded, &mut SourceMap::new(), &Overrides::default());
        let label = format!("{from:?} -> {to:?} ({:?})", inc.reuse);
        assert_eq!(
            format!("{:#?}", got.diagnostics),
            format!("{:#?}", want.diagnostics),
            "{label}: diagnostics differ on\n{text}"
        );
        assert_eq!(
            format!("{:?}", got.value.as_deref()),
            format!("{:?}", want.value.as_ref()),
            "{label}: IR differs on\n{text}"
        );
        fast += usize::from(matches!(inc.reuse, Reuse::Statements { .. }));
        println!("{label}");
    }
    // The first six (a named `let` commented out, an object edited, the `let` uncommented, a
    // named `let` removed, an object edited, one commented out) at least.
    assert!(fast >= 6, "{fast} of {} incremental", edits.len());
}
