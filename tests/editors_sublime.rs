//! Editor support: the Sublime Text / bat grammar (`editors/sublime/scn.sublime-syntax`) run by
//! syntect, the engine inside `bat`.
//!
//! The annotated corpus `editors/tests/*.scn` uses the syntax-test format shared with
//! `vscode-tmgrammar-test` (run over the TextMate grammar from `.ci/run`), with its semantics:
//! the header line and the assertion lines are not part of the highlighted text; `// ^^^ a b`
//! asserts that every character under the carets, on the nearest text line above, has scopes
//! `a` then `b` (exact names, in stack order, others may come between); `// <- a` asserts the
//! same for column 0.

use std::path::{Path, PathBuf};

use syntect::parsing::{ParseState, ScopeStack, SyntaxDefinition, SyntaxSet, SyntaxSetBuilder};

const SYNTAX: &str = include_str!("../editors/sublime/scn.sublime-syntax");

fn syntax_set() -> SyntaxSet {
    let def = SyntaxDefinition::load_from_str(SYNTAX, true, None)
        .expect("the committed sublime-syntax is valid YAML and syntax (this test checks it)");
    let mut b = SyntaxSetBuilder::new();
    b.add(def);
    b.build()
}

/// The scope stack (as names, bottom first) of every byte of every line.
fn highlight(ss: &SyntaxSet, lines: &[&str]) -> Vec<Vec<Vec<String>>> {
    let syntax = ss
        .find_syntax_by_scope(syntect::parsing::Scope::new("source.scn").expect("valid scope"))
        .expect("the set holds the scn syntax");
    let mut state = ParseState::new(syntax);
    let mut stack = ScopeStack::new();
    let mut out = Vec::new();
    for line in lines {
        let text = format!("{line}\n");
        let ops = state
            .parse_line(&text, ss)
            .expect("syntect parses every line");
        let mut per_byte = Vec::with_capacity(text.len());
        let mut ops = ops.into_iter().peekable();
        for i in 0..text.len() {
            while let Some((_, op)) = ops.next_if(|(at, _)| *at <= i) {
                stack.apply(&op).expect("balanced scope operations");
            }
            per_byte.push(stack.as_slice().iter().map(|s| s.build_string()).collect());
        }
        for (_, op) in ops {
            stack.apply(&op).expect("balanced scope operations");
        }
        out.push(per_byte);
    }
    out
}

struct Assertion {
    /// 1-based line in the test file, for messages.
    file_line: usize,
    /// 0-based index into the highlighted source lines.
    source_line: usize,
    from: usize,
    to: usize,
    scopes: Vec<String>,
}

/// Splits a syntax-test file into its source lines and assertions.
fn parse_test(text: &str) -> (Vec<&str>, Vec<Assertion>) {
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    assert!(
        header.starts_with("// SYNTAX TEST \"source.scn\""),
        "bad header: {header}"
    );
    let (mut source, mut asserts) = (Vec::new(), Vec::new());
    for (i, line) in lines.enumerate() {
        let rest = line.strip_prefix("//").unwrap_or("");
        let trimmed = rest.trim_start();
        let is_assert =
            line.starts_with("//") && (trimmed.starts_with('^') || trimmed.starts_with("<-"));
        if !is_assert {
            source.push(line);
            continue;
        }
        assert!(
            !source.is_empty(),
            "assertion before any source line at line {}",
            i + 2
        );
        let (from, to, scopes) = if let Some(s) = trimmed.strip_prefix("<-") {
            (0, 1, s)
        } else {
            let from = 2 + rest.len() - trimmed.len();
            let carets = trimmed.chars().take_while(|c| *c == '^').count();
            (from, from + carets, &trimmed[carets..])
        };
        let scopes: Vec<String> = scopes.split_whitespace().map(str::to_owned).collect();
        assert!(
            !scopes.is_empty(),
            "assertion without scopes at line {}",
            i + 2
        );
        asserts.push(Assertion {
            file_line: i + 2,
            source_line: source.len() - 1,
            from,
            to,
            scopes,
        });
    }
    (source, asserts)
}

fn is_subsequence(want: &[String], stack: &[String]) -> bool {
    let mut it = stack.iter();
    want.iter().all(|w| it.any(|s| s == w))
}

fn corpus() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir("editors/tests")
        .expect("editors/tests exists")
        .map(|e| e.expect("readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "scn"))
        .collect();
    files.sort();
    files
}

#[test]
fn corpus_assertions_hold_in_the_sublime_syntax() {
    let ss = syntax_set();
    let files = corpus();
    assert!(files.len() >= 2, "corpus missing: {files:?}");
    let mut failures = Vec::new();
    let mut asserted = std::collections::BTreeSet::new();
    let mut count = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).expect("corpus file is readable UTF-8");
        let (source, asserts) = parse_test(&text);
        let scopes = highlight(&ss, &source);
        for a in &asserts {
            count += 1;
            asserted.extend(a.scopes.iter().cloned());
            for col in a.from..a.to {
                let stack = scopes[a.source_line].get(col).cloned().unwrap_or_default();
                if !is_subsequence(&a.scopes, &stack) {
                    failures.push(format!(
                        "{}:{} col {col} ({:?}): want {:?}, got {:?}",
                        f.display(),
                        a.file_line,
                        source[a.source_line].get(col..col + 1),
                        a.scopes,
                        stack
                    ));
                    break;
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {count} assertions failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    // The corpus covers every token class the grammars promise.
    for class in [
        "comment.line.double-slash.scn",
        "comment.block.scn",
        "string.quoted.double.scn",
        "constant.character.escape.scn",
        "constant.numeric.scn",
        "keyword.other.unit.scn",
        "constant.other.color.rgb-value.scn",
        "support.function.builtin.color.scn",
        "support.function.builtin.scn",
        "keyword.other.scn",
        "variable.other.property.scn",
        "entity.name.constant.scn",
        "entity.name.camera.scn",
        "entity.name.material.scn",
        "entity.name.texture.scn",
        "entity.name.mesh.scn",
        "entity.name.light.scn",
        "entity.name.group.scn",
        "variable.other.scn",
        "variable.other.mesh.scn",
        "support.type.scn",
        "support.constant.scn",
        "constant.language.boolean.scn",
        "keyword.operator.arithmetic.scn",
        "keyword.operator.assignment.scn",
        "invalid.illegal.character.scn",
        "invalid.illegal.unit.scn",
        "invalid.illegal.color.scn",
    ] {
        assert!(asserted.contains(class), "the corpus never asserts {class}");
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
fn examples_have_no_invalid_scope_in_the_sublime_syntax() {
    let ss = syntax_set();
    let mut files = Vec::new();
    example_files(Path::new("examples"), &mut files);
    assert!(files.len() >= 4, "examples missing: {files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).expect("example is readable UTF-8");
        let lines: Vec<&str> = text.lines().collect();
        for (n, line) in highlight(&ss, &lines).iter().enumerate() {
            for (col, stack) in line.iter().enumerate() {
                assert!(
                    !stack.iter().any(|s| s.starts_with("invalid")),
                    "{}:{}:{} highlighted invalid: {stack:?}\n{}",
                    f.display(),
                    n + 1,
                    col + 1,
                    lines[n]
                );
            }
        }
    }
}

#[test]
fn stray_characters_are_invalid() {
    // The checks above can fail: a stray character is flagged.
    let ss = syntax_set();
    let scopes = highlight(&ss, &["camera c { fov 40deg ; }"]);
    assert!(
        scopes[0][21]
            .iter()
            .any(|s| s == "invalid.illegal.character.scn"),
        "{:?}",
        scopes[0][21]
    );
}
