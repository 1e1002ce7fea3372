//! Stage 1 output: the AST of one `.scn` file, every node spanned.
//!
//! The AST mirrors the permissive grammar (grammar/scene.pest): a block is a flat list of
//! [`Item`]s; which keys exist and what they take is decided by `check`. Inline arrays
//! (`[ ... ]`) stay a span into the source and are parsed by `check::array` straight into IR
//! vectors, so a million-vertex mesh never exists as a million AST nodes.

use crate::source::Span;

/// A name as written, with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
}

impl BinOp {
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A number literal, with its unit suffix if any (`30deg` has suffix `deg`).
    Number {
        value: f64,
        suffix: Option<Ident>,
    },
    /// `#rgb` / `#rrggbb`, the text after `#` (validated by `check`).
    HexColor(String),
    Str(String),
    /// A name: a `let` constant, a declaration, or a keyword value (`true`, `repeat`, `y`).
    Name(String),
    /// `(e)`.
    Paren(Box<Expr>),
    /// `(a, b)` or `(a, b, c)` (any arity here; `check` accepts 2 and 3).
    Tuple(Vec<Expr>),
    Call {
        func: Ident,
        args: Vec<Expr>,
    },
    Neg(Box<Expr>),
    Binary {
        op: BinOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// `[ ... ]`: the span covers the brackets; parsed by `check::array`.
    Array,
    /// A part that was already reported as a syntax error (e.g. too large); `check` skips it.
    Error,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

impl Expr {
    /// The name, if this expression is a bare name.
    pub fn as_name(&self) -> Option<&str> {
        match &self.kind {
            ExprKind::Name(n) => Some(n),
            _ => None,
        }
    }
}

/// `{ ... }`: a flat list of items.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    pub items: Vec<Item>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    Value(Expr),
    Transform(Block),
    Object(ObjectStmt),
    Group(GroupStmt),
}

/// `object MESH { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectStmt {
    pub mesh: Ident,
    pub body: Block,
    pub span: Span,
}

/// `group NAME { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupStmt {
    pub name: Ident,
    pub body: Block,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeclKind {
    Material,
    Texture,
    Mesh,
    Light,
}

impl DeclKind {
    pub fn keyword(self) -> &'static str {
        match self {
            DeclKind::Material => "material",
            DeclKind::Texture => "texture",
            DeclKind::Mesh => "mesh",
            DeclKind::Light => "light",
        }
    }
}

/// The right-hand side head of a declaration: `phong`, `image("wood.png")`, `sphere`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ctor {
    pub name: Ident,
    /// `Some` when written as a call.
    pub args: Option<Vec<Expr>>,
    pub span: Span,
}

/// `material NAME = CTOR { ... }` and friends.
#[derive(Debug, Clone, PartialEq)]
pub struct Decl {
    pub kind: DeclKind,
    pub name: Ident,
    pub ctor: Ctor,
    pub body: Option<Block>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Stmt {
    /// `scnc 1`.
    Version {
        value: Expr,
        span: Span,
    },
    /// `include "file.scn"` (expanded by the driver, kept for completeness).
    Include {
        path: Expr,
        span: Span,
    },
    Let {
        name: Ident,
        value: Expr,
        span: Span,
    },
    Camera {
        name: Ident,
        body: Block,
        span: Span,
    },
    Decl(Decl),
    Object(ObjectStmt),
    Group(GroupStmt),
    Render {
        body: Block,
        span: Span,
    },
}

impl Stmt {
    pub fn span(&self) -> Span {
        match self {
            Stmt::Version { span, .. }
            | Stmt::Include { span, .. }
            | Stmt::Let { span, .. }
            | Stmt::Camera { span, .. }
            | Stmt::Render { span, .. } => *span,
            Stmt::Decl(d) => d.span,
            Stmt::Object(o) => o.span,
            Stmt::Group(g) => g.span,
        }
    }
}

/// One parsed file. `statements` holds every statement that parsed, even when other parts of
/// the file had syntax errors (those are reported separately).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SceneFile {
    pub statements: Vec<Stmt>,
}
