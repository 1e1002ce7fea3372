//! Language server: the outline of one document (document symbols: every declaration, object
//! and `render`, groups holding their objects and groups), from its own parse.

use lsp_types::{DocumentSymbol, SymbolKind as Lsp};

use super::position::LineIndex;
use crate::source::{FileId, Span};
use crate::syntax::{self, ExprKind, GroupStmt, Ident, Item, ObjectStmt, Stmt};

/// The outline of `text`: its statements as a tree of symbols.
pub fn symbols(text: &str) -> Vec<DocumentSymbol> {
    let parsed = syntax::parse(FileId(0), text).value.unwrap_or_default();
    let index = LineIndex::new(text);
    parsed
        .statements
        .iter()
        .filter_map(|s| statement(&index, s))
        .collect()
}

fn statement(index: &LineIndex<'_>, stmt: &Stmt) -> Option<DocumentSymbol> {
    let named = |name: &Ident, kind, detail: Option<&str>, span| {
        symbol(index, &name.name, kind, detail, span, name.span, Vec::new())
    };
    Some(match stmt {
        Stmt::Version { .. } => return None,
        Stmt::Include { path, span } => {
            let ExprKind::Str(file) = &path.kind else {
                return None;
            };
            symbol(
                index,
                file,
                Lsp::FILE,
                Some("include"),
                *span,
                path.span,
                Vec::new(),
            )
        }
        Stmt::Let { name, span, .. } => named(name, Lsp::CONSTANT, None, *span),
        Stmt::Camera { name, span, .. } => named(name, Lsp::OBJECT, Some("camera"), *span),
        Stmt::Decl(d) => {
            let kind = match d.kind {
                syntax::DeclKind::Material => Lsp::STRUCT,
                syntax::DeclKind::Texture => Lsp::TYPE_PARAMETER,
                syntax::DeclKind::Mesh => Lsp::CLASS,
                syntax::DeclKind::Light => Lsp::EVENT,
            };
            let detail = format!("{} = {}", d.kind.keyword(), d.ctor.name.name);
            named(&d.name, kind, Some(&detail), d.span)
        }
        Stmt::Object(o) => object(index, o),
        Stmt::Group(g) => group(index, g),
        Stmt::Render { span, .. } => {
            let keyword = Span::new(span.file, span.start as usize, span.start as usize + 6);
            symbol(
                index,
                "render",
                Lsp::MODULE,
                None,
                *span,
                keyword,
                Vec::new(),
            )
        }
    })
}

fn object(index: &LineIndex<'_>, o: &ObjectStmt) -> DocumentSymbol {
    let detail = Some("object");
    symbol(
        index,
        &o.mesh.name,
        Lsp::FIELD,
        detail,
        o.span,
        o.mesh.span,
        Vec::new(),
    )
}

fn group(index: &LineIndex<'_>, g: &GroupStmt) -> DocumentSymbol {
    let children = g
        .body
        .items
        .iter()
        .filter_map(|item| match item {
            Item::Object(o) => Some(object(index, o)),
            Item::Group(child) => Some(group(index, child)),
            Item::Value(_) | Item::Transform(_) => None,
        })
        .collect();
    let (name, span) = (&g.name, g.span);
    symbol(
        index,
        &name.name,
        Lsp::NAMESPACE,
        Some("group"),
        span,
        name.span,
        children,
    )
}

fn symbol(
    index: &LineIndex<'_>,
    name: &str,
    kind: Lsp,
    detail: Option<&str>,
    span: Span,
    selection: Span,
    children: Vec<DocumentSymbol>,
) -> DocumentSymbol {
    let range = |s: Span| index.range(s.start as usize, s.end as usize);
    // A statement's span takes the whitespace after it.
    let written = index
        .text()
        .get(span.range())
        .map_or(0, |t| t.trim_end().len());
    let span = Span::new(
        span.file,
        span.start as usize,
        span.start as usize + written,
    );
    #[allow(
        deprecated,
        reason = "`deprecated` is a field the protocol still requires"
    )]
    DocumentSymbol {
        name: name.to_string(),
        detail: detail.map(str::to_string),
        kind,
        tags: None,
        deprecated: None,
        range: range(span),
        selection_range: range(selection),
        children: (!children.is_empty()).then_some(children),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_prefix_of_an_example_is_outlined() {
        let text = include_str!("../../examples/showcase.scn");
        let mut outlined = 0;
        for (end, _) in text.char_indices().step_by(13) {
            outlined += symbols(&text[..end]).len();
        }
        assert!(outlined > 0);
    }

    /// An unclosed block comment ending in a multi-byte character folds without panicking
    /// (found by tests/lsp_robustness.rs).
    #[test]
    fn unclosed_comment_ending_mid_character() {
        for text in ["scnc 1\n/*éxé", "/*é\n\né", "/*\n𝛼"] {
            let _ = super::super::folding::ranges(text);
            let _ = symbols(text);
        }
    }
}
