//! Language server: resolves the names of parsed statements into a [`SymbolIndex`], by the
//! checker's rules (`check::names`, `check::props`).
//!
//! First every declaration is registered in its kind's name space (statement order, includes
//! where they are included, groups depth first: the first declaration of a name wins, a
//! duplicate is another declaring occurrence of it; `true`, `false` and `frame` are no
//! constants). Then every block is split as the checker splits it: an item that is a key of the
//! block starts a property, the items after it are its values. A bare name as a value refers to
//! the kind its key names (`material NAME` in an object, `camera NAME` in render, ...; see
//! [`BlockKind::expected`]); any other bare name, in a block or an expression, refers to the
//! constant of that name if there is one.

use std::collections::HashMap;

use super::blocks::{BlockKind, Expected};
use super::symbols::{
    BlockSpan, Mark, Occurrence, Role, Symbol, SymbolId, SymbolIndex, SymbolKind,
};
use crate::check::vocabulary as v;
use crate::source::Span;
use crate::syntax::{Block, DeclKind, Expr, ExprKind, GroupStmt, Ident, Item, ObjectStmt, Stmt};

/// Names that are never constants (the checker rejects `let` of them).
const RESERVED: &[&str] = &["true", "false", "frame"];

/// The index of `statements` (its `sources` left empty for the caller).
pub(super) fn index(statements: &[Stmt]) -> SymbolIndex {
    let mut r = Resolver::default();
    for s in statements {
        r.declare_stmt(s);
    }
    for s in statements {
        r.stmt(s);
    }
    let Resolver {
        symbols,
        mut occurrences,
        mut marks,
        blocks,
        ..
    } = r;
    occurrences.sort_by_key(|o| (o.span.file, o.span.start));
    marks.sort_by_key(|m| (m.span.file, m.span.start));
    SymbolIndex {
        sources: Default::default(),
        symbols,
        occurrences,
        marks,
        blocks,
    }
}

#[derive(Default)]
struct Resolver {
    by_name: HashMap<(SymbolKind, String), SymbolId>,
    symbols: Vec<Symbol>,
    occurrences: Vec<Occurrence>,
    marks: Vec<Mark>,
    blocks: Vec<BlockSpan>,
}

fn decl_kind(kind: DeclKind) -> SymbolKind {
    match kind {
        DeclKind::Material => SymbolKind::Material,
        DeclKind::Texture => SymbolKind::Texture,
        DeclKind::Mesh => SymbolKind::Mesh,
        DeclKind::Light => SymbolKind::Light,
    }
}

impl Resolver {
    fn declare(&mut self, kind: SymbolKind, name: &Ident, span: Span, detail: Option<&Ident>) {
        if kind == SymbolKind::Constant && RESERVED.contains(&name.name.as_str()) {
            return;
        }
        let key = (kind, name.name.as_str().to_owned());
        if self.by_name.contains_key(&key) {
            return;
        }
        self.by_name.insert(key, SymbolId(self.symbols.len()));
        self.symbols.push(Symbol {
            name: name.name.as_str().to_owned(),
            kind,
            name_span: name.span,
            span,
            detail: detail.map(|d| d.name.as_str().to_owned()),
        });
    }

