//! `scnc lsp` under a seeded random sequence of thousands of edits over the examples (inserted
//! brackets, quotes, comment openers, non-ASCII and garbage; deletions; truncations; duplicated
//! slices), sent in bursts as fast typing would: the server never crashes or hangs, and after
//! every burst the diagnostics it publishes for the newest text equal what `scnc check` reports
//! for the same text (code, severity and UTF-16 range of every diagnostic in the file), and
//! hover and completion at random positions of it answer without an error, and the outline,
//! folding, semantic token and navigation requests are answered.

mod lsp_common;

use std::path::Path;
use std::process::Command;

use lsp_common::{temp_dir, uri, Client};
use serde_json::Value;

struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n.max(1) as u64) as usize
    }
}

const GARBAGE: &[&str] = &[
    "{", "}", "(", ")", "[", "]", "\"", "/*", "//", "é", "𝛼", "#", "-", "=", ",", "\n", " ", "9",
    "1e", "deg", "object", "let", "material", "x", "\u{0}", "\t",
];

/// A diagnostic as an editor shows it: code, LSP severity, start and end (line, UTF-16 column).
type Shown = (String, u64, (u64, u64), (u64, u64));

fn char_floor(text: &str, mut at: usize) -> usize {
    at = at.min(text.len());
    while !text.is_char_boundary(at) {
        at -= 1;
    }
    at
}

fn edit(rng: &mut Rng, text: &mut String) {
    let at = char_floor(text, rng.below(text.len() + 1));
    match rng.below(10) {
        0..=4 => text.insert_str(at, GARBAGE[rng.below(GARBAGE.len())]),
        5..=7 => {
            let end = char_floor(text, at + 1 + rng.below(12));
            text.replace_range(at..end, "");
        }
        8 => text.truncate(at),
        _ => {
            let end = char_floor(text, at + rng.below(40));
            let slice = text[at..end].to_string();
            text.insert_str(end, &slice);
        }
    }
}

/// The UTF-16 position of byte `offset` in `text`.
fn position(text: &str, offset: usize) -> (u64, u64) {
    let before = &text[..char_floor(text, offset)];
    let line = before.matches('\n').count();
    let line_start = before.rfind('\n').map_or(0, |n| n + 1);
    let column: usize = before[line_start..].chars().map(char::len_utf16).sum();
    (line as u64, column as u64)
}

/// `scnc check`'s diagnostics for the file at `path` (holding `text`), as the server shows
/// them: (code, severity, range) of those whose primary label is in the file or that have none.
fn check_cli(path: &Path, text: &str) -> Vec<Shown> {
    let out = Command::new(env!("CARGO_BIN_EXE_scnc"))
        .args(["check", "--diagnostic-format", "json"])
        .arg(path)
        .output()
        .expect("scnc check runs");
    let json: Value = serde_json::from_slice(&out.stdout).expect("scnc check prints JSON");
    let mut found = Vec::new();
    for d in json["diagnostics"].as_array().expect("a list") {
        let severity = if d["severity"] == "error" { 1 } else { 2 };
        let code = d["code"].as_str().expect("a code").to_string();
        let primary = d["labels"]
            .as_array()
            .and_then(|labels| labels.iter().find(|l| l["primary"] == true));
        match primary {
            None => found.push((code, severity, (0, 0), (0, 0))),
            Some(l) if Path::new(l["path"].as_str().unwrap_or("")) == path => {
                let (start, end) = (
                    l["start"].as_u64().expect("start") as usize,
                    l["end"].as_u64().expect("end") as usize,
                );
                found.push((code, severity, position(text, start), position(text, end)));
            }
            Some(_) => {}
        }
    }
    found.sort();
    found
}

fn from_server(diags: &[Value]) -> Vec<Shown> {
    let n = |v: &Value| v.as_u64().expect("a number");
    let mut found: Vec<_> = diags
        .iter()
        .map(|d| {
            let r = &d["range"];
            (
                d["code"].as_str().expect("a code").to_string(),
                n(&d["severity"]),
                (n(&r["start"]["line"]), n(&r["start"]["character"])),
                (n(&r["end"]["line"]), n(&r["end"]["character"])),
            )
        })
        .collect();
    found.sort();
    found
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("create");
    for entry in std::fs::read_dir(from).expect("read_dir") {
        let path = entry.expect("entry").path();
        let target = to.join(path.file_name().expect("a name"));
        if path.is_dir() {
            copy_dir(&path, &target);
        } else {
            std::fs::copy(&path, &target).expect("copy");
        }
    }
}

/// The structure and navigation requests on the edited text, at a random position: each is
/// answered (a result or a refusal), never a crash.
fn navigate(client: &mut Client, doc: &str, text: &str, rng: &mut Rng) {
    let (line, character) = position(text, rng.below(text.len() + 1));
    let document = serde_json::json!({ "textDocument": { "uri": doc } });
    let mut at = document.clone();
    at["position"] = serde_json::json!({ "line": line, "character": character });
    let mut references = at.clone();
    references["context"] = serde_json::json!({ "includeDeclaration": true });
    let mut rename = at.clone();
    rename["newName"] = serde_json::json!("renamed");
    for (method, params) in [
        ("textDocument/semanticTokens/full", &document),
        ("textDocument/documentSymbol", &document),
        ("textDocument/foldingRange", &document),
        ("textDocument/definition", &at),
        ("textDocument/references", &references),
        ("textDocument/prepareRename", &at),
        ("textDocument/rename", &rename),
    ] {
        let response = client.request(method, params.clone());
        let refused = response["error"]["code"] == -32803;
        assert!(
            response.get("result").is_some() || refused,
            "{method} after an edit: {response}\n{text}"
        );
    }
}

#[test]
fn thousands_of_random_edits_never_crash_and_match_scnc_check() {
    let dir = temp_dir("robust");
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    copy_dir(&examples, &dir);
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("read_dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .collect();
    names.sort();

    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut client = Client::start();
    let (mut edits, mut compared) = (0, 0);
    for path in &names {
        let original = std::fs::read_to_string(path).expect("an example");
        let doc = uri(path);
        client.open(&doc, &original);
        let mut version = 1;
        let mut text = original.clone();
        for burst in 0..30 {
            if burst % 10 == 0 {
                text = original.clone();
            }
            for _ in 0..10 {
                edit(&mut rng, &mut text);
                version += 1;
                edits += 1;
                client.change(&doc, version, &text);
            }
            let published = client.diagnostics_at(&doc, version);
            std::fs::write(path, &text).expect("write");
            assert_eq!(
                from_server(&published),
                check_cli(path, &text),
                "after edit {edits} of {}:\n{text}",
                path.display()
            );
            compared += 1;
            // Hover and completion anywhere in the mangled text answer (a value or null).
            let lines = text.lines().count() as u64 + 2;
            for method in ["textDocument/hover", "textDocument/completion"] {
                let position = serde_json::json!({
                    "line": rng.below(lines as usize), "character": rng.below(90)
                });
                let params =
                    serde_json::json!({ "textDocument": { "uri": doc }, "position": position });
                let response = client.request(method, params);
                assert!(response.get("error").is_none(), "{method}: {response}");
            }
            navigate(&mut client, &doc, &text, &mut rng);
        }
        client.notify(
            "textDocument/didClose",
            serde_json::json!({ "textDocument": { "uri": doc } }),
        );
        std::fs::write(path, &original).expect("restore");
    }
    eprintln!("{edits} edits, {compared} comparisons with scnc check");
    assert!(edits >= 2000);
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}
