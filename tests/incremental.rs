//! The incremental front end (`compile::Incremental`) against a fresh full compile: seeded
//! edits (characters, lines and whole statements inserted, deleted and replaced; edits that
//! break and fix the syntax; declared names renamed; includes added and removed; `--define`s)
//! are replayed on a scene, and after each one the IR and every diagnostic (severity, code,
//! message, labels with their spans, help) must be the full compile's. The common edit (one
//! object's numbers) of a scene the fast path covers (one file without includes, no error)
//! must take it, every time.

use scnc::assets::MemLoader;
use scnc::compile::{compile_with, Incremental, Overrides, Reuse};
use scnc::source::SourceMap;
use scnc::testing::SplitMix64;
use std::path::Path;

fn base_scene() -> String {
    let mut s = String::from(
        "scnc 1\n// a scene for edits\nlet k = 2\nlet spin = 15deg\n\
         camera main { eye (0, 5, -20)  target (0, 0, 0)  fov 40deg }\n\
         render { resolution 8 x 6 }\n\
         mesh box1 = box { size (1, 2, 1) }\nmesh ball = icosphere { radius 1  subdivisions 1 }\n\
         mesh spare = box { size 1 }\n",
    );
    for m in 0..4 {
        s.push_str(&format!(
            "material m{m} = phong {{ diffuse rgb(0.{m}, 0.5, 0.2)  specular 0.1 }}\n"
        ));
    }
    for i in 0..24 {
        let mesh = ["box1", "ball"][i % 2];
        s.push_str(&format!(
            "object {mesh} {{ material m{}  transform {{ rotate y {}deg  translate ({i}.5, k, {}) }} }}\n",
            i % 4,
            i * 7,
            i % 5
        ));
        if i % 8 == 3 {
            s.push_str(&format!(
                "group g{i} {{ transform {{ translate (0, {i}, 0) }}  object ball {{ material m1 }} }}\n"
            ));
        }
    }
    s.push_str("light sun = point { position (0, 10, 0)  intensity 100 }\n");
    s
}

const INCLUDED: &str = "scnc 1\nmaterial extra = phong { diffuse #fff }\n";