    fn declare_stmt(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Let { name, span, .. } => self.declare(SymbolKind::Constant, name, *span, None),
            Stmt::Camera { name, span, .. } => self.declare(SymbolKind::Camera, name, *span, None),
            Stmt::Decl(d) => self.declare(decl_kind(d.kind), &d.name, d.span, Some(&d.ctor.name)),
            Stmt::Group(g) => self.declare_group(g),
            Stmt::Version { .. } | Stmt::Include { .. } | Stmt::Object(_) | Stmt::Render { .. } => {
            }
        }
    }

    fn declare_group(&mut self, g: &GroupStmt) {
        self.declare(SymbolKind::Group, &g.name, g.span, None);
        for item in &g.body.items {
            if let Item::Group(child) = item {
                self.declare_group(child);
            }
        }
    }

    /// Records `name` written at `span` as `kind`, if such a symbol exists.
    fn occurrence(
        &mut self,
        kind: SymbolKind,
        name: &str,
        span: Span,
        declaration: bool,
        block: Option<BlockKind>,
    ) -> bool {
        let Some(&symbol) = self.by_name.get(&(kind, name.to_string())) else {
            return false;
        };
        self.occurrences.push(Occurrence {
            symbol,
            span,
            declaration,
            block,
        });
        true
    }

    fn mark(&mut self, span: Span, role: Role) {
        self.marks.push(Mark { span, role });
    }

    fn declared(&mut self, kind: SymbolKind, name: &Ident) {
        self.occurrence(kind, &name.name, name.span, true, None);
    }

    fn stmt(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Version { .. } | Stmt::Include { .. } => {}
            Stmt::Let { name, value, .. } => {
                self.declared(SymbolKind::Constant, name);
                self.expr(value, None, None);
            }
            Stmt::Camera { name, body, .. } => {
                self.declared(SymbolKind::Camera, name);
                self.block(body, BlockKind::Camera);
            }
            Stmt::Decl(d) => {
                self.declared(decl_kind(d.kind), &d.name);
                self.mark(d.ctor.name.span, Role::Kind);
                for arg in d.ctor.args.iter().flatten() {
                    self.expr(arg, None, None);
                }
                if let Some(body) = &d.body {
                    self.block(body, BlockKind::of_decl(d.kind, &d.ctor.name.name));
                }
            }
            Stmt::Object(o) => self.object(o),
            Stmt::Group(g) => self.group(g),
            Stmt::Render { body, .. } => self.block(body, BlockKind::Render),
        }
    }

    fn object(&mut self, o: &ObjectStmt) {
        self.occurrence(SymbolKind::Mesh, &o.mesh.name, o.mesh.span, false, None);
        self.block(&o.body, BlockKind::Object);
    }

    fn group(&mut self, g: &GroupStmt) {
        self.declared(SymbolKind::Group, &g.name);
        self.block(&g.body, BlockKind::Group);
    }

    /// Splits `block` into properties as `check::props` does and resolves their values.
    fn block(&mut self, block: &Block, kind: BlockKind) {
        self.blocks.push(BlockSpan {
            kind,
            span: block.span,
        });
        let keys = kind.keys();
        let mut current: Option<(&str, usize)> = None;
        for item in &block.items {
            let e = match item {
                Item::Value(e) => e,
                Item::Transform(b) => {
                    self.block(b, BlockKind::Transform);
                    continue;
                }
                Item::Object(o) => {
                    self.object(o);
                    continue;
                }
                Item::Group(g) => {
                    self.group(g);
                    continue;
                }
            };
            if let Some((key, span, args)) = as_key(e, keys) {
                self.mark(span, Role::Key);
                current = Some((key, 0));
                for arg in args {
                    self.property_value(arg, kind, &mut current);
                }
                continue;
            }
            self.property_value(e, kind, &mut current);
        }
    }

    /// One value of the current property (a value before any key is resolved as an expression).
    fn property_value(&mut self, e: &Expr, kind: BlockKind, current: &mut Option<(&str, usize)>) {
        let expected = current.and_then(|(key, i)| kind.expected(key, i));
        if let Some((_, i)) = current {
            *i += 1;
        }
        self.expr(e, expected, Some(kind));
    }

    /// Resolves the names of `e`; a bare `e` refers to `expected` when given.
    fn expr(&mut self, e: &Expr, expected: Option<Expected>, block: Option<BlockKind>) {
        match &e.kind {
            ExprKind::Name(name) => self.name(name, e.span, expected, block),
            ExprKind::Call(call) => {
                self.mark(call.func.span, Role::Function);
                for a in &call.args {
                    self.expr(a, None, block);
                }
            }
            ExprKind::Paren(inner) | ExprKind::Neg(inner) => self.expr(inner, None, block),
            ExprKind::Tuple(parts) => {
                for p in parts {
                    self.expr(p, None, block);
                }
            }
            ExprKind::Binary { lhs, rhs, .. } => {
                self.expr(lhs, None, block);
                self.expr(rhs, None, block);
            }
            ExprKind::Number { .. }
            | ExprKind::HexColor(_)
            | ExprKind::Str(_)
            | ExprKind::Array
            | ExprKind::Error => {}
        }
    }

    fn name(
        &mut self,
        name: &str,
        span: Span,
        expected: Option<Expected>,
        block: Option<BlockKind>,
    ) {
        let found = match expected {
            Some(Expected::Name(kind)) => self.occurrence(kind, name, span, false, block),
            Some(Expected::ConstantOrTexture) => {
                self.occurrence(SymbolKind::Constant, name, span, false, block)
                    || self.occurrence(SymbolKind::Texture, name, span, false, block)
            }
            None => self.occurrence(SymbolKind::Constant, name, span, false, block),
        };
        if !found && (RESERVED.contains(&name) || is_word(name)) {
            self.mark(span, Role::Word);
        }
    }
}

/// Whether `name` is one of the language's word values (`repeat`, `filmic`, `preview`).
fn is_word(name: &str) -> bool {
    v::WORDS.iter().any(|words| words.contains(&name))
}

/// The key `e` names in a block of `keys`: the key, its span, and a call's arguments (its
/// first values).
fn as_key<'e>(e: &'e Expr, keys: &[&'static str]) -> Option<(&'static str, Span, &'e [Expr])> {
    let (name, span, args) = match &e.kind {
        ExprKind::Name(n) => (n.as_str(), e.span, &[][..]),
        ExprKind::Call(call) => (call.func.name.as_str(), call.func.span, &call.args[..]),
        _ => return None,
    };
    let key = keys.iter().copied().find(|k| *k == name)?;
    Some((key, span, args))
}
