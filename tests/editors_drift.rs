//! Editor support: one source of truth. The keywords, property keys, declaration kinds, bare
//! words, built-in functions, booleans and units come from the compiler's own tables
//! (`scnc::check::vocabulary`, `scnc::syntax::scan::STATEMENT_KEYWORDS`, grammar/scene.pest's
//! `kw_*` rules); every editor grammar under `editors/` must list exactly those: a word missing
//! from a grammar, or a word the language no longer has, fails here.

use std::collections::BTreeSet;

use scnc::check::vocabulary as v;

type Words = BTreeSet<String>;

const PEST: &str = include_str!("../grammar/scene.pest");
const REFERENCE: &str = include_str!("../grammar/README.md");
const TM: &str = include_str!("../editors/vscode/syntaxes/scn.tmLanguage.json");
const SUBLIME: &str = include_str!("../editors/sublime/scn.sublime-syntax");
const TS_GRAMMAR: &str = include_str!("../editors/tree-sitter-scn/grammar.js");
const TS_HIGHLIGHTS: &str = include_str!("../editors/tree-sitter-scn/queries/highlights.scm");
const VIM: &str = include_str!("../editors/vim/syntax/scn.vim");

fn set<'a>(lists: impl IntoIterator<Item = &'a [&'a str]>) -> Words {
    lists.into_iter().flatten().map(|s| s.to_string()).collect()
}

/// The language's word lists, by class.
struct Language {
    keywords: Words,
    keys: Words,
    kinds: Words,
    words: Words,
    functions: Words,
    booleans: Words,
    units: Words,
}

fn language() -> Language {
    let mut keywords = set([scnc::syntax::scan::STATEMENT_KEYWORDS]);
    keywords.insert("transform".into());
    let in_pest: Words = PEST
        .lines()
        .filter_map(|l| l.trim().strip_prefix("kw_"))
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_owned)
        .collect();
    assert_eq!(
        keywords, in_pest,
        "STATEMENT_KEYWORDS + transform vs the pest kw_ rules"
    );
    Language {
        keywords,
        keys: set(v::PROPERTY_KEYS.iter().copied()),
        kinds: set(v::KINDS.iter().copied()),
        words: set(v::WORDS.iter().copied()),
        functions: set([v::FUNCTIONS]),
        booleans: set([v::BOOLEANS]),
        units: set([v::UNITS]),
    }
}

/// Fails with what is missing and what is extra.
fn same(grammar: &str, class: &str, found: &Words, want: &Words) {
    let missing: Vec<_> = want.difference(found).collect();
    let extra: Vec<_> = found.difference(want).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "{grammar}: {class} lacks {missing:?} and has {extra:?}, which the language does not have"
    );
}

/// The `|`-separated alternation between `open` and the next `close` in `text`.
fn alternation(text: &str, open: &str, close: &str) -> Words {
    let start = text
        .find(open)
        .unwrap_or_else(|| panic!("`{open}` not found in {text}"))
        + open.len();
    let len = text[start..]
        .find(close)
        .unwrap_or_else(|| panic!("`{close}` not found after `{open}`"));
    text[start..start + len]
        .split('|')
        .map(str::to_owned)
        .collect()
}

fn union(a: &Words, b: &Words) -> Words {
    a.union(b).cloned().collect()
}

