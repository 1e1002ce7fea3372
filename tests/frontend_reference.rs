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

/// The marker line before each table of grammar/README.md rendered from
/// `scnc::check::reference` (`functions` for the function table).
fn marker(section: &str) -> String {
    format!("<!-- generated from src/check/reference_table.rs: {section} -->\n")
}

/// The README with every generated table replaced by its rendering from the reference data.
fn rendered(readme: &str) -> String {
    use scnc::check::reference::{functions_table, section_table, SECTIONS};
    let tables = SECTIONS
        .iter()
        .map(|s| (*s, section_table(s)))
        .chain([("functions", functions_table())]);
    let mut out = readme.to_string();
    for (section, table) in tables {
        let marker = marker(section);
        let start = out
            .find(&marker)
            .unwrap_or_else(|| panic!("grammar/README.md lacks the line {marker:?}"))
            + marker.len();
        let old_len: usize = out[start..]
            .split_inclusive('\n')
            .take_while(|line| line.starts_with('|'))
            .map(str::len)
            .sum();
        out.replace_range(start..start + old_len, &table);
    }
    out
}

/// The property and function tables are the reference data's (hover and completion show the
/// same text); `SCNC_BLESS=1 cargo test --test frontend_reference` rewrites them.
#[test]
fn reference_tables_are_rendered_from_the_reference_data() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/grammar/README.md");
    let readme = std::fs::read_to_string(path).expect("grammar/README.md");
    let want = rendered(&readme);
    if std::env::var_os("SCNC_BLESS").is_some() {
        std::fs::write(path, &want).expect("write grammar/README.md");
        return;
    }
    if want != readme {
        let diff = similar::TextDiff::from_lines(&readme, &want);
        panic!(
            "grammar/README.md's tables differ from src/check/reference_table.rs \
             (SCNC_BLESS=1 rewrites them):\n{}",
            diff.unified_diff().header("README", "rendered")
        );
    }
}

#[test]
fn a_changed_table_cell_is_noticed() {
    let readme = REFERENCE.replacen("| `fov` | angle |", "| `fov` | number |", 1);
    assert_ne!(readme, REFERENCE, "the test edit must apply");
    assert_ne!(rendered(&readme), readme);
}
