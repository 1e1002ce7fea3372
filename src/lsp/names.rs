//! Language server: the declared names hover and completion show, read from the document's
//! [`SymbolIndex`] (the document and its includes: every name it can use), each with a one-line
//! summary of its declaration and where it is.

use lsp_types::CompletionItemKind;

use super::symbols::{Symbol, SymbolIndex, SymbolKind};
use crate::source::SourceMap;

/// One declared name, as completion offers it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Declared {
    /// The name.
    pub name: String,
    /// What it names.
    pub kind: SymbolKind,
    /// Markdown: its declaration's first line and where it is.
    pub summary: String,
}

/// Every name `index` declares, in declaration order.
pub fn declared(index: &SymbolIndex) -> Vec<Declared> {
    index
        .symbols()
        .map(|(_, s)| Declared {
            name: s.name.clone(),
            kind: s.kind,
            summary: summary(s, index.sources()),
        })
        .collect()
}

/// What a symbol is: its kind, its declaration's first line (in a code span) and its place,
/// `file.scn:LINE`.
pub fn summary(symbol: &Symbol, sources: &SourceMap) -> String {
    let file = sources.get(symbol.span.file);
    let start = (symbol.span.start as usize).min(file.text.len());
    let end = (symbol.span.end as usize).clamp(start, file.text.len());
    let declaration = file.text.get(start..end).unwrap_or_default();
    let first = declaration.lines().next().unwrap_or_default().trim_end();
    let shown = match first.char_indices().nth(80) {
        Some((cut, _)) => format!("{}…", &first[..cut]),
        None => first.to_string(),
    };
    let line = file
        .text
        .get(..start)
        .map_or(0, |t| t.matches('\n').count())
        + 1;
    let name = file
        .path
        .file_name()
        .map_or_else(|| file.name.clone(), |n| n.to_string_lossy().into_owned());
    format!(
        "{} `{}`\n\n```scn\n{shown}\n```\ndeclared at {name}:{line}",
        symbol.kind.what(),
        symbol.name
    )
}

/// How an editor shows a name of `kind` in a completion list.
pub fn completion_kind(kind: SymbolKind) -> CompletionItemKind {
    match kind {
        SymbolKind::Constant => CompletionItemKind::CONSTANT,
        SymbolKind::Camera | SymbolKind::Light | SymbolKind::Group => CompletionItemKind::VARIABLE,
        SymbolKind::Material | SymbolKind::Texture | SymbolKind::Mesh => CompletionItemKind::VALUE,
    }
}