#[test]
fn textmate_grammar_matches_the_language() {
    let lang = language();
    let tm: serde_json::Value = serde_json::from_str(TM).expect("the tmLanguage is JSON");
    let repo = &tm["repository"];
    let rx = |rule: &str, field: &str| -> String {
        repo[rule][field]
            .as_str()
            .unwrap_or_else(|| panic!("repository.{rule}.{field} missing"))
            .to_owned()
    };
    let g = "scn.tmLanguage.json";
    same(
        g,
        "keywords",
        &alternation(&rx("keyword", "match"), r"\b(?:", r")\b"),
        &lang.keywords,
    );
    same(
        g,
        "keys",
        &alternation(&rx("key", "match"), r"\b(?:", r")\b"),
        &lang.keys,
    );
    same(
        g,
        "kinds",
        &alternation(&rx("kind", "match"), r"\b(?:", r")\b"),
        &lang.kinds,
    );
    same(
        g,
        "kinds (calls)",
        &alternation(&rx("call-kind", "begin"), r"\b(", r")(\("),
        &lang.kinds,
    );
    same(
        g,
        "words",
        &alternation(&rx("word", "match"), r"\b(?:", r")\b"),
        &lang.words,
    );
    same(
        g,
        "booleans",
        &alternation(&rx("boolean", "match"), r"\b(?:", r")\b"),
        &lang.booleans,
    );
    let colour = alternation(&rx("call-color", "begin"), r"\b(", r")(\(");
    let other = alternation(&rx("call-builtin", "begin"), r"\b(", r")(\(");
    assert!(
        colour.is_subset(&lang.functions),
        "{g}: colour functions {colour:?}"
    );
    same(g, "functions", &union(&colour, &other), &lang.functions);
    same(
        g,
        "units",
        &alternation(&rx("number", "match"), "(?:(", ")(?!"),
        &lang.units,
    );
}

#[test]
fn sublime_syntax_matches_the_language() {
    let lang = language();
    let var = |name: &str| alternation(SUBLIME, &format!("\n  {name}: '"), "'");
    let g = "scn.sublime-syntax";
    same(g, "keywords", &var("keywords"), &lang.keywords);
    same(g, "keys", &var("keys"), &lang.keys);
    same(g, "kinds", &var("kinds"), &lang.kinds);
    same(g, "words", &var("words"), &lang.words);
    let colour = var("color_functions");
    assert!(
        colour.is_subset(&lang.functions),
        "{g}: colour functions {colour:?}"
    );
    same(
        g,
        "functions",
        &union(&colour, &var("functions")),
        &lang.functions,
    );
    same(g, "units", &var("units"), &lang.units);
    same(g, "booleans", &var("booleans"), &lang.booleans);
}

/// The quoted words of every `(#PRED @CAPTURE "a" "b" ...)` in the query.
fn predicate_words(query: &str, pred: &str, capture: &str) -> Words {
    let head = format!("(#{pred} @{capture}");
    let mut out = Words::new();
    let mut rest = query;
    let mut seen = false;
    while let Some(at) = rest.find(&head) {
        let after = &rest[at + head.len()..];
        // Only this exact capture name (not `@variable.x` for `@variable`).
        if after.starts_with(char::is_whitespace) {
            seen = true;
            let end = after.find(')').expect("predicate is closed");
            out.extend(
                after[..end]
                    .split_whitespace()
                    .map(|w| w.trim_matches('"').to_owned()),
            );
        }
        rest = after;
    }
    assert!(seen, "no `{head}` predicate in the query");
    out
}