/// One seeded edit of `text`, and whether it was the common edit (a digit of an `object`
/// line replaced).
fn edit(rng: &mut SplitMix64, text: &str) -> (String, bool) {
    let lines: Vec<&str> = text.split_inclusive('\n').collect();
    let line = rng.below(lines.len());
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    match rng.below(12) {
        // The common edit: a number of an object changes.
        0..=3 => {
            let objects: Vec<usize> = (0..lines.len())
                .filter(|&i| lines[i].starts_with("object"))
                .collect();
            if let Some(&i) = objects.get(rng.below(objects.len())) {
                let digits: Vec<usize> = out[i]
                    .char_indices()
                    .filter(|(_, c)| c.is_ascii_digit())
                    .map(|(p, _)| p)
                    .collect();
                if let Some(&p) = digits.get(rng.below(digits.len())) {
                    let d = char::from(b'0' + rng.below(10) as u8);
                    out[i].replace_range(p..p + 1, &d.to_string());
                    return (out.concat(), true);
                }
            }
        }
        // A character inserted, deleted or replaced anywhere.
        4 => {
            let mut t = text.to_string();
            let mut p = rng.below(t.len() + 1);
            while !t.is_char_boundary(p) {
                p -= 1;
            }
            let c = [" ", "{", "}", "(", "x", "1", "\n", "\"", "#", "/", "m"][rng.below(11)];
            match rng.below(3) {
                0 => t.insert_str(p, c),
                1 if p < t.len() => {
                    t.remove(p);
                }
                _ => {
                    if p < t.len() {
                        t.remove(p);
                    }
                    t.insert_str(p, c);
                }
            }
            return (t, false);
        }
        // A line deleted, duplicated or moved.
        5 => {
            let l = out.remove(line);
            match rng.below(3) {
                0 => {}
                1 => {
                    out.insert(line, l.clone());
                    out.insert(line, l);
                }
                _ => {
                    let to = rng.below(out.len() + 1);
                    out.insert(to, l);
                }
            }
        }
        // A whole statement inserted.
        6 => {
            let stmt = match rng.below(5) {
                0 => format!("object box1 {{ material m{} }}\n", rng.below(6)),
                1 => "object nosuch { material m0 }\n".to_string(),
                2 => "material m9 = phong { diffuse #888 }\n".to_string(),
                3 => format!("let k{} = 3\n", rng.below(3)),
                _ => "object spare { material m2  transform { scale 2 } }\n".to_string(),
            };
            out.insert(line, stmt);
        }
        // A declared name renamed at its declaration, or everywhere.
        7 => {
            let (from, to) =
                [("m1", "m1x"), ("box1", "crate"), ("k", "kk"), ("m3", "m2")][rng.below(4)];
            let t: String = out.concat();
            let renamed = if rng.below(2) == 0 {
                t.replace(&format!("{from} ="), &format!("{to} ="))
            } else {
                t.replace(from, to)
            };
            return (renamed, false);
        }
        // Includes added and removed.
        8 => {
            if text.contains("include") {
                out.retain(|l| !l.starts_with("include"));
            } else {
                out.insert(
                    1 + rng.below(out.len() - 1),
                    "include \"extra.scn\"\n".into(),
                );
            }
        }
        // Break the syntax of a line, or put the base back (fixes everything).
        9 => {
            let cut = out[line].len() / 2;
            out[line].truncate(cut);
            out[line].push('\n');
        }
        10 => return (base_scene(), false),
        // An object's material changed (a material may become used or unused).
        _ => {
            if let Some(i) = (0..out.len()).find(|&i| out[i].contains("material m0 ")) {
                out[i] = out[i].replacen("material m0 ", "material m3 ", 1);
            }
        }
    }
    (out.concat(), false)
}

fn same(label: &str, incremental: &SourceMap, full: &SourceMap) -> Option<String> {
    let texts = |m: &SourceMap| -> Vec<(String, String)> {
        m.files()
            .map(|(_, f)| (f.name.clone(), f.text.to_string()))
            .collect()
    };
    (texts(incremental) != texts(full)).then(|| format!("{label}: sources differ"))
}

/// How a replay's edits went through the incremental front end.
#[derive(Default)]
struct Replayed {
    /// Edits that took the fast path (`Reuse::Statements`).
    fast: usize,
    /// Common edits (one object's number) made to a scene that compiled without an error.
    number_edits_of_clean_scenes: usize,
    /// Those of them that took the fast path.
    number_edits_fast: usize,
}

fn replay(seed: u64, edits: usize, overrides: Overrides) -> Replayed {
    let path = Path::new("scenes/edit.scn");
    let mut rng = SplitMix64(seed);
    let mut text = base_scene();
    let mut inc = Incremental::new(overrides.clone());
    let mut replayed = Replayed::default();
    let mut number_edit_of_clean_scene = false;
    // Every other step holds its scene across the next edit, as `scnc watch` may: the memo
    // then edits a copy (`Arc::make_mut`), and the held scene must not change.
    let mut held: Option<(std::sync::Arc<scnc::ir::SceneDesc>, String)> = None;
    for step in 0..edits {
        let mut loader = MemLoader::new();
        loader.insert(path, text.clone());
        loader.insert("scenes/extra.scn", INCLUDED);
        let mut inc_sources = SourceMap::new();
        let got = inc.compile(path, &loader, &mut inc_sources);
        let mut full_sources = SourceMap::new();
        let want = compile_with(path, &loader, &mut full_sources, &overrides);
        let label = format!("seed {seed} step {step} ({:?})", inc.reuse);
        assert_eq!(same(&label, &inc_sources, &full_sources), None);
        assert_eq!(
            format!("{:#?}", got.diagnostics),
            format!("{:#?}", want.diagnostics),
            "{label}: diagnostics differ on\n{text}"
        );
        assert_eq!(
            serde_json::to_string(&got.value.as_deref()).expect("IR serialises"),
            serde_json::to_string(&want.value.as_ref()).expect("IR serialises"),
            "{label}: IR differs on\n{text}"
        );
        assert_eq!(
            format!("{:?}", got.value.as_deref()),
            format!("{:?}", want.value.as_ref()),
            "{label}: IR differs (all bits) on\n{text}"
        );
        // The fast path covers one file without includes (`Incremental`'s memo).
        let clean = !got.has_errors() && !text.contains("include");
        if let Some((scene, debug)) = held.take() {
            assert_eq!(format!("{scene:?}"), debug, "{label}: a held scene changed");
        }
        if step % 2 == 0 {
            held = got.value.map(|s| {
                let debug = format!("{s:?}");
                (s, debug)
            });
        }
        let fast = matches!(inc.reuse, Reuse::Statements { .. });
        let reused = fast || matches!(inc.reuse, Reuse::Unchanged);
        replayed.fast += usize::from(fast);
        if number_edit_of_clean_scene {
            replayed.number_edits_of_clean_scenes += 1;
            replayed.number_edits_fast += usize::from(reused);
        }
        let (edited, number_edit) = edit(&mut rng, &text);
        number_edit_of_clean_scene = clean && number_edit;
        text = edited;
    }
    replayed
}

