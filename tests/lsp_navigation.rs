//! `scnc lsp` navigation driven over a pipe, with exact ranges (UTF-16 columns after non-ASCII
//! text): go to definition and find references within a file and across an include (from the
//! including and the included side), prepareRename and rename across an include, renames
//! refused on a taken name, a key and a non-name, the document outline, folding ranges, and
//! semantic tokens decoded with the announced legend.

mod lsp_common;

use lsp_common::{temp_dir, uri, Client};
use serde_json::{json, Value};

const LIB: &str = "scnc 1\n// é𝛼 library\nlet white = #fff\n\
                   material matte = phong { diffuse white }\n\
                   material shiny = phong { specular 0.5 }\n";

/// Line 2: `size` is at UTF-16 column 19 (byte 24) after `é𝛼`.
const MAIN: &str = "scnc 1\ninclude \"lib.scn\"\nlet s = \"é𝛼\"  let size = 1\n\
                    camera main { eye (0, 1, -4)  target (0, 0, 0) }\n\
                    mesh ball = sphere { radius size }\n\
                    object ball { material matte }\n\
                    group g {\n  object ball { material matte }\n}\n\
                    render { camera main }\n";

type Range4 = (u64, u64, u64, u64);

fn range_of(v: &Value) -> Range4 {
    let n = |v: &Value| v.as_u64().expect("a number");
    (
        n(&v["start"]["line"]),
        n(&v["start"]["character"]),
        n(&v["end"]["line"]),
        n(&v["end"]["character"]),
    )
}

fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({ "textDocument": { "uri": uri }, "position": { "line": line, "character": character } })
}

/// Sets up lib.scn on disk and main.scn open in a client.
fn scene(name: &str) -> (Client, std::path::PathBuf, String, String) {
    let dir = temp_dir(name);
    std::fs::write(dir.join("lib.scn"), LIB).expect("write");
    let (main, lib) = (uri(&dir.join("main.scn")), uri(&dir.join("lib.scn")));
    let mut client = Client::start();
    client.open(&main, MAIN);
    (client, dir, main, lib)
}

/// (uri, range) of every location in a response.
fn locations(response: &Value) -> Vec<(String, Range4)> {
    response["result"]
        .as_array()
        .unwrap_or_else(|| panic!("a list of locations: {response}"))
        .iter()
        .map(|l| {
            (
                l["uri"].as_str().expect("a uri").to_string(),
                range_of(&l["range"]),
            )
        })
        .collect()
}

