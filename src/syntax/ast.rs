//! Stage 1 output: the AST of one `.scn` file, every node spanned.
//!
//! The AST mirrors the permissive grammar (grammar/scene.pest): a block is a flat list of
//! [`Item`]s; which keys exist and what they take is decided by `check`. Inline arrays
//! (`[ ... ]`) stay a span into the source and are parsed by `check::array` straight into IR
//! vectors, so a million-vertex mesh never exists as a million AST nodes.

use crate::source::Span;
pub use crate::syntax::name::Name;

/// A name as written, with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Ident {
    /// The name's text.
    pub name: Name,
    /// Where it is written.
    pub span: Span,
}

/// An arithmetic operator in an expression.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// `+`.
    Add,
    /// `-`.
    Sub,
    /// `*`.
    Mul,
    /// `/`.
    Div,
}

impl BinOp {
    /// The operator as written.
    pub fn symbol(self) -> &'static str {
        match self {
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
        }
    }
}

/// What an expression is.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A number literal, with its unit suffix if any (`30deg` has suffix `deg`).
    Number {
        /// The number's value.
        value: f64,
        /// The unit glued to it, if any: it ends where the number does ([`Expr::suffix`] has
        /// its span). Held inline, as names are: a box was an allocation and a free for
        /// every angle of a scene.
        suffix: Option<Name>,
    },
    /// `#rgb` / `#rrggbb`, the text after `#` (validated by `check`).
    HexColor(String),
    /// A string literal, unescaped.
    Str(String),
    /// A name: a `let` constant, a declaration, or a keyword value (`true`, `repeat`, `y`).
    Name(Name),
    /// `(e)`.
    Paren(Box<Expr>),
    /// `(a, b)` or `(a, b, c)` (any arity here; `check` accepts 2 and 3).
    Tuple(Vec<Expr>),
    /// `f(a, b)` (boxed, to keep every expression node small).
    Call(Box<Call>),
    /// `-e`.
    Neg(Box<Expr>),
    /// `lhs op rhs`.
    Binary {
        /// The operator.
        op: BinOp,
        /// The left operand.
        lhs: Box<Expr>,
        /// The right operand.
        rhs: Box<Expr>,
    },
    /// `[ ... ]`: the span covers the brackets; parsed by `check::array`.
    Array,
    /// A part that was already reported as a syntax error (e.g. too large); `check` skips it.
    Error,
}

/// `f(a, b)`: a function call.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    /// The function's name.
    pub func: Ident,
    /// The arguments in order.
    pub args: Vec<Expr>,
}

/// An expression with its span.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Where it is written.
    pub span: Span,
}

impl Expr {
    /// The unit suffix of a number literal, with its span (the last bytes of the number's).
    pub fn suffix(&self) -> Option<Ident> {
        match &self.kind {
            ExprKind::Number {
                suffix: Some(name), ..
            } => {
                let end = self.span.end as usize;
                Some(Ident {
                    name: name.clone(),
                    span: Span::new(self.span.file, end - name.len(), end),
                })
            }
            _ => None,
        }
    }

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
    /// The items in order; `check` splits them into properties.
    pub items: Vec<Item>,
    /// From `{` to `}`.
    pub span: Span,
}

/// One item of a block.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A key or a value (`check` decides which).
    Value(Expr),
    /// `transform { ... }`.
    Transform(Block),
    /// `object MESH { ... }` (inside a group; boxed, as the rarer and larger kind of item).
    Object(Box<ObjectStmt>),
    /// `group NAME { ... }` (inside a group; boxed).
    Group(Box<GroupStmt>),
}

/// `object MESH { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectStmt {
    /// The mesh it places.
    pub mesh: Ident,
    /// Its properties (`material`, `transform`).
    pub body: Block,
    /// The whole statement.
    pub span: Span,
}

/// `group NAME { ... }`.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupStmt {
    /// The group's name.
    pub name: Ident,
    /// Its transform, objects and groups.
    pub body: Block,
    /// The whole statement.
    pub span: Span,
}

/// The keyword of a declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DeclKind {
    /// `material`.
    Material,
    /// `texture`.
    Texture,
    /// `mesh`.
    Mesh,
    /// `light`.
    Light,
}

impl DeclKind {
    /// The keyword as written.
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
    /// The kind's name (`phong`, `image`).
    pub name: Ident,
    /// `Some` when written as a call.
    pub args: Option<Vec<Expr>>,
    /// From the name to the closing `)`.
    pub span: Span,
}

/// `material NAME = CTOR { ... }` and friends.
#[derive(Debug, Clone, PartialEq)]
pub struct Decl {
    /// Which keyword.
    pub kind: DeclKind,
    /// The declared name.
    pub name: Ident,
    /// What it is (`phong`, `obj("m.obj")`).
    pub ctor: Ctor,
    /// Its properties, if a block follows.
    pub body: Option<Block>,
    /// The whole declaration.
    pub span: Span,
}

/// A top-level statement.
#[derive(Debug, Clone, PartialEq)]
pub enum Stmt {
    /// `scnc 1`.
    Version {
        /// The version number.
        value: Expr,
        /// The whole statement.
        span: Span,
    },
    /// `include "file.scn"` (expanded by the driver, kept for completeness).
    Include {
        /// The file name (a string, or an error reported by the driver).
        path: Expr,
        /// The whole statement.
        span: Span,
    },
    /// `let NAME = EXPR`.
    Let {
        /// The constant's name.
        name: Ident,
        /// Its value.
        value: Expr,
        /// The whole statement.
        span: Span,
    },
    /// `camera NAME { ... }`.
    Camera {
        /// The camera's name.
        name: Ident,
        /// Its properties.
        body: Block,
        /// The whole statement.
        span: Span,
    },
    /// `material`/`texture`/`mesh`/`light NAME = ...` (boxed: the largest statement).
    Decl(Box<Decl>),
    /// `object MESH { ... }`.
    Object(ObjectStmt),
    /// `group NAME { ... }`.
    Group(GroupStmt),
    /// `render { ... }`.
    Render {
        /// Its settings.
        body: Block,
        /// The whole statement.
        span: Span,
    },
}

impl Stmt {
    /// The whole statement's span: from its keyword to its last token (a `let`'s value, a
    /// block-less declaration's constructor), never the blanks or comments after it.
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
    /// The statements in order.
    pub statements: Vec<Stmt>,
}
