//! Stage 1, syntax: expression parse trees → [`Expr`], folded by precedence.
//!
//! The folding (`fold.rs`) is shared with the fast parser; every node counts towards the
//! top-level expression's [`super::MAX_EXPR_NODES`].

use pest::iterators::Pair;

use super::fold::{self, unescape};
use super::{part, Converter};
use crate::syntax::ast::*;
use crate::syntax::Rule;

impl Converter {
    /// `expr = term (op term)*`, folded with a two-level precedence by an explicit stack.
    pub fn expr(&self, pair: Pair<Rule>) -> Expr {
        if self.overflowed() {
            return self.error_expr(&pair);
        }
        let mut operands: Vec<Expr> = Vec::new();
        let mut ops: Vec<BinOp> = Vec::new();
        let whole = pair.clone();
        for p in pair.into_inner() {
            if self.overflowed() {
                // Stop building: the caller replaces the whole expression anyway.
                return self.error_expr(&whole);
            }
            if p.as_rule() == Rule::bin_op {
                let op = match p.as_str() {
                    "+" => BinOp::Add,
                    "-" => BinOp::Sub,
                    "*" => BinOp::Mul,
                    _ => BinOp::Div,
                };
                fold::push_op(&mut operands, &mut ops, op);
            } else {
                self.count();
                operands.push(self.term(p));
            }
        }
        fold::finish(operands, ops)
    }

    fn error_expr(&self, pair: &Pair<Rule>) -> Expr {
        Expr {
            kind: ExprKind::Error,
            span: self.span(pair),
        }
    }

    #[allow(clippy::expect_used, reason = "the grammar gives a term a primary")]
    pub(super) fn term(&self, pair: Pair<Rule>) -> Expr {
        if self.overflowed() {
            return self.error_expr(&pair);
        }
        self.count();
        let span = self.span(&pair);
        let mut negs = 0usize;
        let mut primary = None;
        for p in pair.into_inner() {
            if p.as_rule() == Rule::neg {
                negs += 1;
            } else {
                primary = Some(self.primary(p));
            }
        }
        let mut e = primary.expect("grammar: a term has a primary");
        // `--x` is `x`: collapsing keeps the tree shallow however many signs are written.
        if negs % 2 == 1 {
            e = Expr {
                kind: ExprKind::Neg(Box::new(e)),
                span,
            };
        }
        e
    }

    fn primary(&self, pair: Pair<Rule>) -> Expr {
        let span = self.span(&pair);
        let kind = match pair.as_rule() {
            Rule::number => {
                let mut inner = pair.into_inner();
                let digits = part(&mut inner, "a number has digits");
                // The grammar only admits well-formed decimal literals, which f64 parses; the
                // fallback is for literals too long to matter.
                let value = digits.as_str().parse::<f64>().unwrap_or(f64::NAN);
                let suffix = inner.next().map(|s| self.ident(s).name);
                ExprKind::Number { value, suffix }
            }
            Rule::hex_color => ExprKind::HexColor(pair.as_str()[1..].to_string()),
            Rule::string => {
                let raw = pair.into_inner().next().map_or("", |p| p.as_str());
                ExprKind::Str(unescape(raw))
            }
            Rule::call => {
                let (func, args) = self.call_parts(pair);
                ExprKind::Call(Box::new(Call { func, args }))
            }
            Rule::paren => {
                let mut parts: Vec<Expr> = pair.into_inner().map(|p| self.expr(p)).collect();
                if parts.len() == 1 {
                    ExprKind::Paren(Box::new(parts.remove(0)))
                } else {
                    ExprKind::Tuple(parts)
                }
            }
            Rule::array => ExprKind::Array,
            _ => ExprKind::Name(Name::new(pair.as_str())),
        };
        Expr { kind, span }
    }
}