#[test]
fn tree_sitter_grammar_and_highlights_match_the_language() {
    let lang = language();
    // grammar.js: its only word literals are the keywords.
    let code: String = TS_GRAMMAR
        .lines()
        .filter(|l| !l.trim_start().starts_with(['/', '*']))
        .collect::<Vec<_>>()
        .join("\n");
    let pieces: Vec<&str> = code.split('\'').collect();
    let literals: Words = (1..pieces.len())
        .step_by(2)
        // Field names (`field('name', ...)`) and the grammar's name are not tokens.
        .filter(|&i| !pieces[i - 1].ends_with("field(") && !pieces[i - 1].ends_with("name: "))
        .map(|i| pieces[i])
        .filter(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
        .map(str::to_owned)
        .collect();
    same("grammar.js", "keywords", &literals, &lang.keywords);
    let g = "highlights.scm";
    let kw_start = TS_HIGHLIGHTS
        .find("\n[\n")
        .expect("a [ ... ] @keyword list");
    let kw_len = TS_HIGHLIGHTS[kw_start..]
        .find("] @keyword")
        .expect("the list is @keyword");
    let kws: Words = TS_HIGHLIGHTS[kw_start + 3..kw_start + kw_len]
        .split_whitespace()
        .map(|w| w.trim_matches('"').to_owned())
        .collect();
    same(g, "keywords", &kws, &lang.keywords);
    same(
        g,
        "keys",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "property"),
        &lang.keys,
    );
    same(
        g,
        "kinds",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "type.builtin"),
        &lang.kinds,
    );
    same(
        g,
        "words",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "constant.builtin"),
        &lang.words,
    );
    same(
        g,
        "functions",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "function.builtin"),
        &lang.functions,
    );
    same(
        g,
        "booleans",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "boolean"),
        &lang.booleans,
    );
    same(
        g,
        "units",
        &predicate_words(TS_HIGHLIGHTS, "any-of?", "keyword.unit"),
        &lang.units,
    );
    same(
        g,
        "units (error)",
        &predicate_words(TS_HIGHLIGHTS, "not-any-of?", "error"),
        &lang.units,
    );
    same(
        g,
        "other calls",
        &predicate_words(TS_HIGHLIGHTS, "not-any-of?", "function"),
        &union(&lang.kinds, &lang.functions),
    );
    let not_references = union(&union(&lang.keys, &lang.words), &lang.booleans);
    same(
        g,
        "non-references",
        &predicate_words(TS_HIGHLIGHTS, "not-any-of?", "variable"),
        &not_references,
    );
}

#[test]
fn vim_syntax_matches_the_language() {
    let lang = language();
    let group = |name: &str| -> Words {
        VIM.lines()
            .filter_map(|l| l.strip_prefix("syn keyword "))
            .filter_map(|l| l.strip_prefix(name))
            .filter(|l| l.starts_with(' '))
            .flat_map(|l| l.split_whitespace())
            .filter(|w| *w != "contained")
            .map(str::to_owned)
            .collect()
    };
    let g = "scn.vim";
    same(g, "keywords", &group("scnKeyword"), &lang.keywords);
    same(g, "keys", &group("scnKey"), &lang.keys);
    same(g, "kinds", &group("scnKind"), &lang.kinds);
    same(g, "words", &group("scnWord"), &lang.words);
    let colour = group("scnColorFunction");
    assert!(
        colour.is_subset(&lang.functions),
        "{g}: colour functions {colour:?}"
    );
    same(
        g,
        "functions",
        &union(&colour, &group("scnFunction")),
        &lang.functions,
    );
    same(g, "booleans", &group("scnBoolean"), &lang.booleans);
    let open = r"syn match scnUnit /\(";
    let start = VIM.find(open).expect("a scnUnit match") + open.len();
    let len = VIM[start..].find(r"\)").expect("the unit group is closed");
    let units: Words = VIM[start..start + len]
        .split(r"\|")
        .map(str::to_owned)
        .collect();
    same(g, "units", &units, &lang.units);
}

#[test]
fn reference_documents_every_key_kind_and_word() {
    let lang = language();
    for u in &lang.units {
        let shown = (0..10).any(|d| REFERENCE.contains(&format!("{d}{u}")));
        assert!(shown, "grammar/README.md never shows a number in `{u}`");
    }
    for w in lang.keys.iter().chain(&lang.kinds).chain(&lang.words) {
        let whole_word = REFERENCE.match_indices(w.as_str()).any(|(at, _)| {
            let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
            !REFERENCE[..at].ends_with(ident) && !REFERENCE[at + w.len()..].starts_with(ident)
        });
        assert!(whole_word, "grammar/README.md never mentions `{w}`");
    }
}

#[test]
fn the_comparison_can_fail() {
    let want: Words = ["a", "b"].map(String::from).into();
    let found: Words = ["a", "c"].map(String::from).into();
    let r = std::panic::catch_unwind(|| same("g", "keys", &found, &want));
    assert!(r.is_err(), "a missing and an extra word went unnoticed");
}
