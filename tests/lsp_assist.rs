//! `scnc lsp` hover, completion and explanation links, driven over a pipe as an editor drives
//! them, with exact UTF-16 ranges (non-ASCII text before the hovered word) and contents.

mod lsp_common;

use lsp_common::{temp_dir, uri, Client};
use serde_json::{json, Value};

/// The LSP position (line, UTF-16 column) of the `n`th byte of `text`.
fn position(text: &str, n: usize) -> Value {
    let line = text[..n].matches('\n').count();
    let start = text[..n].rfind('\n').map_or(0, |i| i + 1);
    let column: usize = text[start..n].chars().map(char::len_utf16).sum();
    json!({ "line": line, "character": column })
}

/// The position `into` bytes into the first occurrence of `needle`.
fn at(text: &str, needle: &str, into: usize) -> Value {
    let n = text
        .find(needle)
        .unwrap_or_else(|| panic!("`{needle}` in the text"));
    position(text, n + into)
}

/// The range of the first occurrence of `needle`.
fn range_of(text: &str, needle: &str) -> Value {
    let n = text
        .find(needle)
        .unwrap_or_else(|| panic!("`{needle}` in the text"));
    json!({ "start": position(text, n), "end": position(text, n + needle.len()) })
}

fn hover(client: &mut Client, uri: &str, position: Value) -> Value {
    let params = json!({ "textDocument": { "uri": uri }, "position": position });
    client.request("textDocument/hover", params)["result"].clone()
}

/// The labels of the completions at `position`.
fn labels(client: &mut Client, uri: &str, position: Value) -> Vec<String> {
    let params = json!({ "textDocument": { "uri": uri }, "position": position });
    let result = client.request("textDocument/completion", params)["result"].clone();
    result
        .as_array()
        .unwrap_or_else(|| panic!("a completion list, not {result}"))
        .iter()
        .map(|i| i["label"].as_str().expect("a label").to_string())
        .collect()
}

const SCENE: &str = "scnc 1
// é𝛼 before everything
let grey = srgb(0.5, 0.5, 0.5)  let tint = #ff8000
camera c { eye (0, 0, -1)  target (0, 0, 0)  fov 30deg }
material wall = phong { diffuse grey }
material floor = phong { diffuse 0.8 }
texture board = checker { scale 8 }
mesh ball = sphere { radius 1 }
object ball { material wall }
";

