//! Stage 1, syntax: `.scn` text → AST ([`SceneFile`]), every node spanned. Errors: syntax
//! diagnostics (`scnc::syntax::*`).
//!
//! The grammar is `grammar/scene.pest`. A file that parses whole is converted directly. When it
//! does not, the text is cut at resynchronisation points (lines that start a statement, found by
//! [`scan`]) and each chunk is parsed on its own, so one run reports the syntax error of every
//! broken statement and still keeps every good statement for the checker. Before pest runs,
//! nesting depth is checked by the linear pre-scan so deep input cannot overflow the stack.

pub mod ast;
mod convert;
mod errors;
pub mod scan;

pub use ast::*;
pub use convert::MAX_EXPR_NODES;

use pest::Parser;

use crate::diag::{Diagnostic, Staged};
use crate::source::{FileId, Span};

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/scene.pest"]
pub(crate) struct SceneParser;

/// Parses one file: every statement that parsed (always a value: the parser recovers at the next
/// statement) and a diagnostic per syntax error.
pub fn parse(file: FileId, text: &str) -> Staged<SceneFile> {
    let (parsed, diagnostics) = parse_recovering(file, text);
    Staged::new(Some(parsed), diagnostics)
}

fn parse_recovering(file: FileId, text: &str) -> (SceneFile, Vec<Diagnostic>) {
    let scanned = scan::scan(text);
    if scanned.too_deep_at.is_none() {
        if let Some(ok) = parse_batched(file, text, &scanned) {
            return ok;
        }
        if let Some(ok) = parse_range(file, text, 0) {
            return ok;
        }
    }
    parse_chunks(file, text, &scanned)
}

/// Bytes of source parsed per pest call on the fast path. pest keeps the whole token queue of
/// a parse alive until it is converted, so parsing in batches bounds that memory.
const BATCH_BYTES: usize = 64 * 1024;

/// Parses `text[base..]` as a whole sequence of statements, or `None` on a syntax error.
fn parse_range(file: FileId, text: &str, base: usize) -> Option<(SceneFile, Vec<Diagnostic>)> {
    let mut pairs = SceneParser::parse(Rule::file, &text[base..]).ok()?;
    let conv = convert::Converter::new(file, base);
    let file_pair = pairs.next().expect("pest: Rule::file yields one pair");
    let statements = conv.file(file_pair);
    Some((SceneFile { statements }, conv.errors.into_inner()))
}

/// Fast path for valid files: parses batches of about [`BATCH_BYTES`] cut at resync points.
/// A resync point can fall inside a statement (a name starting a continuation line), so any
/// failing batch sends the caller back to parsing the file whole.
fn parse_batched(
    file: FileId,
    text: &str,
    scanned: &scan::Scan,
) -> Option<(SceneFile, Vec<Diagnostic>)> {
    if text.len() <= BATCH_BYTES {
        return None;
    }
    let mut statements = Vec::new();
    let mut diags = Vec::new();
    let mut start = 0;
    let mut cuts = scanned.resync.iter().copied().peekable();
    while start < text.len() {
        let mut end = text.len();
        while let Some(&c) = cuts.peek() {
            cuts.next();
            if c >= start + BATCH_BYTES {
                end = c;
                break;
            }
        }
        let mut pairs = SceneParser::parse(Rule::file, &text[start..end]).ok()?;
        let conv = convert::Converter::new(file, start);
        let file_pair = pairs.next().expect("pest: Rule::file yields one pair");
        statements.extend(conv.file(file_pair));
        diags.extend(conv.errors.into_inner());
        start = end;
    }
    Some((SceneFile { statements }, diags))
}

