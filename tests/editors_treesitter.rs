//! Editor support: the tree-sitter grammar (`editors/tree-sitter-scn`, used by Neovim, Helix
//! and Zed) parses every example without ERROR or MISSING nodes, and its queries compile and
//! capture what the other grammars scope.

use std::path::{Path, PathBuf};

use tree_sitter::{Language, Node, Parser, Query, QueryCursor, StreamingIterator, Tree};

fn language() -> Language {
    tree_sitter_scn::LANGUAGE.into()
}

fn parse(text: &str) -> Tree {
    let mut parser = Parser::new();
    parser
        .set_language(&language())
        .expect("the generated parser's ABI is supported by this tree-sitter version");
    parser
        .parse(text, None)
        .expect("parsing is not cancelled (no timeout set)")
}

/// Every ERROR or MISSING node, as `row:column kind`.
fn errors(node: Node, out: &mut Vec<String>) {
    if node.is_error() || node.is_missing() {
        let p = node.start_position();
        out.push(format!("{}:{} {}", p.row + 1, p.column + 1, node.to_sexp()));
    }
    let mut cursor = node.walk();
    for child in node.children(&mut cursor) {
        errors(child, out);
    }
}

fn example_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("examples/ is readable") {
        let p = e.expect("readable directory entry").path();
        if p.is_dir() {
            example_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "scn") {
            out.push(p);
        }
    }
}

#[test]
fn examples_parse_without_error_nodes() {
    let mut files = Vec::new();
    example_files(Path::new("examples"), &mut files);
    assert!(files.len() >= 4, "examples missing: {files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).expect("example is readable UTF-8");
        let tree = parse(&text);
        let mut found = Vec::new();
        errors(tree.root_node(), &mut found);
        assert!(found.is_empty(), "{}: {found:?}", f.display());
        assert!(!tree.root_node().has_error());
        assert!(
            tree.root_node().named_child_count() > 0,
            "{} parsed to nothing",
            f.display()
        );
    }
}

#[test]
fn broken_input_has_error_nodes() {
    for bad in [
        "camera { fov 40deg }",
        "let = 1",
        "render { (1, 2 }",
        "object o { /* open",
    ] {
        assert!(parse(bad).root_node().has_error(), "accepted: {bad}");
    }
}

#[test]
fn block_comments_nest_and_keys_are_not_calls() {
    let tree = parse("/* a /* b */ c */ camera main { eye (0, 1, -5) fov 40deg }");
    let sexp = tree.root_node().to_sexp();
    assert_eq!(
        sexp,
        "(source_file (block_comment) (camera name: (identifier) body: (block (identifier) \
         (parenthesized (number) (number) (negation (number))) (identifier) \
         (number unit: (unit)))))"
    );
}

/// (capture name, text, byte range) of every capture of `query` over `text`.
fn captures(query_src: &str, text: &str) -> Vec<(String, String, std::ops::Range<usize>)> {
    let query = Query::new(&language(), query_src).expect("the query compiles");
    let tree = parse(text);
    let mut cursor = QueryCursor::new();
    let mut caps = cursor.captures(&query, tree.root_node(), text.as_bytes());
    let mut out = Vec::new();
    while let Some((m, i)) = caps.next() {
        let c = m.captures[*i];
        let name = query.capture_names()[c.index as usize].to_string();
        let node_text = c
            .node
            .utf8_text(text.as_bytes())
            .expect("source is UTF-8")
            .to_string();
        out.push((name, node_text, c.node.byte_range()));
    }
    out
}

#[test]
fn queries_compile_and_capture_the_token_classes() {
    Query::new(&language(), tree_sitter_scn::FOLDS_QUERY).expect("folds compile");
    Query::new(&language(), tree_sitter_scn::INDENTS_QUERY).expect("indents compile");
    let text = "let k = radians(30) * -base\n\
                material wall = phong { diffuse red  normal_green opengl }\n\
                light sky = environment { image(\"s.hdr\")  visible true  rotate 12px }\n\
                object ball { material wall  transform { scale #ff8800 } }";
    let caps = captures(tree_sitter_scn::HIGHLIGHTS_QUERY, text);
    let has = |name: &str, t: &str| caps.iter().any(|(n, x, _)| n == name && x == t);
    for (name, t) in [
        ("keyword", "let"),
        ("constant", "k"),
        ("function.builtin", "radians"),
        ("number", "30"),
        ("operator", "*"),
        ("variable", "base"),
        ("type", "wall"),
        ("type.builtin", "phong"),
        ("property", "diffuse"),
        ("variable", "red"),
        ("constant.builtin", "opengl"),
        ("type.builtin", "image"),
        ("string", "\"s.hdr\""),
        ("boolean", "true"),
        ("error", "px"),
        ("keyword", "transform"),
        ("variable", "ball"),
        ("property", "scale"),
        ("constant", "#ff8800"),
    ] {
        assert!(has(name, t), "no @{name} on `{t}`: {caps:?}");
    }
    // No node gets two different captures (the patterns do not overlap, so editors that pick
    // the first match and editors that pick the last agree).
    let mut by_node = std::collections::HashMap::new();
    for (n, t, range) in &caps {
        if let Some(prev) = by_node.insert(range.clone(), n) {
            assert_eq!(prev, n, "`{t}` captured twice");
        }
    }
}