#[test]
fn definition_and_references_within_a_file_and_across_an_include() {
    let (mut client, dir, main, lib) = scene("definition");
    let def = client.request("textDocument/definition", at(&main, 4, 30));
    assert_eq!(def["result"]["uri"], main.as_str());
    assert_eq!(range_of(&def["result"]["range"]), (2, 19, 2, 23));
    let def = client.request("textDocument/definition", at(&main, 5, 25));
    assert_eq!(def["result"]["uri"], lib.as_str());
    assert_eq!(range_of(&def["result"]["range"]), (3, 9, 3, 14));
    // Not a name: no answer.
    let none = client.request("textDocument/definition", at(&main, 5, 2));
    assert_eq!(none["result"], Value::Null);

    let uses = vec![
        (main.clone(), (5, 23, 5, 28)),
        (main.clone(), (7, 25, 7, 30)),
    ];
    let mut with_declaration = vec![(lib.clone(), (3, 9, 3, 14))];
    with_declaration.extend(uses.clone());
    let refs = |client: &mut Client, uri: &str, line, character, declaration: bool| {
        let mut p = at(uri, line, character);
        p["context"] = json!({ "includeDeclaration": declaration });
        locations(&client.request("textDocument/references", p))
    };
    assert_eq!(refs(&mut client, &main, 7, 26, false), uses);
    assert_eq!(refs(&mut client, &main, 7, 26, true), with_declaration);
    // From the included file's side: the includer is found (open, and beside it on disk).
    client.open(&lib, LIB);
    assert_eq!(refs(&mut client, &lib, 3, 10, true), with_declaration);
    // A constant used in the included file only.
    assert_eq!(
        refs(&mut client, &lib, 3, 35, true),
        [(lib.clone(), (2, 4, 2, 9)), (lib.clone(), (3, 33, 3, 38))]
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn rename_reaches_every_file_and_refuses_taken_names() {
    let (mut client, dir, main, lib) = scene("rename");
    let prepared = client.request("textDocument/prepareRename", at(&main, 5, 24));
    assert_eq!(range_of(&prepared["result"]["range"]), (5, 23, 5, 28));
    assert_eq!(prepared["result"]["placeholder"], "matte");
    let keyword = client.request("textDocument/prepareRename", at(&main, 5, 2));
    assert_eq!(keyword["result"], Value::Null);

    let rename = |client: &mut Client, line, character, name: &str| {
        let mut p = at(&main, line, character);
        p["newName"] = json!(name);
        client.request("textDocument/rename", p)
    };
    let edit = |r: Range4| {
        json!({ "range": { "start": { "line": r.0, "character": r.1 },
                           "end": { "line": r.2, "character": r.3 } }, "newText": "dull" })
    };
    let renamed = rename(&mut client, 5, 24, "dull");
    let changes = &renamed["result"]["changes"];
    assert_eq!(changes[&lib], json!([edit((3, 9, 3, 14))]));
    assert_eq!(
        changes[&main],
        json!([edit((5, 23, 5, 28)), edit((7, 25, 7, 30))])
    );
    assert_eq!(changes.as_object().map(|o| o.len()), Some(2));

    let refused = |response: Value, why: &str| {
        assert_eq!(response["error"]["code"], -32803, "{response}");
        let message = response["error"]["message"].as_str().expect("a message");
        assert!(message.contains(why), "{message}");
    };
    refused(
        rename(&mut client, 5, 24, "shiny"),
        "material `shiny` is already declared at lib.scn:5",
    );
    refused(rename(&mut client, 2, 20, "radius"), "is a key of a block");
    refused(rename(&mut client, 2, 20, "2x"), "is not a name");
    refused(rename(&mut client, 2, 20, "object"), "is a keyword");
    refused(
        rename(&mut client, 2, 20, "white"),
        "constant `white` is already declared",
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

/// (name, kind, range, selection range, children) of every symbol, depth first.
fn outline(symbols: &Value, out: &mut Vec<(String, u64, Range4, Range4, usize)>) {
    for s in symbols.as_array().expect("a list") {
        let children = s["children"].as_array().map_or(0, Vec::len);
        out.push((
            s["name"].as_str().expect("a name").to_string(),
            s["kind"].as_u64().expect("a kind"),
            range_of(&s["range"]),
            range_of(&s["selectionRange"]),
            children,
        ));
        if children > 0 {
            outline(&s["children"], out);
        }
    }
}

#[test]
fn document_symbols_are_the_outline_with_groups_nesting() {
    let (mut client, dir, main, _) = scene("outline");
    let params = json!({ "textDocument": { "uri": main } });
    let response = client.request("textDocument/documentSymbol", params);
    let mut found = Vec::new();
    outline(&response["result"], &mut found);
    let s = |name: &str, kind, range, selection, children| {
        (name.to_string(), kind, range, selection, children)
    };
    assert_eq!(
        found,
        [
            s("lib.scn", 1, (1, 0, 1, 17), (1, 8, 1, 17), 0),
            s("s", 14, (2, 0, 2, 13), (2, 4, 2, 5), 0),
            s("size", 14, (2, 15, 2, 27), (2, 19, 2, 23), 0),
            s("main", 19, (3, 0, 3, 48), (3, 7, 3, 11), 0),
            s("ball", 5, (4, 0, 4, 34), (4, 5, 4, 9), 0),
            s("ball", 8, (5, 0, 5, 30), (5, 7, 5, 11), 0),
            s("g", 3, (6, 0, 8, 1), (6, 6, 6, 7), 1),
            s("ball", 8, (7, 2, 7, 32), (7, 9, 7, 13), 0),
            s("render", 2, (9, 0, 9, 22), (9, 0, 9, 6), 0),
        ]
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn folding_ranges_cover_blocks_arrays_and_comments() {
    let dir = temp_dir("folding");
    let doc = uri(&dir.join("fold.scn"));
    let mut client = Client::start();
    client.open(
        &doc,
        "scnc 1\n// one\n// two\nmaterial m = phong {\n  diffuse #fff\n}\n\
         mesh t = inline {\n  positions [0 0 0\n    1 0 0\n    0 1 0]\n  indices [0 1 2]\n}\n\
         /* a\n   b */\n",
    );
    let response = client.request(
        "textDocument/foldingRange",
        json!({ "textDocument": { "uri": doc } }),
    );
    let found: Vec<(u64, u64, Option<&str>)> = response["result"]
        .as_array()
        .expect("a list")
        .iter()
        .map(|f| {
            (
                f["startLine"].as_u64().expect("a line"),
                f["endLine"].as_u64().expect("a line"),
                f["kind"].as_str(),
            )
        })
        .collect();
    assert_eq!(
        found,
        [
            (1, 2, Some("comment")),
            (3, 4, None),
            (6, 10, None),
            (7, 9, None),
            (12, 13, Some("comment")),
        ]
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn semantic_tokens_colour_names_by_kind_in_utf16_columns() {
    let dir = temp_dir("semantic");
    let doc = uri(&dir.join("tokens.scn"));
    let mut client = Client::start();
    let legend = client.capabilities["semanticTokensProvider"]["legend"].clone();
    let names = |key: &str| -> Vec<String> {
        legend[key]
            .as_array()
            .expect("a legend list")
            .iter()
            .map(|t| t.as_str().expect("a name").to_string())
            .collect()
    };
    let (types, modifiers) = (names("tokenTypes"), names("tokenModifiers"));
    client.open(
        &doc,
        "scnc 1\nlet s = \"é𝛼\"  let size = 30deg\n\
         material m = phong { diffuse rgb(1, 0, 0) }  // é m\n\
         mesh b = sphere { radius size }\nobject b { material m }\n",
    );
    let response = client.request(
        "textDocument/semanticTokens/full",
        json!({ "textDocument": { "uri": doc } }),
    );
    let data: Vec<u64> = response["result"]["data"]
        .as_array()
        .expect("data")
        .iter()
        .map(|v| v.as_u64().expect("a number"))
        .collect();
    let (mut line, mut column) = (0, 0);
    let mut decoded = Vec::new();
    for t in data.chunks(5) {
        line += t[0];
        column = if t[0] == 0 { column + t[1] } else { t[1] };
        let mods: Vec<&str> = (0..modifiers.len())
            .filter(|i| t[4] & (1 << i) != 0)
            .map(|i| modifiers[i].as_str())
            .collect();
        decoded.push((
            line,
            column,
            t[2],
            types[t[3] as usize].clone(),
            mods.join(","),
        ));
    }
    let t = |line, column, len, ty: &str, mods: &str| {
        (line, column, len, ty.to_string(), mods.to_string())
    };
    assert_eq!(
        decoded,
        [
            t(0, 0, 4, "keyword", ""),
            t(0, 5, 1, "number", ""),
            t(1, 0, 3, "keyword", ""),
            t(1, 4, 1, "variable", "declaration,readonly"),
            t(1, 8, 5, "string", ""),
            t(1, 15, 3, "keyword", ""),
            t(1, 19, 4, "variable", "declaration,readonly"),
            t(1, 26, 5, "number", ""),
            t(2, 0, 8, "keyword", ""),
            t(2, 9, 1, "struct", "declaration"),
            t(2, 13, 5, "type", ""),
            t(2, 21, 7, "property", ""),
            t(2, 29, 3, "function", "defaultLibrary"),
            t(2, 33, 1, "number", ""),
            t(2, 36, 1, "number", ""),
            t(2, 39, 1, "number", ""),
            t(2, 45, 6, "comment", ""),
            t(3, 0, 4, "keyword", ""),
            t(3, 5, 1, "class", "declaration"),
            t(3, 9, 6, "type", ""),
            t(3, 18, 6, "property", ""),
            t(3, 25, 4, "variable", "readonly"),
            t(4, 0, 6, "keyword", ""),
            t(4, 7, 1, "class", ""),
            t(4, 11, 8, "property", ""),
            t(4, 20, 1, "struct", ""),
        ]
    );
    client.shutdown();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn capabilities_announce_navigation() {
    let client = Client::start();
    let c = client.capabilities.clone();
    assert_eq!(c["definitionProvider"], true);
    assert_eq!(c["referencesProvider"], true);
    assert_eq!(c["renameProvider"]["prepareProvider"], true);
    assert_eq!(c["documentSymbolProvider"], true);
    assert_eq!(c["foldingRangeProvider"], true);
    assert_eq!(c["semanticTokensProvider"]["full"], true);
    client.shutdown();
}
