//! The grammar is the single source of truth: the keyword list used for recovery and
//! did-you-mean matches the grammar's keyword rules, and the language reference documents every
//! statement keyword and every function the checker knows.

const GRAMMAR: &str = include_str!("../grammar/scene.pest");
const REFERENCE: &str = include_str!("../grammar/README.md");

#[test]
fn statement_keywords_match_the_grammar() {
    let mut in_grammar: Vec<&str> = GRAMMAR
        .lines()
        .filter_map(|l| l.trim().strip_prefix("kw_"))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|k| *k != "transform")
        .collect();
    in_grammar.sort_unstable();
    let mut listed = scnc::syntax::scan::STATEMENT_KEYWORDS.to_vec();
    listed.sort_unstable();
    assert_eq!(in_grammar, listed);
}

#[test]
fn reference_documents_keywords_and_functions() {
    for kw in scnc::syntax::scan::STATEMENT_KEYWORDS {
        assert!(
            REFERENCE.contains(&format!("`{kw}")),
            "keyword {kw} undocumented"
        );
    }
    for f in scnc::check::FUNCTIONS {
        assert!(
            REFERENCE.contains(&format!("`{f}(")),
            "function {f} undocumented"
        );
    }
}
