//! Stage 1, syntax: pest errors → [`Diagnostic`]s with friendly wording.
//!
//! pest reports the rules it expected at the failure position; they are translated into words a
//! scene author knows ("a value", "`}`"), an unclosed bracket is reported at the bracket, and an
//! unknown word where a statement must start gets a did-you-mean against the statement keywords.

use pest::error::{Error, ErrorVariant, InputLocation};

use super::scan::{self, STATEMENT_KEYWORDS};
use super::Rule;
use crate::diag::{suggest, Code, Diagnostic};
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

/// Where in `chunk` a pest error sits, for spans: the file and the chunk's offset in it.
#[derive(Clone, Copy)]
struct At<'a> {
    file: FileId,
    base: usize,
    chunk: &'a str,
}

impl At<'_> {
    fn span(self, start: usize, end: usize) -> Span {
        Span::new(self.file, self.base + start, self.base + end)
    }
}

/// The diagnostic for pest's error `e` on `chunk`, which starts at byte `base` of `file`.
pub(super) fn from_pest(file: FileId, base: usize, chunk: &str, e: &Error<Rule>) -> Diagnostic {
    let at = At { file, base, chunk };
    let (pos, literals) = failure_point(chunk, e);
    let found = token_at(chunk, pos);
    unknown_keyword(at, pos, found)
        .or_else(|| unclosed_delimiter(at, pos))
        .unwrap_or_else(|| unexpected_token(at, pos, found, &literals, e))
}

/// Where in `chunk` pest's error `e` sits: the position [`from_pest`] reports it at.
pub(super) fn failure_pos(chunk: &str, e: &Error<Rule>) -> usize {
    failure_point(chunk, e).0
}

/// [`from_pest`]'s diagnostic for a chunk (at byte `base` of `file`) whose parse fails at
/// its end (only blanks after the failure point): "this `{` is never closed" at the innermost
/// bracket still open there, whatever pest expected. `None` when no bracket is open at the end
/// (then the words depend on pest's error).
pub(super) fn unclosed_at_end(file: FileId, base: usize, chunk: &str) -> Option<Diagnostic> {
    unclosed_delimiter(At { file, base, chunk }, chunk.len())
}

/// The farthest position pest reached and the structural tokens (`` `}` ``, `` `=` ``) it
/// wanted there: with error detail on, pest knows them, though its rule-level report does not.
fn failure_point(chunk: &str, e: &Error<Rule>) -> (usize, Vec<String>) {
    let mut pos = pos0(e);
    let mut literals: Vec<String> = Vec::new();
    if let Some(attempts) = e.parse_attempts() {
        if attempts.max_position >= pos && attempts.max_position <= chunk.len() {
            pos = attempts.max_position;
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
    (pos, literals)
}

/// A word where a statement should start: most likely a misspelled keyword.
fn unknown_keyword(at: At, pos: usize, found: &str) -> Option<Diagnostic> {
    let first_token = at.chunk.len() - at.chunk.trim_start().len();
    let is_word = found
        .chars()
        .next()
        .is_some_and(|c| c.is_alphabetic() || c == '_');
    if pos != first_token || !is_word || STATEMENT_KEYWORDS.contains(&found) {
        return None;
    }
    Some(
        Diagnostic::error(
            Code::SyntaxUnknownKeyword,
            format!("unknown statement `{found}`"),
        )
        .at(
            at.span(pos, pos + found.len()),
            "expected a statement keyword",
        )
        .help(suggest::help_for(found, STATEMENT_KEYWORDS, "statements")),
    )
}

/// The chunk ended inside a bracket (or comment): point at where it opened.
fn unclosed_delimiter(at: At, pos: usize) -> Option<Diagnostic> {
    if !at.chunk.get(pos..).unwrap_or("").trim().is_empty() {
        return None;
    }
    let (open, tok) = scan::unclosed(at.chunk)?;
    let close = match tok {
        "(" => ")",
        "[" => "]",
        "{" => "}",
        _ => "*/",
    };
    Some(
        Diagnostic::error(
            Code::SyntaxUnclosedDelimiter,
            format!("this `{tok}` is never closed"),
        )
        .at(at.span(open, open + tok.len()), "opened here")
        .help(format!(
            "add `{close}` where the block, list or comment ends"
        )),
    )
}

/// Anything else: what was found, and what pest expected in words a scene author knows.
fn unexpected_token(
    at: At,
    pos: usize,
    found: &str,
    literals: &[String],
    e: &Error<Rule>,
) -> Diagnostic {
    let mut expected: Vec<&str> = literals.iter().map(String::as_str).collect();
    if let ErrorVariant::ParsingError { positives, .. } = &e.variant {
        // When pest got farther than its rule-level report, the positives are about an
        // earlier position; the literals say it all.
        let farther = e.parse_attempts().is_some_and(|a| a.max_position > pos0(e));
        if literals.is_empty() || !farther {
            expected.extend(positives.iter().map(|r| describe(*r)));
        }
    }
    expected.sort_unstable();
    expected.dedup();
    let chunk = at.chunk;
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
    let d = Diagnostic::error(Code::SyntaxUnexpectedToken, format!("unexpected {what}"))
        .at(at.span(start, end), "unexpected here");
    if matches!(found, "*" | "/" | "+") {
        d.help("inside a block each value is one term: write arithmetic in parentheses, e.g. `intensity (2 * 5)`, or use a `let`")
    } else if !expected.is_empty() {
        d.help(format!("expected {}", join_or(&expected)))
    } else {
        d
    }
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
