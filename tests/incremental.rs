//! The incremental front end (`compile::Incremental`) against a fresh full compile: seeded
//! edits (characters, lines and whole statements inserted, deleted and replaced; edits that
//! break and fix the syntax; declared names renamed; includes added and removed; `--define`s)
//! are replayed on a scene, and after each one the IR and every diagnostic (severity, code,
//! message, labels with their spans, help) must be the full compile's. The common edit (one
//! object's numbers) must take the fast path.

use scnc::assets::MemLoader;
use scnc::compile::{compile_with, Incremental, Overrides, Reuse};
use scnc::source::SourceMap;
use std::path::Path;

/// A small xorshift generator: the edits are a function of the seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

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

/// One seeded edit of `text`.
fn edit(rng: &mut Rng, text: &str) -> String {
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
            return t;
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
            return if rng.below(2) == 0 {
                t.replace(&format!("{from} ="), &format!("{to} ="))
            } else {
                t.replace(from, to)
            };
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
        10 => return base_scene(),
        // An object's material changed (a material may become used or unused).
        _ => {
            if let Some(i) = (0..out.len()).find(|&i| out[i].contains("material m0 ")) {
                out[i] = out[i].replacen("material m0 ", "material m3 ", 1);
            }
        }
    }
    out.concat()
}

fn same(label: &str, incremental: &SourceMap, full: &SourceMap) -> Option<String> {
    let texts = |m: &SourceMap| -> Vec<(String, String)> {
        m.files()
            .map(|(_, f)| (f.name.clone(), f.text.to_string()))
            .collect()
    };
    (texts(incremental) != texts(full)).then(|| format!("{label}: sources differ"))
}

fn replay(seed: u64, edits: usize, overrides: Overrides) -> usize {
    let path = Path::new("scenes/edit.scn");
    let mut rng = Rng(seed);
    let mut text = base_scene();
    let mut inc = Incremental::new(overrides.clone());
    let mut fast = 0;
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
        if let Some((scene, debug)) = held.take() {
            assert_eq!(format!("{scene:?}"), debug, "{label}: a held scene changed");
        }
        if step % 2 == 0 {
            held = got.value.map(|s| {
                let debug = format!("{s:?}");
                (s, debug)
            });
        }
        if matches!(inc.reuse, Reuse::Statements { .. }) {
            fast += 1;
        }
        text = edit(&mut rng, &text);
    }
    fast
}

#[test]
fn seeded_edits_compile_as_a_fresh_compile_does() {
    let mut fast = 0;
    for seed in 1..=8u64 {
        let f = replay(
            seed.wrapping_mul(0x9E37_79B9_7F4A_7C15),
            100,
            Overrides::default(),
        );
        fast += f;
    }
    // The fast path must carry a good part of the edits, or this test checks nothing.
    assert!(fast > 80, "only {fast} edits took the incremental path");
}

#[test]
fn defines_and_frame_keep_their_values_across_edits() {
    let overrides = Overrides {
        frame: 3.0,
        defines: vec![("k".into(), "frame * 2".into())],
    };
    let fast = replay(0xDEAD_BEEF, 80, overrides);
    assert!(fast > 10, "only {fast} edits took the incremental path");
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
