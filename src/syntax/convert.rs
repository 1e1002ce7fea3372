//! Stage 1, syntax: pest parse tree → AST ([`SceneFile`]).
//!
//! Every node gets a [`Span`] in the file it came from (`base` shifts positions when a chunk of
//! the file was parsed alone during error recovery). Expressions are folded into a tree with
//! the usual precedence (`* /` over `+ -`, left-associative) by an explicit operator stack, not
//! recursion, so long expressions cannot overflow the stack; nesting depth is bounded earlier by
//! the bracket pre-scan in `recover`.

use std::cell::{Cell, RefCell};

use pest::iterators::{Pair, Pairs};

use super::ast::*;
use super::Rule;
use crate::diag::{Code, Diagnostic};
use crate::source::{FileId, Span};

/// Most nodes one top-level expression may have. Keeps every later recursion over expressions
/// (folding, dropping) shallow whatever the input.
pub const MAX_EXPR_NODES: usize = 256;

pub(super) struct Converter {
    pub file: FileId,
    pub base: usize,
    /// Nodes built for the current top-level expression.
    nodes: Cell<usize>,
    pub errors: RefCell<Vec<Diagnostic>>,
}

impl Converter {
    pub fn new(file: FileId, base: usize) -> Converter {
        Converter {
            file,
            base,
            nodes: Cell::new(0),
            errors: RefCell::new(Vec::new()),
        }
    }

    /// Converts one top-level expression (a `let` value, a block item, a call argument list's
    /// owner), replacing it by [`ExprKind::Error`] if it is too large.
    fn top<F: FnOnce(&Converter) -> Expr>(&self, pair: &Pair<Rule>, f: F) -> Expr {
        self.nodes.set(0);
        let e = f(self);
        if self.nodes.get() > MAX_EXPR_NODES {
            let span = self.span(pair);
            drop(e);
            self.errors.borrow_mut().push(
                Diagnostic::error(
                    Code::SyntaxExpressionTooLarge,
                    format!("expression too large (more than {MAX_EXPR_NODES} terms)"),
                )
                .at(span, "this expression")
                .help("split it into several `let` constants"),
            );
            return Expr {
                kind: ExprKind::Error,
                span,
            };
        }
        e
    }

    fn overflowed(&self) -> bool {
        self.nodes.get() > MAX_EXPR_NODES
    }

    fn count(&self) {
        self.nodes.set(self.nodes.get() + 1);
    }

    fn top_term(&self, pair: Pair<Rule>) -> Expr {
        let p2 = pair.clone();
        self.top(&p2, |c| c.term(pair))
    }

    fn top_expr(&self, pair: Pair<Rule>) -> Expr {
        let p2 = pair.clone();
        self.top(&p2, |c| c.expr(pair))
    }

    fn span(&self, pair: &Pair<Rule>) -> Span {
        let s = pair.as_span();
        Span::new(self.file, self.base + s.start(), self.base + s.end())
    }

    fn ident(&self, pair: Pair<Rule>) -> Ident {
        Ident {
            name: pair.as_str().to_string(),
            span: self.span(&pair),
        }
    }

    pub fn file(&self, pair: Pair<Rule>) -> Vec<Stmt> {
        pair.into_inner()
            .filter(|p| p.as_rule() != Rule::EOI)
            .map(|p| self.statement(p))
            .collect()
    }

    fn statement(&self, pair: Pair<Rule>) -> Stmt {
        let span = self.span(&pair);
        let rule = pair.as_rule();
        let mut inner = pair.into_inner();
        let kw = part(&mut inner, "every statement starts with its keyword");
        match rule {
            Rule::version => Stmt::Version {
                value: self.top_term(part(&mut inner, "version has a value")),
                span,
            },
            Rule::include => Stmt::Include {
                path: self.top_term(part(&mut inner, "include has a path")),
                span,
            },
            Rule::let_stmt => Stmt::Let {
                name: self.ident(part(&mut inner, "let has a name")),
                value: self.top_expr(part(&mut inner, "let has a value")),
                span,
            },
            Rule::camera => Stmt::Camera {
                name: self.ident(part(&mut inner, "camera has a name")),
                body: self.block(part(&mut inner, "camera has a block")),
                span,
            },
            Rule::object => Stmt::Object(self.object_rest(inner, span)),
            Rule::group => Stmt::Group(self.group_rest(inner, span)),
            Rule::render => Stmt::Render {
                body: self.block(part(&mut inner, "render has a block")),
                span,
            },
            Rule::decl => {
                let kind = match kw.as_rule() {
                    Rule::kw_material => DeclKind::Material,
                    Rule::kw_texture => DeclKind::Texture,
                    Rule::kw_mesh => DeclKind::Mesh,
                    _ => DeclKind::Light,
                };
                let name = self.ident(part(&mut inner, "decl has a name"));
                let ctor = self.ctor(part(&mut inner, "decl has a constructor"));
                let body = inner.next().map(|b| self.block(b));
                Stmt::Decl(Decl {
                    kind,
                    name,
                    ctor,
                    body,
                    span,
                })
            }
            _ => unreachable!("grammar: `statement` has no other alternatives"),
        }
    }

