//! Language server: the scenes a file belongs to, for navigation across includes. A name
//! declared in an included file is used by the files that include it, so the reach of a
//! document is every [`SymbolIndex`] that contains it: the one rooted at the document itself,
//! and those rooted at each open document and each `.scn` file beside it that includes it
//! (directly or not). A symbol is the same across them when its declaration is (same file,
//! same place), and its occurrences are the union, each place once.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use lsp_types::{Location, Position, Range, Url};

use super::blocks::BlockKind;
use super::documents::Documents;
use super::position::LineIndex;
use super::symbols::{Occurrence, SymbolId, SymbolIndex, SymbolKind};
use crate::source::Span;

/// Most `.scn` files beside a document that are indexed to find its includers.
const MAX_SIBLINGS: usize = 64;

/// A symbol the same in every index: its kind and where it is declared.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SymbolKey {
    /// Its kind.
    pub kind: SymbolKind,
    /// The file of its declaration.
    pub path: PathBuf,
    /// The byte offset of its name there.
    pub start: u32,
}

/// One place a symbol is written, with its file.
#[derive(Debug, Clone)]
pub struct Place {
    /// The file.
    pub path: PathBuf,
    /// The file's text (the editor's when open).
    pub text: Arc<str>,
    /// The name's bytes in `text`.
    pub span: Span,
    /// Whether it declares the name.
    pub declaration: bool,
    /// The block it is a value in, if it is one.
    pub block: Option<BlockKind>,
}

impl Place {
    /// The place as an LSP location (`None` when the path makes no URI).
    pub fn location(&self) -> Option<Location> {
        let uri = Url::from_file_path(&self.path).ok()?;
        Some(Location::new(uri, self.range()))
    }

    /// Its range in UTF-16 positions.
    pub fn range(&self) -> Range {
        LineIndex::new(&self.text).range(self.span.start as usize, self.span.end as usize)
    }
}

/// Every index that contains one document.
#[derive(Debug)]
pub struct Workspace {
    path: PathBuf,
    indices: Vec<SymbolIndex>,
}

impl Workspace {
    /// The indices containing the document at `path` (open or on disk).
    pub fn around(documents: &Documents, path: &Path) -> Workspace {
        let loader = documents.loader();
        let mut roots: Vec<PathBuf> = vec![path.to_path_buf()];
        roots.extend(documents.iter().map(|(_, d)| d.path.clone()));
        roots.extend(siblings(path));
        let mut seen = BTreeSet::new();
        let indices = roots
            .into_iter()
            .filter(|root| seen.insert(root.clone()))
            .map(|root| SymbolIndex::build(&root, &loader))
            .filter(|index| index.file(path).is_some())
            .collect();
        Workspace {
            path: path.to_path_buf(),
            indices,
        }
    }

    /// The symbol whose name is written at `position` of the document, and where.
    pub fn at(&self, position: Position) -> Option<(SymbolKey, Place)> {
        let index = self.indices.first()?;
        let file = index.file(&self.path)?;
        let text = index.sources().get(file).text.clone();
        let offset = LineIndex::new(&text).offset(position);
        let found = index.at(file, offset)?;
        let place = Place {
            path: self.path.clone(),
            text,
            span: found.span,
            declaration: found.declaration,
            block: found.block,
        };
        Some((key(index, found.symbol), place))
    }

    /// The symbol `key`'s name, and every place it is written in any index, each once, in
    /// path then text order.
    pub fn places(&self, key: &SymbolKey) -> Vec<Place> {
        let mut places: Vec<Place> = Vec::new();
        for index in &self.indices {
            let Some(id) = find(index, key) else { continue };
            for o in index.occurrences(id) {
                places.push(place(index, o));
            }
        }
        places.sort_by(|a, b| (&a.path, a.span.start).cmp(&(&b.path, b.span.start)));
        places.dedup_by(|a, b| a.path == b.path && a.span.start == b.span.start);
        places
    }

    /// The declaration of `key`.
    pub fn declaration(&self, key: &SymbolKey) -> Option<Place> {
        self.indices.iter().find_map(|index| {
            let id = find(index, key)?;
            let symbol = index.symbol(id);
            let file = index.sources().get(symbol.name_span.file);
            Some(Place {
                path: file.path.clone(),
                text: file.text.clone(),
                span: symbol.name_span,
                declaration: true,
                block: None,
            })
        })
    }

    /// The declaration of the symbol `name` of `kind`, if any index has one.
    pub fn declared(&self, kind: SymbolKind, name: &str) -> Option<Place> {
        self.indices.iter().find_map(|index| {
            let id = index.lookup(kind, name)?;
            self.declaration(&key(index, id))
        })
    }

    /// Every index (the document's own first).
    pub fn indices(&self) -> &[SymbolIndex] {
        &self.indices
    }
}

/// The `.scn` files beside `path` (not itself), sorted, at most [`MAX_SIBLINGS`].
fn siblings(path: &Path) -> Vec<PathBuf> {
    let Some(dir) = path.parent() else {
        return Vec::new();
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "scn") && p != path)
        .collect();
    found.sort();
    found.truncate(MAX_SIBLINGS);
    found
}

fn key(index: &SymbolIndex, id: SymbolId) -> SymbolKey {
    let symbol = index.symbol(id);
    SymbolKey {
        kind: symbol.kind,
        path: index.sources().get(symbol.name_span.file).path.clone(),
        start: symbol.name_span.start,
    }
}

/// The symbol of `index` that is `key`.
fn find(index: &SymbolIndex, key: &SymbolKey) -> Option<SymbolId> {
    let file = index.file(&key.path)?;
    index
        .declarations(key.kind)
        .find(|(_, s)| s.name_span.file == file && s.name_span.start == key.start)
        .map(|(id, _)| id)
}

fn place(index: &SymbolIndex, o: &Occurrence) -> Place {
    let file = index.sources().get(o.span.file);
    Place {
        path: file.path.clone(),
        text: file.text.clone(),
        span: o.span,
        declaration: o.declaration,
        block: o.block,
    }
}