/// Error recovery: parse each chunk between resync points separately.
fn parse_chunks(file: FileId, text: &str, scanned: &scan::Scan) -> (SceneFile, Vec<Diagnostic>) {
    // Record the literal tokens pest tried at the failure point (`=`, `}`), for the messages.
    // Only the error path turns this on; it never changes whether a parse succeeds.
    pest::set_error_detail(true);
    let mut starts: Vec<usize> = vec![0];
    starts.extend(scanned.resync.iter().copied().filter(|&s| s > 0));
    starts.push(text.len());
    let mut statements = Vec::new();
    let mut diags = Vec::new();
    for w in starts.windows(2) {
        let (start, end) = (w[0], w[1]);
        let chunk = &text[start..end];
        if chunk.trim().is_empty() {
            continue;
        }
        if let Some(deep) = scanned.too_deep_at.filter(|&d| d >= start && d < end) {
            diags.push(
                Diagnostic::error(
                    "scnc::syntax::too_deep",
                    format!("nesting deeper than {} levels", scan::MAX_NESTING),
                )
                .at(Span::new(file, deep, deep + 1), "too deep here")
                .help("flatten the structure: use `let` constants or fewer nested groups"),
            );
            continue;
        }
        match SceneParser::parse(Rule::file, chunk) {
            Ok(mut pairs) => {
                let conv = convert::Converter::new(file, start);
                let file_pair = pairs.next().expect("pest: Rule::file yields one pair");
                statements.extend(conv.file(file_pair));
                diags.extend(conv.errors.into_inner());
            }
            Err(e) => diags.push(errors::from_pest(file, start, chunk, &e)),
        }
    }
    (SceneFile { statements }, diags)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(src: &str) -> SceneFile {
        let (f, d) = parse(FileId(0), src).into_parts();
        assert!(d.is_empty(), "{d:#?}");
        f.unwrap_or_default()
    }

    #[test]
    fn parses_statements_and_items() {
        let f = parse_ok(
            "scnc 1\nlet a = 1 + 2 * 3\ncamera c { eye (0, 1, 2) fov 30deg transform { rotate y 5deg } }\n\
             material m = phong { diffuse #fff }\nmesh t = obj(\"a.obj\")\nrender { resolution 4 x 4 }",
        );
        assert_eq!(f.statements.len(), 6);
        let Stmt::Let { value, .. } = &f.statements[1] else {
            panic!("expected let")
        };
        // 1 + (2 * 3)
        let ExprKind::Binary { op, rhs, .. } = &value.kind else {
            panic!("expected binary")
        };
        assert_eq!(*op, BinOp::Add);
        assert!(matches!(rhs.kind, ExprKind::Binary { op: BinOp::Mul, .. }));
    }

    #[test]
    fn call_needs_no_space_before_paren() {
        let f = parse_ok("scnc 1 light l = area { quad (1,0,0) (0,0,0) rgb(1,2,3) }");
        let Stmt::Decl(d) = &f.statements[1] else {
            panic!("expected decl")
        };
        let items = &d.body.as_ref().expect("body").items;
        assert_eq!(items.len(), 4);
        assert!(matches!(
            &items[3],
            Item::Value(Expr {
                kind: ExprKind::Call { .. },
                ..
            })
        ));
    }

    #[test]
    fn recovers_at_next_statement() {
        let src =
            "scnc 1\ncamera c { eye (1,2 }\nmaterial m = phong { }\nmesh = quad\nrender { }\n";
        let (f, d) = parse(FileId(0), src).into_parts();
        assert_eq!(d.len(), 2, "{d:#?}");
        assert_eq!(f.map(|f| f.statements.len()), Some(3));
    }

    #[test]
    fn deep_nesting_is_a_diagnostic() {
        let src = format!(
            "scnc 1\nlet a = {}1{}\n",
            "(".repeat(5000),
            ")".repeat(5000)
        );
        let (_, d) = parse(FileId(0), &src).into_parts();
        assert_eq!(d[0].code, "scnc::syntax::too_deep");
    }

    #[test]
    fn long_expressions_are_capped() {
        let src = format!("scnc 1\nlet a = 1{}\n", " + 1".repeat(300));
        let (_, d) = parse(FileId(0), &src).into_parts();
        assert_eq!(d[0].code, "scnc::syntax::expression_too_large");
    }
}