#[test]
fn hover_shows_keys_units_and_colours_with_exact_ranges() {
    let dir = temp_dir("hover");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    client.open(&main, SCENE);

    let fov = hover(&mut client, &main, at(SCENE, "fov", 1));
    assert_eq!(fov["range"], range_of(SCENE, "fov"));
    assert_eq!(fov["contents"]["kind"], "markdown");
    assert_eq!(
        fov["contents"]["value"],
        "`fov` in a camera\n\ntype: angle · unit: `deg` or `rad` · default: `40deg`\n\n\
         vertical field of view, in (0deg, 180deg) exclusive"
    );

    let deg = hover(&mut client, &main, at(SCENE, "30deg", 3));
    assert_eq!(deg["range"], range_of(SCENE, "30deg"));
    let text = deg["contents"]["value"].as_str().expect("markdown");
    assert!(text.starts_with("`30deg` = 0.5236 rad\n"), "{text}");

    // The call is hovered as a whole; its line starts after the non-ASCII comment line.
    let srgb = hover(&mut client, &main, at(SCENE, "srgb(", 2));
    assert_eq!(srgb["range"], range_of(SCENE, "srgb(0.5, 0.5, 0.5)"));
    assert_eq!(
        srgb["contents"]["value"],
        "colour (sRGB-encoded)\n\nlinear (0.214, 0.214, 0.214) · sRGB (0.5, 0.5, 0.5) · #808080"
    );
    let hex = hover(&mut client, &main, at(SCENE, "#ff8000", 0));
    assert_eq!(hex["range"], range_of(SCENE, "#ff8000"));
    let text = hex["contents"]["value"].as_str().expect("markdown");
    assert!(text.contains("linear (1, 0.2159, 0)"), "{text}");

    // A key of a block is documented in that block's terms; nothing on a comment.
    let scale = hover(&mut client, &main, at(SCENE, "scale 8", 0));
    let text = scale["contents"]["value"].as_str().expect("markdown");
    assert!(
        text.starts_with(
            "`scale` in a checker texture\n\ntype: number > 0 · unit: squares per UV unit"
        ),
        "{text}"
    );
    assert_eq!(
        hover(&mut client, &main, at(SCENE, "before", 0)),
        Value::Null
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn completion_offers_missing_keys_names_by_kind_functions_and_units() {
    let dir = temp_dir("complete");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    // Mid-edit: the camera block is open and half a key is typed; the file does not parse.
    let text = format!("{SCENE}camera d {{ eye (0, 0, 1)  f\nrender {{ seed 1 }}\n");
    client.open(&main, &text);
    let n = text.find("  f\n").expect("the half key") + 3;
    let keys = labels(&mut client, &main, position(&text, n));
    assert_eq!(keys, ["target", "up", "fov", "transform"]);

    // After `material` in an object: the materials, not the mesh or the texture.
    let text2 = format!("{SCENE}object ball {{ material  }}\n");
    client.change(&main, 2, &text2);
    let n = text2.rfind("material ").expect("the key") + "material ".len();
    assert_eq!(
        labels(&mut client, &main, position(&text2, n)),
        ["wall", "floor"]
    );

    // Names declared in an included file are offered too, after the document's own.
    std::fs::write(
        dir.join("lib.scn"),
        "scnc 1\nmaterial gold = phong { specular 0.9 }\n",
    )
    .expect("write");
    let text2 = format!("{SCENE}include \"lib.scn\"\nobject ball {{ material  }}\n");
    client.change(&main, 6, &text2);
    let n = text2.rfind("material ").expect("the key") + "material ".len();
    assert_eq!(
        labels(&mut client, &main, position(&text2, n)),
        ["wall", "floor", "gold"]
    );

    // In parentheses: constants, then every function, booleans and `frame`.
    let text3 = format!("{SCENE}let x = (gr");
    client.change(&main, 3, &text3);
    let found = labels(&mut client, &main, position(&text3, text3.len()));
    assert_eq!(found[..2], ["grey", "tint"]);
    for f in scnc::check::FUNCTIONS {
        assert!(found.iter().any(|l| l == f), "{f} missing from {found:?}");
    }

    // After a number: the units, replacing only the suffix typed so far.
    let text4 = format!("{SCENE}camera e {{ fov 40d");
    client.change(&main, 4, &text4);
    let params =
        json!({ "textDocument": { "uri": main }, "position": position(&text4, text4.len()) });
    let items = client.request("textDocument/completion", params)["result"].clone();
    let deg = &items[0];
    assert_eq!(deg["label"], "deg");
    let d = text4.len() - 1;
    assert_eq!(
        deg["textEdit"]["range"],
        json!({ "start": position(&text4, d), "end": position(&text4, d + 1) })
    );
    assert!(deg["documentation"]["value"]
        .as_str()
        .expect("docs")
        .contains("radians"));

    // A choice key offers its words, each documented.
    let text5 = format!("{SCENE}render {{ tonemap ");
    client.change(&main, 5, &text5);
    assert_eq!(
        labels(&mut client, &main, position(&text5, text5.len())),
        ["clamp", "reinhard", "filmic"]
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn diagnostics_link_to_their_codes_explanation() {
    let dir = temp_dir("explain");
    let main = uri(&dir.join("main.scn"));
    let mut client = Client::start();
    client.open(&main, &format!("{SCENE}let b = nope\n"));
    let diags = client.diagnostics_for(&main);
    let unknown = diags
        .iter()
        .find(|d| d["code"] == "scnc::check::unknown_name")
        .unwrap_or_else(|| panic!("an unknown_name diagnostic in {diags:?}"));
    let href = unknown["codeDescription"]["href"].as_str().expect("a link");
    let want = format!(
        "file://{}/src/diag/explain/check/unknown_name.md",
        env!("CARGO_MANIFEST_DIR")
    );
    assert_eq!(href, want);
    let path = href.strip_prefix("file://").expect("a file URL");
    let explanation = std::fs::read_to_string(path).expect("the explanation exists");
    assert!(explanation.contains("```scn"), "{explanation}");
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

/// In process, at every character boundary of every example and of its truncations and
/// bracket-mangled variants: hover and completion never panic.
#[test]
fn hover_and_completion_answer_at_every_offset_of_mangled_examples() {
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut checked = 0;
    for entry in std::fs::read_dir(examples).expect("examples") {
        let path = entry.expect("entry").path();
        if path.extension().and_then(|e| e.to_str()) != Some("scn") {
            continue;
        }
        let text = std::fs::read_to_string(&path).expect("an example");
        let half = text.len() / 2;
        let half = (half..text.len())
            .find(|&i| text.is_char_boundary(i))
            .unwrap_or(0);
        let variants = [
            text.clone(),
            text[..half].to_string(),
            text.replace('}', "").replace(')', "("),
            text.replace('"', "/*é𝛼"),
        ];
        for variant in &variants {
            let mut sources = scnc::source::SourceMap::new();
            let file = sources.add("main.scn", "main.scn", variant.as_str());
            let statements = scnc::syntax::parse(file, variant)
                .value
                .map(|f| f.statements)
                .unwrap_or_default();
            let index = scnc::lsp::symbols::SymbolIndex::from_statements(sources, &statements);
            let names = scnc::lsp::names::declared(&index);
            for offset in (0..=variant.len()).filter(|&i| variant.is_char_boundary(i)) {
                let _ = scnc::lsp::hover::hover(variant, offset);
                let _ = scnc::lsp::completion::complete(variant, offset, &names);
                checked += 1;
            }
        }
    }
    assert!(checked > 10_000, "{checked}");
}
