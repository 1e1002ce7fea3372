//! Stage 1, syntax: `.scn` text → AST ([`SceneFile`]), every node spanned. Errors: syntax
//! diagnostics (`scnc::syntax::*`).
//!
//! The grammar is `grammar/scene.pest`. A file without syntax errors is parsed by the
//! hand-written fast path (`fast.rs`: the same AST, pest's parse for any statement it does not
//! accept whole). When it has errors, the text is cut at resynchronisation points (lines that
//! start a statement, found by [`scan`]) and each chunk is parsed on its own, so one run
//! reports the syntax error of every broken statement and still keeps every good statement for
//! the checker: by the fast parser when it accepts the chunk whole, by pest (the source of every
//! syntax error) otherwise, so a file with one error costs about what a clean one does. A
//! failing chunk whose tail is `object`s and `group`s (a `{` left open over them) has its error
//! told without parsing that tail (`tail.rs`). Nesting depth is checked so that deep input cannot
//! overflow the stack: by the fast parser as it parses (it stops where the linear pre-scan
//! `scan::too_deep` would find the text too deep, and has the pre-scan read the whole text
//! before pest parses anything), by the pre-scan before the error recovery and a region's parse.

pub mod ast;
mod convert;
mod errors;
mod fast;
mod name;
pub mod scan;
mod tail;

pub use ast::*;
pub use convert::MAX_EXPR_NODES;
pub(crate) use tail::nests;

use pest::Parser;

use crate::diag::{Code, Diagnostic, Staged};
use crate::source::{FileId, Span};

/// The pest parser generated from `grammar/scene.pest`.
mod generated {
    #![allow(
        missing_docs,
        reason = "pest_derive generates `Rule`, one variant per grammar rule"
    )]

    /// The parser of `grammar/scene.pest`.
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/scene.pest"]
    pub struct SceneParser;
}
pub(crate) use generated::{Rule, SceneParser};

/// Parses one file: every statement that parsed (always a value: the parser recovers at the next
/// statement) and a diagnostic per syntax error.
pub fn parse(file: FileId, text: &str) -> Staged<SceneFile> {
    let (parsed, diagnostics) = parse_recovering(file, text);
    Staged::new(Some(parsed), diagnostics)
}

fn parse_recovering(file: FileId, text: &str) -> (SceneFile, Vec<Diagnostic>) {
    if let Some((statements, diags)) = fast::parse(file, text) {
        return (SceneFile { statements }, diags);
    }
    parse_chunks(file, text, &scan::scan(text), Chunks::Fast)
}

/// [`parse`] for a file without syntax errors or diagnostics, handing each statement to `each`
/// as soon as it is parsed (so that the caller may lower it and drop its AST at once). `false`
/// when the file has any syntax error or diagnostic, nests too deep, or a statement the fast
/// parser leaves to pest does not parse before the next line that starts with a word
/// (`fast::Fallback::Line`: an object cut inside its braces is not read over the rest of the
/// file): some statements may have been handed out already, and the caller must start over
/// with [`parse`] (which reports them).
pub fn parse_each(file: FileId, text: &str, each: &mut dyn FnMut(Stmt)) -> bool {
    fast::parse_each(file, text, each, fast::Fallback::Line).is_some_and(|diags| diags.is_empty())
}

/// The statements of `text[start..end]`, where `start` is the start of a top-level statement
/// (or of the file) and `end` the start of another (or the end of the file), exactly as
/// [`parse`] of the whole `text` finds them there; `None` when they are not whole statements,
/// or on any syntax error or diagnostic (the incremental compile then parses the whole file).
pub fn parse_region(file: FileId, text: &str, start: usize, end: usize) -> Option<Vec<Stmt>> {
    let region = text.get(start..end)?;
    if scan::too_deep(region).is_some() {
        return None;
    }
    fast::parse_region(file, text, start, end)
}

