//! `scnc lsp` driven over a pipe as an editor drives it: initialize, diagnostics published on
//! open and change (exact UTF-16 ranges after non-ASCII text, codes, help, related locations,
//! cleared when fixed), includers re-checked when an included document changes, formatting,
//! shutdown and exit.

mod lsp_common;

use lsp_common::{range, temp_dir, uri, Client};
use serde_json::{json, Value};

const CAMERA: &str = "camera c { eye (0, 0, -1)  target (0, 0, 0) }\n";

#[test]
fn diagnostics_have_utf16_ranges_codes_help_and_clear_when_fixed() {
    let dir = temp_dir("diag");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    // `𝛼` is two UTF-16 units and four bytes: the error is at UTF-16 column 23.
    client.open(
        &main,
        &format!("scnc 1\nlet s = \"é𝛼\"  let b = nope + 1\n{CAMERA}"),
    );
    let diags = client.diagnostics_for(&main);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(range(&diags[0]), (1, 23, 1, 27));
    assert_eq!(diags[0]["code"], "scnc::check::unknown_name");
    assert_eq!(diags[0]["severity"], 1);
    let message = diags[0]["message"].as_str().expect("a message");
    assert!(message.starts_with("unknown name `nope`"), "{message}");
    assert!(
        message.contains("\nhelp: constants must be declared"),
        "{message}"
    );

    // A duplicate: the first declaration is a related location.
    client.change(&main, 2, &format!("scnc 1\nlet a = 1\nlet a = 2\n{CAMERA}"));
    let diags = client.diagnostics_for(&main);
    let duplicate = diags
        .iter()
        .find(|d| d["code"] == "scnc::check::duplicate_name")
        .unwrap_or_else(|| panic!("a duplicate_name diagnostic in {diags:?}"));
    let related = &duplicate["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], main.as_str());
    assert_eq!(related["location"]["range"]["start"]["line"], 1);

    client.change(&main, 3, &format!("scnc 1\nlet a = 1\n{CAMERA}"));
    let diags = client.diagnostics_for(&main);
    assert!(
        diags.iter().all(|d| d["severity"] != 1),
        "errors left after the fix: {diags:?}"
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn build_stage_diagnostics_report_a_missing_mesh_file() {
    let dir = temp_dir("build");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    let text = format!(
        "scnc 1\n{CAMERA}mesh m = obj(\"missing.obj\")\nmaterial w = phong {{ diffuse rgb(0.5, 0.5, 0.5) }}\nobject m {{ material w }}\n"
    );
    client.open(&main, &text);
    let diags = client.diagnostics_for(&main);
    let missing = diags
        .iter()
        .find(|d| d["code"] == "scnc::build::missing_file")
        .unwrap_or_else(|| panic!("a missing_file diagnostic in {diags:?}"));
    assert_eq!(range(missing), (2, 13, 2, 26));
    assert_eq!(diags.len(), 1, "{diags:?}");
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn editing_an_included_document_rechecks_its_includer() {
    let dir = temp_dir("include");
    let (main_path, lib_path) = (dir.join("main.scn"), dir.join("lib.scn"));
    std::fs::write(&lib_path, "scnc 1\nlet k = 1\n").expect("write");
    let (main, lib) = (uri(&main_path), uri(&lib_path));
    let mut client = Client::start();
    client.open(
        &main,
        &format!("scnc 1\ninclude \"lib.scn\"\nlet b = k\n{CAMERA}"),
    );
    assert!(client.diagnostics_for(&main).is_empty());
    // The unsaved editor text of lib.scn is what main.scn includes.
    client.open(&lib, "scnc 1\nlet renamed = 1\n");
    let diags = client.diagnostics_for(&main);
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(diags[0]["code"], "scnc::check::unknown_name");
    assert_eq!(range(&diags[0]), (2, 8, 2, 9));
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn formatting_replaces_the_document_or_refuses_syntax_errors() {
    let dir = temp_dir("format");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    client.open(&main, "scnc 1\n// é\nlet a=1\n");
    let params = json!({ "textDocument": { "uri": main }, "options": { "tabSize": 2, "insertSpaces": true } });
    let edits = client.request("textDocument/formatting", params.clone());
    assert_eq!(
        edits["result"],
        json!([{ "range": { "start": { "line": 0, "character": 0 }, "end": { "line": 3, "character": 0 } },
                 "newText": "scnc 1\n// é\nlet a = 1\n" }])
    );
    client.change(&main, 2, "scnc 1\n// é\nlet a = 1\n");
    assert_eq!(
        client.request("textDocument/formatting", params.clone())["result"],
        json!([])
    );
    client.change(&main, 3, "scnc 1\nobject o {\n");
    assert_eq!(
        client.request("textDocument/formatting", params)["result"],
        Value::Null
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}
