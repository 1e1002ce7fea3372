//! Stage 1, syntax: what the pest converter and the fast parser share so that both build the
//! same AST: precedence folding of `term (op term)*` with an explicit operator stack (`* /`
//! bind tighter than `+ -`, both left-associative; no recursion per operator, so a long sum
//! cannot overflow the stack) and string unescaping.

use crate::syntax::ast::*;

fn prec(op: BinOp) -> u8 {
    match op {
        BinOp::Add | BinOp::Sub => 1,
        BinOp::Mul | BinOp::Div => 2,
    }
}

/// Takes the operator `op` that follows the operands so far: folds what binds at least as
/// tightly, then stacks `op`.
pub(crate) fn push_op(operands: &mut Vec<Expr>, ops: &mut Vec<BinOp>, op: BinOp) {
    while let Some(&top) = ops.last() {
        if prec(top) >= prec(op) {
            ops.pop();
            reduce(operands, top);
        } else {
            break;
        }
    }
    ops.push(op);
}

/// Folds what is left: the one expression of `term (op term)*`.
#[allow(
    clippy::expect_used,
    reason = "callers push a first operand before any operator, and one per operator"
)]
pub(crate) fn finish(mut operands: Vec<Expr>, mut ops: Vec<BinOp>) -> Expr {
    while let Some(op) = ops.pop() {
        reduce(&mut operands, op);
    }
    operands
        .pop()
        .expect("grammar: an expression has at least one term")
}

#[allow(
    clippy::expect_used,
    reason = "the operator stack holds two operands per binary operator"
)]
fn reduce(operands: &mut Vec<Expr>, op: BinOp) {
    let rhs = operands
        .pop()
        .expect("operator stack: a binary op has a right operand");
    let lhs = operands
        .pop()
        .expect("operator stack: a binary op has a left operand");
    let span = lhs.span.join(rhs.span);
    operands.push(Expr {
        kind: ExprKind::Binary {
            op,
            lhs: Box::new(lhs),
            rhs: Box::new(rhs),
        },
        span,
    });
}

/// A string literal's text as written between its quotes → its value (`\n`, `\t`; any other
/// escaped character stands for itself).
pub(crate) fn unescape(raw: &str) -> String {
    let mut out = String::with_capacity(raw.len());
    let mut chars = raw.chars();
    while let Some(c) = chars.next() {
        if c == '\\' {
            match chars.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some(other) => out.push(other),
                None => out.push('\\'),
            }
        } else {
            out.push(c);
        }
    }
    out
}