/// The whole file parsed by pest alone, or `None` on a syntax error: the oracle the fast
/// parser is tested against.
#[cfg(test)]
#[allow(
    clippy::expect_used,
    reason = "a successful parse of `file` yields exactly one pair"
)]
fn parse_with_pest(file: FileId, text: &str) -> Option<(SceneFile, Vec<Diagnostic>)> {
    let mut pairs = SceneParser::parse(Rule::file, text).ok()?;
    let conv = convert::Converter::new(file, 0);
    let file_pair = pairs.next().expect("pest: Rule::file yields one pair");
    let statements = conv.file(file_pair);
    Some((SceneFile { statements }, conv.errors.into_inner()))
}

/// [`parse`] with the plain error recovery (pest on every chunk, as before the fast parser
/// took the chunks that parse): the oracle the recovery is tested against.
#[cfg(test)]
fn parse_plain(file: FileId, text: &str) -> (SceneFile, Vec<Diagnostic>) {
    if scan::too_deep(text).is_none() {
        if let Some((statements, diags)) = fast::parse(file, text) {
            return (SceneFile { statements }, diags);
        }
    }
    parse_chunks(file, text, &scan::scan(text), Chunks::Pest)
}

/// pest's error detail (the literal tokens tried at the failure point) is one process-wide
/// switch that slows every parse; it is on only while some error recovery runs, counted so
/// that parses on other threads never turn it off under each other.
struct ErrorDetail;

static ERROR_DETAIL_USERS: std::sync::Mutex<usize> = std::sync::Mutex::new(0);

impl ErrorDetail {
    fn on() -> ErrorDetail {
        let mut users = ERROR_DETAIL_USERS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        *users += 1;
        pest::set_error_detail(true);
        ErrorDetail
    }
}

impl Drop for ErrorDetail {
    fn drop(&mut self) {
        let mut users = ERROR_DETAIL_USERS
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        *users = users.saturating_sub(1);
        if *users == 0 {
            pest::set_error_detail(false);
        }
    }
}

/// Error recovery: parse each chunk between resync points separately.
fn parse_chunks(
    file: FileId,
    text: &str,
    scanned: &scan::Scan,
    by: Chunks,
) -> (SceneFile, Vec<Diagnostic>) {
    let mut starts: Vec<usize> = vec![0];
    starts.extend(scanned.resync.iter().copied().filter(|&s| s > 0));
    starts.push(text.len());
    let (parsed, diags, _) =
        parse_chunks_between(file, text, &starts, scanned.too_deep_at, &[], by);
    (parsed, diags)
}

/// [`parse`]'s error recovery over part of a file with a syntax error: from `start`, a
/// top-level statement's start that [`parse`] of the whole `text` cuts a chunk at (or the
/// file's start), to the first statement of `kept` where the whole file's resynchronisation
/// points are again those of the text it was edited from ([`scan::resync_from`]). `kept` are
/// the byte ranges of the statements after the edit, in order, each known to parse alone as a
/// top-level statement over exactly its range, with only blanks and comments between two of
/// them and after the last (the statements of a text that parsed, moved by the edit): a chunk
/// whose tail they are is not parsed whole when its error can be told without (`tail.rs`).
/// The statements and diagnostics [`parse`] of the whole `text` finds there, where the part
/// ends, and how many kept statements were spared a parse; `None` when `start` is not where
/// [`parse`] cuts, or nesting gets too deep in the part.
pub fn parse_recovering_from(
    file: FileId,
    text: &str,
    start: usize,
    kept: &[(usize, usize)],
) -> Option<Recovered> {
    let mut stops = kept.iter().map(|&(s, _)| s);
    let (resync, stop) = scan::resync_from(text, start, &mut stops)?;
    if start != 0 && resync.first() != Some(&start) {
        return None;
    }
    let mut starts = vec![start];
    starts.extend(resync.into_iter().filter(|&s| s > start));
    starts.push(stop);
    let (parsed, diagnostics, spared) =
        parse_chunks_between(file, text, &starts, None, kept, Chunks::Fast);
    Some(Recovered {
        statements: parsed.statements,
        diagnostics,
        stop,
        spared,
    })
}

/// What [`parse_recovering_from`] found.
pub struct Recovered {
    /// The statements that parsed.
    pub statements: Vec<Stmt>,
    /// A diagnostic per syntax error.
    pub diagnostics: Vec<Diagnostic>,
    /// Where the part ends.
    pub stop: usize,
    /// How many kept statements were not parsed (their chunk's error told without).
    pub spared: usize,
}

