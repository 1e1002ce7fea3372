//! `scnc fmt` over every example and test scene: formatting is idempotent and never changes
//! meaning (the IR, spans aside, or the diagnostics of a scene that does not compile, are the
//! same before and after); comments survive; the examples are kept formatted; `--check` exit
//! codes and diff; a file with syntax errors is left untouched.

use std::path::{Path, PathBuf};
use std::process::Command;

use scnc::assets::FsLoader;
use scnc::compile::compile_source;
use scnc::fmt::format;
use scnc::source::FileId;
use serde_json::Value;

fn scenes_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("the directory is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            scenes_under(&path, out);
        } else if path.extension().is_some_and(|e| e == "scn") {
            out.push(path);
        }
    }
}

fn scenes(root: &str) -> Vec<PathBuf> {
    let mut out = Vec::new();
    scenes_under(&Path::new(env!("CARGO_MANIFEST_DIR")).join(root), &mut out);
    assert!(!out.is_empty(), "no scenes under {root}");
    out
}

/// Replaces every span (`"FILE#START..END"`) with `"span"`: formatting moves text.
fn without_spans(v: &mut Value) {
    match v {
        Value::String(s) => {
            let is_span = s.split_once('#').is_some_and(|(file, range)| {
                file.bytes().all(|b| b.is_ascii_digit())
                    && range.split_once("..").is_some_and(|(a, b)| {
                        !a.is_empty()
                            && !b.is_empty()
                            && a.bytes().chain(b.bytes()).all(|b| b.is_ascii_digit())
                    })
            });
            if is_span {
                *s = "span".into();
            }
        }
        Value::Object(map) => map.values_mut().for_each(without_spans),
        Value::Array(items) => items.iter_mut().for_each(without_spans),
        _ => {}
    }
}

/// What a scene means: its IR without spans, or (if it does not compile) its diagnostics'
/// codes and messages.
fn meaning(path: &Path, text: &str) -> Value {
    let compiled = compile_source(&path.display().to_string(), text, &FsLoader::new());
    let mut ir = serde_json::to_value(&compiled.scene).expect("the IR serialises");
    without_spans(&mut ir);
    let diags: Vec<String> = compiled
        .diagnostics
        .iter()
        .map(|d| format!("{:?}: {}", d.code, d.message))
        .collect();
    serde_json::json!({ "ir": ir, "diagnostics": diags })
}

fn comments(text: &str) -> Vec<String> {
    scnc::fmt::tokens::tokenize(text)
        .into_iter()
        .filter(|t| {
            matches!(
                t.kind,
                scnc::fmt::tokens::TokenKind::LineComment
                    | scnc::fmt::tokens::TokenKind::BlockComment
            )
        })
        .map(|t| t.text.to_string())
        .collect()
}

#[test]
fn formatting_is_idempotent_and_keeps_meaning_and_comments() {
    let mut formatted_count = 0;
    for path in scenes("examples").into_iter().chain(scenes("tests")) {
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue; // binary fixtures
        };
        let Some(once) = format(FileId(0), &text).value else {
            continue; // syntax errors: fmt refuses, tested below
        };
        formatted_count += 1;
        let twice = format(FileId(0), &once)
            .value
            .expect("formatted text parses");
        assert_eq!(
            once,
            twice,
            "{}: formatting is not idempotent",
            path.display()
        );
        assert_eq!(
            meaning(&path, &text),
            meaning(&path, &once),
            "{}: formatting changed its meaning",
            path.display()
        );
        assert_eq!(comments(&text), comments(&once), "{}", path.display());
    }
    assert!(
        formatted_count >= 40,
        "only {formatted_count} scenes parsed"
    );
}

#[test]
fn examples_are_formatted() {
    for path in scenes("examples") {
        let text = std::fs::read_to_string(&path).expect("examples are text");
        let formatted = format(FileId(0), &text).value.expect("examples parse");
        assert!(
            formatted == text,
            "{} is not formatted: run `scnc fmt {}`",
            path.display(),
            path.display()
        );
    }
}

#[test]
fn comments_stay_in_place() {
    let text = "// head\nscnc 1 /* one */\n\n\n// before\nmaterial m = phong { // after brace\n  diffuse (1,1,1) // trailing\n  /* inside */ specular 0\n  // last\n}\n";
    let formatted = format(FileId(0), text).value.expect("parses");
    assert_eq!(
        formatted,
        "// head\nscnc 1 /* one */\n\n// before\nmaterial m = phong { // after brace\n  diffuse (1, 1, 1) // trailing\n  /* inside */ specular 0\n  // last\n}\n"
    );
}