    fn object_rest(&self, mut inner: pest::iterators::Pairs<Rule>, span: Span) -> ObjectStmt {
        ObjectStmt {
            mesh: self.ident(part(&mut inner, "object names a mesh")),
            body: self.block(part(&mut inner, "object has a block")),
            span,
        }
    }

    fn group_rest(&self, mut inner: pest::iterators::Pairs<Rule>, span: Span) -> GroupStmt {
        GroupStmt {
            name: self.ident(part(&mut inner, "group has a name")),
            body: self.block(part(&mut inner, "group has a block")),
            span,
        }
    }

    #[allow(
        clippy::expect_used,
        reason = "the grammar makes every call part a child of its callee"
    )]
    fn ctor(&self, pair: Pair<Rule>) -> Ctor {
        let span = self.span(&pair);
        let inner = part(&mut pair.into_inner(), "ctor is a call or a name");
        match inner.as_rule() {
            Rule::call => {
                let p2 = inner.clone();
                let mut args = Vec::new();
                let mut func = None;
                let e = self.top(&p2, |c| {
                    let (f, a) = c.call_parts(inner);
                    func = Some(f);
                    args = a;
                    Expr {
                        kind: ExprKind::Array,
                        span,
                    }
                });
                if matches!(e.kind, ExprKind::Error) {
                    args = vec![e];
                }
                Ctor {
                    name: func.expect("call_parts always runs inside top"),
                    args: Some(args),
                    span,
                }
            }
            _ => Ctor {
                name: self.ident(inner),
                args: None,
                span,
            },
        }
    }

    #[allow(clippy::expect_used, reason = "the grammar gives a transform a block")]
    fn block(&self, pair: Pair<Rule>) -> Block {
        let span = self.span(&pair);
        let items = pair
            .into_inner()
            .map(|p| {
                let item_span = self.span(&p);
                match p.as_rule() {
                    Rule::transform => Item::Transform(
                        self.block(
                            p.into_inner()
                                .nth(1)
                                .expect("grammar: transform has a block"),
                        ),
                    ),
                    Rule::object => {
                        let mut inner = p.into_inner();
                        inner.next();
                        Item::Object(self.object_rest(inner, item_span))
                    }
                    Rule::group => {
                        let mut inner = p.into_inner();
                        inner.next();
                        Item::Group(self.group_rest(inner, item_span))
                    }
                    _ => Item::Value(self.top_term(p)),
                }
            })
            .collect();
        Block { items, span }
    }

    fn call_parts(&self, pair: Pair<Rule>) -> (Ident, Vec<Expr>) {
        let mut inner = pair.into_inner();
        let func = self.ident(part(&mut inner, "call has a callee"));
        let args = part(&mut inner, "call has arguments")
            .into_inner()
            .map(|a| self.expr(a))
            .collect();
        (func, args)
    }

    /// `expr = term (op term)*`, folded with a two-level precedence by an explicit stack.
    #[allow(
        clippy::expect_used,
        reason = "the grammar gives an expression at least one term"
    )]
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
                while let Some(&top) = ops.last() {
                    if prec(top) >= prec(op) {
                        ops.pop();
                        reduce(&mut operands, top);
                    } else {
                        break;
                    }
                }
                ops.push(op);
            } else {
                self.count();
                operands.push(self.term(p));
            }
        }
        while let Some(op) = ops.pop() {
            reduce(&mut operands, op);
        }
        operands
            .pop()
            .expect("grammar: an expression has at least one term")
    }

    fn error_expr(&self, pair: &Pair<Rule>) -> Expr {
        Expr {
            kind: ExprKind::Error,
            span: self.span(pair),
        }
    }

    #[allow(clippy::expect_used, reason = "the grammar gives a term a primary")]
    fn term(&self, pair: Pair<Rule>) -> Expr {
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
                let suffix = inner.next().map(|s| self.ident(s));
                ExprKind::Number { value, suffix }
            }
            Rule::hex_color => ExprKind::HexColor(pair.as_str()[1..].to_string()),
            Rule::string => {
                let raw = pair.into_inner().next().map_or("", |p| p.as_str());
                ExprKind::Str(unescape(raw))
            }
            Rule::call => {
                let (func, args) = self.call_parts(pair);
                ExprKind::Call { func, args }
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
            _ => ExprKind::Name(pair.as_str().to_string()),
        };
        Expr { kind, span }
    }
}

/// The next child of a parse-tree node whose rule in `grammar/scene.pest` always has it (`what`
/// names the rule's guarantee). Only a grammar change that forgot this converter can break
/// that, so it is an invariant of the program, not a user error.
fn part<'i>(pairs: &mut Pairs<'i, Rule>, what: &str) -> Pair<'i, Rule> {
    match pairs.next() {
        Some(pair) => pair,
        None => unreachable!("grammar: {what}"),
    }
}

fn prec(op: BinOp) -> u8 {
    match op {
        BinOp::Add | BinOp::Sub => 1,
        BinOp::Mul | BinOp::Div => 2,
    }
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

fn unescape(raw: &str) -> String {
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