#[test]
fn seeded_edits_compile_as_a_fresh_compile_does() {
    let mut total = Replayed::default();
    for seed in 1..=8u64 {
        let r = replay(
            seed.wrapping_mul(0xD1B5_4A32_D192_ED03),
            100,
            Overrides::default(),
        );
        total.fast += r.fast;
        total.number_edits_of_clean_scenes += r.number_edits_of_clean_scenes;
        total.number_edits_fast += r.number_edits_fast;
    }
    eprintln!(
        "fast {} of 800; number edits of clean scenes {}, fast {}",
        total.fast, total.number_edits_of_clean_scenes, total.number_edits_fast
    );
    assert_fast_path_taken(&total, 20);
}

/// The common edit (one object's number) of a scene without errors always takes the fast
/// path, and the replay made enough of them for that to mean something.
fn assert_fast_path_taken(r: &Replayed, at_least: usize) {
    assert!(
        r.number_edits_of_clean_scenes >= at_least,
        "only {} number edits of clean scenes: the replay checks too little of the fast path",
        r.number_edits_of_clean_scenes
    );
    assert_eq!(
        r.number_edits_fast, r.number_edits_of_clean_scenes,
        "a number edit of a clean scene took the full path"
    );
}

#[test]
fn defines_and_frame_keep_their_values_across_edits() {
    let overrides = Overrides {
        frame: 3.0,
        defines: vec![("k".into(), "frame * 2".into())],
    };
    let r = replay(0xDEAD_BEEF, 160, overrides);
    eprintln!(
        "fast {} of 160; number edits of clean scenes {}, fast {}",
        r.fast, r.number_edits_of_clean_scenes, r.number_edits_fast
    );
    assert_fast_path_taken(&r, 4);
}

#[test]
fn an_object_edit_rechecks_that_object_alone() {
    let path = Path::new("edit.scn");
    let text = base_scene();
    let mut inc = Incremental::new(Overrides::default());
    let mut loader = MemLoader::new();
    loader.insert(path, text.clone());
    let mut sources = SourceMap::new();
    let _ = inc.compile(path, &loader, &mut sources);
    assert_eq!(inc.reuse, Reuse::Full);
    let edited = text.replacen("translate (5.5, k, 0)", "translate (5.5, k, 9)", 1);
    assert_ne!(edited, text);
    loader.insert(path, edited);
    let _ = inc.compile(path, &loader, &mut sources);
    assert_eq!(
        inc.reuse,
        Reuse::Statements {
            parsed: 2,
            checked: 1
        }
    );
    let _ = inc.compile(path, &loader, &mut sources);
    assert_eq!(inc.reuse, Reuse::Unchanged);
}
