//! Language server: the folding ranges of one document, from its own parse and the
//! comment-keeping token scan: blocks and `[ ... ]` arrays over several lines, runs of line
//! comments each alone on its line, block comments over several lines.
//!
//! A fold ends on the line before its closing `}` or `]` when that line holds nothing else, so
//! the closer stays visible; otherwise on the closer's line.

use lsp_types::{FoldingRange, FoldingRangeKind};

use super::position::LineIndex;
use crate::fmt::tokens::{tokenize, TokenKind};
use crate::source::{FileId, Span};
use crate::syntax::{self, Block, Expr, ExprKind, Item, Stmt};

/// The folding ranges of `text`, in text order.
pub fn ranges(text: &str) -> Vec<FoldingRange> {
    let parsed = syntax::parse(FileId(0), text).value.unwrap_or_default();
    let index = LineIndex::new(text);
    let mut folds = Folds {
        index: &index,
        text,
        out: Vec::new(),
    };
    for stmt in &parsed.statements {
        folds.statement(stmt);
    }
    folds.comments();
    let mut out = folds.out;
    out.sort_by_key(|f| (f.start_line, f.end_line));
    out
}

struct Folds<'a> {
    index: &'a LineIndex<'a>,
    text: &'a str,
    out: Vec<FoldingRange>,
}

impl Folds<'_> {
    fn statement(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Let { value, .. } => self.expr(value),
            Stmt::Camera { body, .. } | Stmt::Render { body, .. } => self.block(body),
            Stmt::Decl(d) => {
                d.ctor.args.iter().flatten().for_each(|a| self.expr(a));
                if let Some(body) = &d.body {
                    self.block(body);
                }
            }
            Stmt::Object(o) => self.block(&o.body),
            Stmt::Group(g) => self.block(&g.body),
            Stmt::Version { .. } | Stmt::Include { .. } => {}
        }
    }

    fn block(&mut self, block: &Block) {
        self.bracketed(block.span, None);
        for item in &block.items {
            match item {
                Item::Value(e) => self.expr(e),
                Item::Transform(b) => self.block(b),
                Item::Object(o) => self.block(&o.body),
                Item::Group(g) => self.block(&g.body),
            }
        }
    }

    fn expr(&mut self, e: &Expr) {
        match &e.kind {
            ExprKind::Array => self.bracketed(e.span, None),
            ExprKind::Call(call) => call.args.iter().for_each(|p| self.expr(p)),
            ExprKind::Tuple(parts) => parts.iter().for_each(|p| self.expr(p)),
            ExprKind::Paren(inner) | ExprKind::Neg(inner) => self.expr(inner),
            ExprKind::Binary { lhs, rhs, .. } => {
                self.expr(lhs);
                self.expr(rhs);
            }
            _ => {}
        }
    }

    /// A fold over `span` (a bracketed region, or a comment when `kind` says so).
    fn bracketed(&mut self, span: Span, kind: Option<FoldingRangeKind>) {
        let open = self.index.position(span.start as usize).line;
        let close = self.index.position(span.end as usize).line;
        // The closer's line holds nothing before it (`get` is `None` off a char boundary: a
        // span of mangled text, or an unclosed comment, may end inside a multi-byte character).
        let last = (span.end as usize).saturating_sub(1);
        let line_start = self
            .text
            .get(..last)
            .and_then(|before| before.rfind('\n'))
            .map_or(0, |n| n + 1);
        let closer_alone = kind.is_none()
            && self
                .text
                .get(line_start..last)
                .is_some_and(|before| before.trim().is_empty());
        let end = if closer_alone {
            close.saturating_sub(1)
        } else {
            close
        };
        if end > open {
            self.out.push(fold(open, end, kind));
        }
    }

    /// Runs of line comments on consecutive lines (each alone on its line), and block comments
    /// over several lines.
    fn comments(&mut self) {
        let mut run: Option<(u32, u32)> = None;
        for token in tokenize(self.text) {
            let line = self.index.position(token.start).line;
            // A comment after code on its line is no part of a run.
            let own_line = token.newlines_before > 0 || token.start == 0;
            match token.kind {
                TokenKind::LineComment if own_line => match &mut run {
                    Some((_, last)) if *last + 1 == line => *last = line,
                    _ => {
                        self.close_run(run.take());
                        run = Some((line, line));
                    }
                },
                TokenKind::BlockComment => {
                    self.close_run(run.take());
                    let end = token.start + token.text.len();
                    let span = Span::new(FileId(0), token.start, end);
                    self.bracketed(span, Some(FoldingRangeKind::Comment));
                }
                _ => self.close_run(run.take()),
            }
        }
        self.close_run(run);
    }

    fn close_run(&mut self, run: Option<(u32, u32)>) {
        if let Some((first, last)) = run.filter(|(f, l)| l > f) {
            self.out
                .push(fold(first, last, Some(FoldingRangeKind::Comment)));
        }
    }
}

fn fold(start_line: u32, end_line: u32, kind: Option<FoldingRangeKind>) -> FoldingRange {
    FoldingRange {
        start_line,
        start_character: None,
        end_line,
        end_character: None,
        kind,
        collapsed_text: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unclosed_comment_ending_in_non_ascii_folds_to_the_end() {
        let folds = ranges("scnc 1\n/* a\n é");
        let found: Vec<_> = folds.iter().map(|f| (f.start_line, f.end_line)).collect();
        assert_eq!(found, [(1, 2)]);
    }

    #[test]
    fn every_prefix_of_an_example_is_folded() {
        let text = include_str!("../../examples/showcase.scn");
        let mut folded = 0;
        for (end, _) in text.char_indices().step_by(13) {
            folded += ranges(&text[..end]).len();
        }
        assert!(folded > 0);
    }
}
