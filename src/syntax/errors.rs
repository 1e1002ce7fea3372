//! Stage 1, syntax: pest errors → [`Diagnostic`]s with friendly wording.
//!
//! pest reports the rules it expected at the failure position; they are translated into words a
//! scene author knows ("a value", "`}`"), an unclosed bracket is reported at the bracket, and an
//! unknown word where a statement must start gets a did-you-mean against the statement keywords.

use pest::error::{Error, ErrorVariant, InputLocation};

use super::scan::{self, STATEMENT_KEYWORDS};
use super::Rule;
use crate::diag::Diagnostic;
use crate::diag::{suggest, Code};
use crate::source::{FileId, Span};

fn describe(rule: Rule) -> &'static str {
    match rule {
        Rule::EOI => "end of file",
        Rule::statement
        | Rule::version
        | Rule::include
        | Rule::let_stmt
        | Rule::camera
        | Rule::decl
        | Rule::render
        | Rule::kw_scnc
        | Rule::kw_include
        | Rule::kw_let
        | Rule::kw_camera
        | Rule::kw_material
        | Rule::kw_texture
        | Rule::kw_mesh
        | Rule::kw_light
        | Rule::kw_render => "a statement",
        Rule::object | Rule::kw_object => "`object`",
        Rule::group | Rule::kw_group => "`group`",
        Rule::transform | Rule::kw_transform => "`transform`",
        Rule::ident | Rule::callee => "a name",
        Rule::ctor => "a constructor such as `phong` or `obj(\"file.obj\")`",
        Rule::block => "`{`",
        Rule::bin_op => "an operator",
        Rule::call_args => "`(`",
        Rule::string | Rule::str_inner => "a string",
        Rule::number | Rule::digits => "a number",
        _ => "a value",
    }
}

/// The token at `offset`: a word, or one character.
fn token_at(chunk: &str, offset: usize) -> &str {
    let rest = chunk.get(offset..).unwrap_or("");
    let word_len = rest
        .char_indices()
        .find(|(_, c)| !(c.is_alphanumeric() || *c == '_'))
        .map_or(rest.len(), |(i, _)| i);
    if word_len > 0 {
        &rest[..word_len]
    } else {
        rest.chars().next().map_or("", |c| &rest[..c.len_utf8()])
    }
}

pub(super) fn from_pest(file: FileId, base: usize, chunk: &str, e: &Error<Rule>) -> Diagnostic {
    let mut pos = match e.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    };
    // With error detail on, pest knows the farthest point reached and the literal tokens it
    // wanted there (`=`, `}`), which its rule-level report misses.
    let mut literals: Vec<String> = Vec::new();
    if let Some(attempts) = e.parse_attempts() {
        if attempts.max_position >= pos && attempts.max_position <= chunk.len() {
            if attempts.max_position > pos {
                pos = attempts.max_position;
            }
            for t in attempts.expected_tokens() {
                // Only structural punctuation: value starts (`#`, `-`, `[`) are "a value" and
                // comment starts are always possible.
                let token = t.to_string();
                if matches!(token.as_str(), "=" | "{" | "}" | "(" | ")" | "," | "]") {
                    literals.push(format!("`{token}`"));
                }
            }
        }
    }
    let found = token_at(chunk, pos);
    let first_token = chunk.len() - chunk.trim_start().len();
    // A word where a statement should start: most likely a misspelled keyword.
    if pos == first_token
        && found
            .chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
        && !STATEMENT_KEYWORDS.contains(&found)
    {
        let span = Span::new(file, base + pos, base + pos + found.len());
        return Diagnostic::error(
            Code::SyntaxUnknownKeyword,
            format!("unknown statement `{found}`"),
        )
        .at(span, "expected a statement keyword")
        .help(suggest::help_for(found, STATEMENT_KEYWORDS, "statements"));
    }
    // The chunk ended inside a bracket: point at the bracket.
    if chunk[pos..].trim().is_empty() {
        if let Some((open, tok)) = scan::unclosed(chunk) {
            let span = Span::new(file, base + open, base + open + tok.len());
            let close = match tok {
                "(" => ")",
                "[" => "]",
                "{" => "}",
                _ => "*/",
            };
            return Diagnostic::error(
                Code::SyntaxUnclosedDelimiter,
                format!("this `{tok}` is never closed"),
            )
            .at(span, "opened here")
            .help(format!(
                "add `{close}` where the block, list or comment ends"
            ));
        }
    }
    let mut expected: Vec<&str> = literals.iter().map(String::as_str).collect();
    if let ErrorVariant::ParsingError { positives, .. } = &e.variant {
        if !literals.is_empty() && e.parse_attempts().is_some_and(|a| a.max_position > pos0(e)) {
            // The rule-level positives are about an earlier position; the literals say it all.
        } else {
            expected.extend(positives.iter().map(|r| describe(*r)));
        }
    }
    expected.sort_unstable();
    expected.dedup();
    let (start, end) = if found.is_empty() {
        // At the end of the chunk: point at the last character before it.
        let p = chunk.trim_end().len();
        let back = chunk[..p].chars().next_back().map_or(0, char::len_utf8);
        (p - back, p)
    } else {
        (pos, pos + found.len())
    };
    let what = if found.is_empty() {
        "end of input".to_string()
    } else if found.starts_with(char::is_control) {
        "a control character".to_string()
    } else {
        format!("`{found}`")
    };
    let mut d = Diagnostic::error(Code::SyntaxUnexpectedToken, format!("unexpected {what}"))
        .at(Span::new(file, base + start, base + end), "unexpected here");
    if matches!(found, "*" | "/" | "+") {
        d = d.help("inside a block each value is one term: write arithmetic in parentheses, e.g. `intensity (2 * 5)`, or use a `let`");
    } else if !expected.is_empty() {
        d = d.help(format!("expected {}", join_or(&expected)));
    }
    d
}

fn pos0(e: &Error<Rule>) -> usize {
    match e.location {
        InputLocation::Pos(p) => p,
        InputLocation::Span((s, _)) => s,
    }
}

fn join_or(items: &[&str]) -> String {
    match items {
        [] => String::new(),
        [one] => (*one).to_string(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}