/// Which parser the error recovery tries first on each chunk.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Chunks {
    /// The fast parser (`fast::chunk`), pest only for a chunk it does not accept (a chunk
    /// with a syntax error or a diagnostic): the same statements and diagnostics, in about
    /// the time of a file that parses.
    Fast,
    /// pest on every chunk: the plain recovery, the oracle `Fast` is tested against.
    #[cfg(test)]
    Pest,
}

/// Parses each chunk `text[starts[i]..starts[i + 1]]` on its own (a chunk whose tail is
/// statements of `kept` not whole when [`tail::error`] can tell its error; see
/// [`parse_recovering_from`]); also how many kept statements that spared.
#[allow(
    clippy::expect_used,
    reason = "a successful parse of `file` yields exactly one pair"
)]
fn parse_chunks_between(
    file: FileId,
    text: &str,
    starts: &[usize],
    too_deep_at: Option<usize>,
    kept: &[(usize, usize)],
    by: Chunks,
) -> (SceneFile, Vec<Diagnostic>, usize) {
    // Record the literal tokens pest tried at the failure point (`=`, `}`), for the messages.
    // Only the error path turns this on; it never changes whether a parse succeeds.
    let _detail = ErrorDetail::on();
    let mut statements = Vec::new();
    let mut diags = Vec::new();
    let mut spared = 0;
    for w in starts.windows(2) {
        let (start, end) = (w[0], w[1]);
        let chunk = &text[start..end];
        if chunk.trim().is_empty() {
            continue;
        }
        if let Some(deep) = too_deep_at.filter(|&d| d >= start && d < end) {
            diags.push(
                Diagnostic::error(
                    Code::SyntaxTooDeep,
                    format!("nesting deeper than {} levels", scan::MAX_NESTING),
                )
                .at(Span::new(file, deep, deep + 1), "too deep here")
                .help("flatten the structure: use `let` constants or fewer nested groups"),
            );
            continue;
        }
        if let Some((diag, n)) = tail::error(file, text, start, end, kept) {
            diags.push(diag);
            spared += n;
            continue;
        }
        if by == Chunks::Fast {
            if let Some(parsed) = fast::chunk(file, text, start, end) {
                statements.extend(parsed);
                continue;
            }
            // A chunk that fails with a tail of `object`s and `group`s (a `{` left open over
            // them, which `scan` cannot resynchronise inside) is the end of `text[..end]`: its
            // error is told from its head and the first of them, as after an edit.
            if kept.is_empty() {
                let run = fast::nesting_tail(file, text, start, end);
                if let Some((diag, _)) = tail::error(file, &text[..end], start, end, &run) {
                    diags.push(diag);
                    continue;
                }
            }
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
    (SceneFile { statements }, diags, spared)
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
                kind: ExprKind::Call(_),
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
        assert_eq!(d[0].code, Code::SyntaxTooDeep);
    }

    #[test]
    fn a_unit_suffix_is_held_inline_without_growing_the_nodes() {
        // `Number`'s suffix was a `Box<Ident>`; inline, it must not make every node larger.
        assert_eq!(std::mem::size_of::<Expr>(), 48);
        assert_eq!(std::mem::size_of::<Item>(), 48);
        let f = parse_ok("scnc 1 let a = 30deg + 2");
        let Stmt::Let { value, .. } = &f.statements[1] else {
            panic!("expected let")
        };
        let ExprKind::Binary { lhs, .. } = &value.kind else {
            panic!("expected binary")
        };
        let suffix = lhs.suffix().expect("a suffix");
        assert_eq!(suffix.name, "deg");
        assert_eq!((suffix.span.start, suffix.span.end), (17, 20));
    }

    #[test]
    fn long_expressions_are_capped() {
        let src = format!("scnc 1\nlet a = 1{}\n", " + 1".repeat(300));
        let (_, d) = parse(FileId(0), &src).into_parts();
        assert_eq!(d[0].code, Code::SyntaxExpressionTooLarge);
    }
}