fn scnc(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(args)
        .output()
        .expect("scnc runs")
}

#[test]
fn check_exits_1_with_a_diff_and_formatting_rewrites_the_file() {
    let dir = std::env::temp_dir().join(format!("scnc-fmt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let messy = dir.join("messy.scn");
    let tidy = dir.join("tidy.scn");
    std::fs::write(&messy, "scnc 1\nlet a=1\n").expect("write");
    std::fs::write(&tidy, "scnc 1\nlet a = 1\n").expect("write");
    let (messy_s, tidy_s) = (
        messy.to_str().expect("utf-8"),
        tidy.to_str().expect("utf-8"),
    );

    let clean = scnc(&["fmt", "--check", tidy_s]);
    assert_eq!(clean.status.code(), Some(0));
    assert!(clean.stdout.is_empty());

    let dirty = scnc(&["fmt", "--check", tidy_s, messy_s]);
    assert_eq!(dirty.status.code(), Some(1));
    let diff = String::from_utf8_lossy(&dirty.stdout);
    assert!(diff.contains("-let a=1\n+let a = 1\n"), "{diff}");
    assert_eq!(
        std::fs::read_to_string(&messy).expect("read"),
        "scnc 1\nlet a=1\n"
    );

    let fixed = scnc(&["fmt", messy_s]);
    assert_eq!(fixed.status.code(), Some(0));
    assert_eq!(
        std::fs::read_to_string(&messy).expect("read"),
        "scnc 1\nlet a = 1\n"
    );
    assert_eq!(scnc(&["fmt", "--check", messy_s]).status.code(), Some(0));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_file_with_syntax_errors_is_left_untouched_with_its_diagnostics() {
    let dir = std::env::temp_dir().join(format!("scnc-fmt-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let bad = dir.join("bad.scn");
    let text = "scnc 1\nlet   a=1\nobject o {\n";
    std::fs::write(&bad, text).expect("write");
    let bad_s = bad.to_str().expect("utf-8");
    for args in [vec!["fmt", bad_s], vec!["fmt", "--check", bad_s]] {
        let out = scnc(&args);
        assert_eq!(out.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.contains("scnc::syntax::unclosed_delimiter"),
            "{stderr}"
        );
        assert_eq!(std::fs::read_to_string(&bad).expect("read"), text);
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// A small xorshift generator: the edits are the same on every run.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

/// Seeded random whitespace edits of the examples (spaces, tabs and line breaks inserted next to
/// whitespace or punctuation, whitespace deleted): whenever the edited text parses, formatting it is idempotent
/// and keeps its meaning.
#[test]
fn random_whitespace_edits_format_to_the_same_meaning() {
    let mut rng = Rng(0x5eed_f00d_1234_5678);
    let mut checked = 0;
    for path in scenes("examples") {
        let text = std::fs::read_to_string(&path).expect("examples are text");
        for _ in 0..12 {
            let mut edited: Vec<char> = text.chars().collect();
            for _ in 0..8 {
                let at = rng.below(edited.len());
                // Next to whitespace or punctuation, so that names and numbers stay whole.
                let boundary = |c: char| c.is_whitespace() || "{}(),=".contains(c);
                let after_boundary = at > 0 && boundary(edited[at - 1]);
                if !boundary(edited[at]) && !after_boundary {
                    continue;
                }
                match rng.below(4) {
                    0 => edited.insert(at, ' '),
                    1 => edited.insert(at, '\n'),
                    2 => edited.insert(at, '\t'),
                    _ => {
                        if edited[at].is_whitespace() {
                            edited.remove(at);
                        }
                    }
                }
            }
            let edited: String = edited.into_iter().collect();
            let Some(once) = format(FileId(0), &edited).value else {
                continue;
            };
            checked += 1;
            let twice = format(FileId(0), &once)
                .value
                .expect("formatted text parses");
            assert_eq!(once, twice, "not idempotent on:\n{edited}");
            assert_eq!(
                meaning(&path, &edited),
                meaning(&path, &once),
                "meaning changed on:\n{edited}"
            );
        }
    }
    eprintln!("{checked} edited scenes parsed and were formatted");
    assert!(checked >= 20, "only {checked} edited scenes parsed");
}
