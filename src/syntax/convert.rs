//! Stage 1, syntax: pest parse tree → AST ([`SceneFile`]).
//!
//! Every node gets a [`Span`] in the file it came from (`base` shifts positions when a chunk of
//! the file was parsed alone during error recovery). Statements, declarations and blocks are
//! here; expressions, folded by precedence with an explicit operator stack, in `convert/expr.rs`.
//! Nesting depth is bounded earlier by the bracket pre-scan (`scan.rs`).

use std::cell::{Cell, RefCell};

use pest::iterators::{Pair, Pairs};

mod expr;
pub(super) mod fold;

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
            name: Name::new(pair.as_str()),
            span: self.span(&pair),
        }
    }

    pub fn file(&self, pair: Pair<Rule>) -> Vec<Stmt> {
        pair.into_inner()
            .filter(|p| p.as_rule() != Rule::EOI)
            .map(|p| self.statement(p))
            .collect()
    }

    pub fn statement(&self, pair: Pair<Rule>) -> Stmt {
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
            Rule::let_stmt => {
                let name = self.ident(part(&mut inner, "let has a name"));
                let value = self.top_expr(part(&mut inner, "let has a value"));
                Stmt::Let {
                    span: to_last_token(span, value.span),
                    name,
                    value,
                }
            }
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
                let last = body.as_ref().map_or(ctor.span, |b| b.span);
                Stmt::Decl(Box::new(Decl {
                    kind,
                    name,
                    ctor,
                    body,
                    span: to_last_token(span, last),
                }))
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
                        Item::Object(Box::new(self.object_rest(inner, item_span)))
                    }
                    Rule::group => {
                        let mut inner = p.into_inner();
                        inner.next();
                        Item::Group(Box::new(self.group_rest(inner, item_span)))
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

/// A statement's span (`whole`, pest's) cut at the end of its last part (`last`): pest's
/// `let_stmt` and a block-less `decl` take the blanks and comments after their last token
/// (skipped while looking for a further operator or a `{`), and a statement must not change
/// with what follows it (an incremental compile maps an edit to the statements it touches).
fn to_last_token(whole: Span, last: Span) -> Span {
    Span::new(
        whole.file,
        whole.start as usize,
        last.end.max(whole.start) as usize,
    )
}
