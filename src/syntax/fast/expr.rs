//! Stage 1, syntax (fast path): terms and expressions of `grammar/scene.pest` straight to
//! [`Expr`], with the spans and the precedence folding of the pest converter
//! (`convert/expr.rs`): `term = neg* primary`, `expr = term (bin_op term)*`.

use super::cursor::Cursor;
use crate::syntax::ast::*;
use crate::syntax::convert::fold::{self, unescape};
use crate::syntax::MAX_EXPR_NODES;

impl Cursor<'_> {
    /// Counts one term (the converter counts a term inside an expression twice; counting
    /// every term twice never undercounts). `None` once past the limit: pest and the converter
    /// then report the expression as too large.
    fn count_term(&mut self) -> Option<()> {
        self.nodes += 2;
        (self.nodes <= MAX_EXPR_NODES).then_some(())
    }

    /// A top-level term: a block item, the value of `scnc` or `include`.
    pub fn top_term(&mut self) -> Option<Expr> {
        self.nodes = 0;
        self.term()
    }

    /// A top-level expression: a `let` value.
    pub fn top_expr(&mut self) -> Option<Expr> {
        self.nodes = 0;
        self.expr()
    }

    /// `term = neg* ~ primary`; an odd number of signs is one `Neg` spanning the term.
    pub fn term(&mut self) -> Option<Expr> {
        self.count_term()?;
        let start = self.pos;
        let mut negs = 0usize;
        while self.peek() == Some(b'-') {
            negs += 1;
            self.pos += 1;
            self.skip();
        }
        let e = self.primary()?;
        Some(if negs % 2 == 1 {
            Expr {
                span: self.span(start, e.span.end as usize),
                kind: ExprKind::Neg(Box::new(e)),
            }
        } else {
            e
        })
    }

    /// `expr = term ~ (bin_op ~ term)*`, folded like the converter folds it.
    ///
    /// pest's `term ~ (bin_op ~ term)*` keeps the whitespace after the first term (the
    /// sequence's skip) but not after a later one (a failed repetition's); the cursor is left
    /// where pest leaves it (a `let` statement's span ends at its value either way).
    pub fn expr(&mut self) -> Option<Expr> {
        let first = self.term()?;
        self.skip();
        let Some(op) = self.bin_op() else {
            // The common case, one term: no operand stacks.
            return Some(first);
        };
        let mut operands = vec![first];
        let mut ops: Vec<BinOp> = Vec::new();
        let mut op = op;
        loop {
            self.pos += 1;
            self.skip();
            fold::push_op(&mut operands, &mut ops, op);
            operands.push(self.term()?);
            let before = self.pos;
            self.skip();
            match self.bin_op() {
                Some(next) => op = next,
                None => {
                    self.pos = before;
                    break;
                }
            }
        }
        Some(fold::finish(operands, ops))
    }

    /// The operator at the cursor, if any (not consumed).
    fn bin_op(&self) -> Option<BinOp> {
        match self.peek()? {
            b'+' => Some(BinOp::Add),
            b'-' => Some(BinOp::Sub),
            b'*' => Some(BinOp::Mul),
            b'/' => Some(BinOp::Div),
            _ => None,
        }
    }

    fn primary(&mut self) -> Option<Expr> {
        let start = self.pos;
        let kind = match self.peek()? {
            b if super::cursor::is_ident_start(b) => {
                let end = self.word_end()?;
                if self.at(end) == Some(b'(') {
                    let func = self.ident()?;
                    let args = self.call_args()?;
                    ExprKind::Call(Box::new(Call { func, args }))
                } else {
                    self.pos = end;
                    ExprKind::Name(Name::new(&self.text[start..end]))
                }
            }
            b'0'..=b'9' | b'.' => self.number()?,
            b'(' => self.paren()?,
            b'#' => ExprKind::HexColor(self.hex_color().to_string()),
            b'"' => ExprKind::Str(unescape(self.string_raw()?)),
            b'[' => {
                self.array()?;
                ExprKind::Array
            }
            _ => return None,
        };
        Some(Expr {
            kind,
            span: self.span(start, self.pos),
        })
    }

    /// `number = ${ digits ~ suffix? }`.
    fn number(&mut self) -> Option<ExprKind> {
        let end = self.digits_end()?;
        // The grammar only admits well-formed decimal literals, which f64 parses (as in the
        // converter; `decimal` gives the same bits, the short ones without `str::parse`).
        let value = super::decimal::value(&self.text[self.pos..end]);
        self.pos = end;
        let suffix = match self.peek() {
            Some(b) if super::cursor::is_ident_start(b) => Some(self.ident()?.name),
            _ => None,
        };
        Some(ExprKind::Number { value, suffix })
    }

    /// `paren = "(" ~ expr ~ ("," ~ expr)* ~ ","? ~ ")"`: one part is `Paren`, more a `Tuple`.
    fn paren(&mut self) -> Option<ExprKind> {
        let mut parts = self.list()?;
        if parts.is_empty() {
            return None;
        }
        Some(if parts.len() == 1 {
            ExprKind::Paren(Box::new(parts.remove(0)))
        } else {
            ExprKind::Tuple(parts)
        })
    }

    /// `call_args = "(" ~ (expr ~ ("," ~ expr)* ~ ","?)? ~ ")"`.
    pub fn call_args(&mut self) -> Option<Vec<Expr>> {
        self.list()
    }

    /// `( e, e, ... )` with an optional trailing comma, possibly empty, the cursor on `(`.
    fn list(&mut self) -> Option<Vec<Expr>> {
        self.eat(b'(')?;
        self.open()?;
        self.skip();
        if self.eat(b')').is_some() {
            self.close();
            return Some(Vec::new());
        }
        // Room for a vector or a colour at once (the capacity the first push would give),
        // without the general growth path a push into an empty `Vec` takes.
        let mut parts = Vec::with_capacity(4);
        loop {
            parts.push(self.expr()?);
            self.skip();
            if self.eat(b')').is_some() {
                break;
            }
            self.eat(b',')?;
            self.skip();
            if self.eat(b')').is_some() {
                break;
            }
        }
        self.close();
        Some(parts)
    }
}
