//! Language server: the declared names hover and completion offer, by kind.
//!
//! Until the symbol index (`symbols.rs`) is merged, this reads the open document's own
//! declarations with the tolerant token scan (`KEYWORD NAME` at bracket depth 0, groups at any
//! depth; a declaration in column 0 closes blocks left open), which works on text that does
//! not parse.

use lsp_types::CompletionItemKind;

use crate::fmt::tokens::{tokenize, TokenKind};

/// What a declared name names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NameKind {
    /// `let NAME = ...`.
    Constant,
    /// `camera NAME { ... }`.
    Camera,
    /// `material NAME = ...`.
    Material,
    /// `texture NAME = ...`.
    Texture,
    /// `mesh NAME = ...`.
    Mesh,
    /// `light NAME = ...`.
    Light,
    /// `group NAME { ... }`.
    Group,
}

impl NameKind {
    /// The statement keyword that declares it.
    pub fn keyword(self) -> &'static str {
        match self {
            NameKind::Constant => "let",
            NameKind::Camera => "camera",
            NameKind::Material => "material",
            NameKind::Texture => "texture",
            NameKind::Mesh => "mesh",
            NameKind::Light => "light",
            NameKind::Group => "group",
        }
    }

    /// The kind a statement keyword declares.
    pub fn of_keyword(keyword: &str) -> Option<NameKind> {
        [
            NameKind::Constant,
            NameKind::Camera,
            NameKind::Material,
            NameKind::Texture,
            NameKind::Mesh,
            NameKind::Light,
            NameKind::Group,
        ]
        .into_iter()
        .find(|k| k.keyword() == keyword)
    }

    /// How an editor shows it in a completion list.
    pub fn completion_kind(self) -> CompletionItemKind {
        match self {
            NameKind::Constant => CompletionItemKind::CONSTANT,
            NameKind::Camera | NameKind::Light | NameKind::Group => CompletionItemKind::VARIABLE,
            NameKind::Material | NameKind::Texture | NameKind::Mesh => CompletionItemKind::VALUE,
        }
    }
}

/// One declared name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Declared {
    /// The name.
    pub name: String,
    /// What it names.
    pub kind: NameKind,
    /// A one-line summary of its declaration (`material wall = phong`).
    pub summary: String,
}

/// The names `text` declares.
pub fn declared(text: &str) -> Vec<Declared> {
    let tokens: Vec<_> = tokenize(text)
        .into_iter()
        .filter(|t| !matches!(t.kind, TokenKind::LineComment | TokenKind::BlockComment))
        .collect();
    let mut depth = 0usize;
    let mut out = Vec::new();
    for (i, t) in tokens.iter().enumerate() {
        match t.kind {
            TokenKind::Punct('{' | '(') => depth += 1,
            TokenKind::Punct('}' | ')') => depth = depth.saturating_sub(1),
            _ => {}
        }
        let Some(kind) = NameKind::of_keyword(t.text) else {
            continue;
        };
        // A declaration in column 0 ends any block left open above it (mid-edit text).
        if t.spaces_before == 0 && (t.newlines_before > 0 || i == 0) {
            depth = 0;
        }
        let Some(name) = tokens.get(i + 1).filter(|n| is_name(n.text)) else {
            continue;
        };
        if depth > 0 && kind != NameKind::Group {
            continue;
        }
        let line_end = text[t.start..]
            .find('\n')
            .map_or(text.len(), |n| t.start + n);
        let line = text[t.start..line_end].trim_end();
        let summary = match line.char_indices().nth(80) {
            Some((cut, _)) => format!("`{}…`", &line[..cut]),
            None => format!("`{line}`"),
        };
        out.push(Declared {
            name: name.text.to_string(),
            kind,
            summary,
        });
    }
    out
}

fn is_name(word: &str) -> bool {
    word.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn declarations_by_kind_even_mid_edit() {
        let names =
            declared("scnc 1\nlet a = 1\nmaterial w = phong { diffuse\nmesh m = sphere {}\n");
        let found: Vec<(NameKind, &str)> =
            names.iter().map(|d| (d.kind, d.name.as_str())).collect();
        assert_eq!(
            found,
            vec![
                (NameKind::Constant, "a"),
                (NameKind::Material, "w"),
                (NameKind::Mesh, "m")
            ]
        );
    }
}
