//! Language server: the symbol index of one scene and its includes. Every declared name
//! (constants, materials, textures, meshes, lights, cameras, groups) with its kind and
//! declaration, every place it is written (declaration or reference) across the included files,
//! and the words around them (keys, kinds, functions) for colouring.
//!
//! It is built from the parse alone ([`crate::compile::parse_files`]: includes expanded as the
//! compiler expands them), so it works on a document with errors as far as the parse goes; names
//! resolve as the checker resolves them (`resolve.rs`). Queries take byte
//! offsets and [`Span`]s; the LSP layers convert with [`super::position`].
//!
//! ```text
//! let red = #f00                       Constant `red`   declared 4..7
//! material m = phong { diffuse red }   Material `m`,    reference to `red` at 29..32
//! object ball { material m }           reference to Mesh `ball`, to Material `m`
//! ```

use std::path::Path;

use crate::assets::Loader;
use crate::source::{FileId, SourceMap, Span};
use crate::syntax::Stmt;

use super::blocks::BlockKind;

/// The kinds of declared name; each kind is its own name space, as in the checker.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SymbolKind {
    /// `let NAME = ...`.
    Constant,
    /// `material NAME = ...`.
    Material,
    /// `texture NAME = ...`.
    Texture,
    /// `mesh NAME = ...`.
    Mesh,
    /// `light NAME = ...`.
    Light,
    /// `camera NAME { ... }`.
    Camera,
    /// `group NAME { ... }`.
    Group,
}

impl SymbolKind {
    /// Every kind.
    pub const ALL: [SymbolKind; 7] = [
        SymbolKind::Constant,
        SymbolKind::Material,
        SymbolKind::Texture,
        SymbolKind::Mesh,
        SymbolKind::Light,
        SymbolKind::Camera,
        SymbolKind::Group,
    ];

    /// The kind in words, as diagnostics say it ("constant", "material").
    pub fn what(self) -> &'static str {
        match self {
            SymbolKind::Constant => "constant",
            SymbolKind::Material => "material",
            SymbolKind::Texture => "texture",
            SymbolKind::Mesh => "mesh",
            SymbolKind::Light => "light",
            SymbolKind::Camera => "camera",
            SymbolKind::Group => "group",
        }
    }
}

/// Index of a symbol in its [`SymbolIndex`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SymbolId(pub usize);

/// One declared name (its first declaration when declared twice, as the checker keeps it).
#[derive(Debug, Clone, PartialEq)]
pub struct Symbol {
    /// The name.
    pub name: String,
    /// Its name space.
    pub kind: SymbolKind,
    /// Where the name is written in its declaration.
    pub name_span: Span,
    /// The whole declaring statement.
    pub span: Span,
    /// What follows `=` (`phong`, `obj`), when there is one.
    pub detail: Option<String>,
}

/// One place a symbol's name is written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Occurrence {
    /// The symbol written.
    pub symbol: SymbolId,
    /// Where.
    pub span: Span,
    /// Whether this declares the name (its declaration, or a duplicate one the checker rejects).
    pub declaration: bool,
    /// The block the name is written in as a value, when it is one: a new name that is one of
    /// its keys would be read as a key there.
    pub block: Option<BlockKind>,
}

/// What a word that is no declared name is, where the index knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// A property key of its block (`diffuse`, `fov`).
    Key,
    /// The kind after `=` in a declaration (`phong`, `sphere`, `obj`).
    Kind,
    /// A built-in function called (`rgb(...)`).
    Function,
    /// A word value of the language (`true`, `repeat`, `filmic`) or the constant `frame`.
    Word,
}

/// A word the index classified, and where it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mark {
    /// Where the word is written.
    pub span: Span,
    /// What it is.
    pub role: Role,
}

/// A block and its kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockSpan {
    /// What the block belongs to.
    pub kind: BlockKind,
    /// From `{` to `}`.
    pub span: Span,
}

/// Every declared name of one scene (a file and its includes) and every use of it.
#[derive(Debug, Default)]
pub struct SymbolIndex {
    pub(super) sources: SourceMap,
    pub(super) symbols: Vec<Symbol>,
    /// Sorted by (file, start).
    pub(super) occurrences: Vec<Occurrence>,
    /// Sorted by (file, start).
    pub(super) marks: Vec<Mark>,
    /// In the order met (an enclosing block before the blocks inside it).
    pub(super) blocks: Vec<BlockSpan>,
}

impl SymbolIndex {
    /// Indexes the scene file at `path` (file 0) and its includes, read through `loader`.
    pub fn build(path: &Path, loader: &dyn Loader) -> SymbolIndex {
        let (sources, statements) = crate::compile::parse_files(path, loader);
        SymbolIndex::from_statements(sources, &statements)
    }

    /// Indexes parsed statements whose spans point into `sources`.
    pub fn from_statements(sources: SourceMap, statements: &[Stmt]) -> SymbolIndex {
        let mut index = super::resolve::index(statements);
        index.sources = sources;
        index
    }

    /// The files indexed (the root is file 0).
    pub fn sources(&self) -> &SourceMap {
        &self.sources
    }

    /// The indexed file read from `path`, if it is one.
    pub fn file(&self, path: &Path) -> Option<FileId> {
        self.sources.find(path)
    }

    /// Every symbol, in declaration order.
    pub fn symbols(&self) -> impl Iterator<Item = (SymbolId, &Symbol)> {
        self.symbols
            .iter()
            .enumerate()
            .map(|(i, s)| (SymbolId(i), s))
    }

    /// A symbol by id.
    pub fn symbol(&self, id: SymbolId) -> &Symbol {
        &self.symbols[id.0]
    }

    /// The symbols of one kind, in declaration order (what a key of that kind can name).
    pub fn declarations(&self, kind: SymbolKind) -> impl Iterator<Item = (SymbolId, &Symbol)> {
        self.symbols().filter(move |(_, s)| s.kind == kind)
    }

    /// The symbol `name` of `kind`, if declared.
    pub fn lookup(&self, kind: SymbolKind, name: &str) -> Option<SymbolId> {
        self.declarations(kind)
            .find(|(_, s)| s.name == name)
            .map(|(id, _)| id)
    }

    /// The occurrence of a name at byte `offset` of `file` (its end counts, so a cursor just
    /// after a name finds it).
    pub fn at(&self, file: FileId, offset: usize) -> Option<&Occurrence> {
        let found = find_at(&self.occurrences, |o| o.span, file, offset)?;
        Some(&self.occurrences[found])
    }

    /// The classified word at byte `offset` of `file`, if any.
    pub fn mark_at(&self, file: FileId, offset: usize) -> Option<&Mark> {
        let found = find_at(&self.marks, |m| m.span, file, offset)?;
        Some(&self.marks[found])
    }

    /// Every place `id` is written, its declarations included (flagged), in file order.
    pub fn occurrences(&self, id: SymbolId) -> impl Iterator<Item = &Occurrence> {
        self.occurrences.iter().filter(move |o| o.symbol == id)
    }

    /// The references to `id` (declarations left out), in file order.
    pub fn references(&self, id: SymbolId) -> impl Iterator<Item = &Occurrence> {
        self.occurrences(id).filter(|o| !o.declaration)
    }

    /// Every occurrence in `file`, in order.
    pub fn occurrences_in(&self, file: FileId) -> impl Iterator<Item = &Occurrence> {
        self.occurrences.iter().filter(move |o| o.span.file == file)
    }

    /// Every classified word in `file`, in order.
    pub fn marks_in(&self, file: FileId) -> impl Iterator<Item = &Mark> {
        self.marks.iter().filter(move |m| m.span.file == file)
    }

    /// The innermost block of `file` containing byte `offset` (strictly inside its braces).
    pub fn block_at(&self, file: FileId, offset: usize) -> Option<BlockSpan> {
        self.blocks
            .iter()
            .filter(|b| {
                b.span.file == file
                    && (b.span.start as usize) < offset
                    && offset < b.span.end as usize
            })
            .min_by_key(|b| b.span.len())
            .copied()
    }
}

/// The item of `items` (sorted by file and start, not overlapping) whose span contains
/// `offset`, ends included.
fn find_at<T>(
    items: &[T],
    span: impl Fn(&T) -> Span,
    file: FileId,
    offset: usize,
) -> Option<usize> {
    let after = items.partition_point(|t| {
        let s = span(t);
        (s.file, s.start as usize) <= (file, offset)
    });
    let i = after.checked_sub(1)?;
    let s = span(&items[i]);
    (s.file == file && offset <= s.end as usize).then_some(i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::MemLoader;

    const LIB: &str = "scnc 1\nlet white = #fff\ntexture wood = checker { even white }\n\
                       material matte = phong { diffuse wood }\n";
    const MAIN: &str = "scnc 1\ninclude \"lib.scn\"\nlet wide = 40deg\n\
                        camera main { fov wide }\nmesh ball = sphere { radius 1 }\n\
                        group g { object ball { material matte } group inner { } }\n\
                        light l = area { mesh ball  radiance 1 }\nrender { camera main }\n";

    fn index() -> SymbolIndex {
        let mut loader = MemLoader::new();
        loader.insert("/s/lib.scn", LIB.as_bytes());
        loader.insert("/s/main.scn", MAIN.as_bytes());
        SymbolIndex::build(Path::new("/s/main.scn"), &loader)
    }

    fn offset(text: &str, needle: &str) -> usize {
        text.find(needle)
            .unwrap_or_else(|| panic!("{needle:?} in the text"))
    }

    /// The (file, text) of every occurrence of the symbol `kind name`.
    fn written(index: &SymbolIndex, kind: SymbolKind, name: &str) -> Vec<(u32, usize, bool)> {
        let id = index.lookup(kind, name).expect("declared");
        index
            .occurrences(id)
            .map(|o| (o.span.file.0, o.span.start as usize, o.declaration))
            .collect()
    }

    #[test]
    fn declarations_of_every_kind_across_the_include() {
        let index = index();
        let names = |kind| -> Vec<String> {
            index
                .declarations(kind)
                .map(|(_, s)| s.name.clone())
                .collect()
        };
        assert_eq!(names(SymbolKind::Constant), ["white", "wide"]);
        assert_eq!(names(SymbolKind::Texture), ["wood"]);
        assert_eq!(names(SymbolKind::Material), ["matte"]);
        assert_eq!(names(SymbolKind::Mesh), ["ball"]);
        assert_eq!(names(SymbolKind::Light), ["l"]);
        assert_eq!(names(SymbolKind::Camera), ["main"]);
        assert_eq!(names(SymbolKind::Group), ["g", "inner"]);
        let matte = index.lookup(SymbolKind::Material, "matte").expect("matte");
        let symbol = index.symbol(matte);
        assert_eq!(symbol.detail.as_deref(), Some("phong"));
        assert_eq!(
            index.sources().get(symbol.name_span.file).path,
            Path::new("/s/lib.scn")
        );
    }

    #[test]
    fn references_resolve_by_the_key_that_names_them() {
        let index = index();
        // The key `fov` is no reference; its value is the constant.
        assert_eq!(
            written(&index, SymbolKind::Constant, "wide"),
            [
                (0, offset(MAIN, "wide ="), true),
                (0, offset(MAIN, "wide }"), false)
            ]
        );
        assert_eq!(
            written(&index, SymbolKind::Mesh, "ball"),
            [
                (0, offset(MAIN, "ball ="), true),
                (0, offset(MAIN, "ball {"), false),
                (0, offset(MAIN, "ball  radiance"), false)
            ]
        );
        // Across the include: declared in lib.scn (file 1), used in main.scn.
        assert_eq!(
            written(&index, SymbolKind::Material, "matte"),
            [
                (0, offset(MAIN, "matte }"), false),
                (1, offset(LIB, "matte ="), true)
            ]
        );
        assert_eq!(
            written(&index, SymbolKind::Texture, "wood"),
            [
                (1, offset(LIB, "wood ="), true),
                (1, offset(LIB, "wood }"), false)
            ]
        );
        assert_eq!(written(&index, SymbolKind::Camera, "main").len(), 2);
    }

    #[test]
    fn lookup_at_a_position_and_the_words_around() {
        let index = index();
        let at = offset(MAIN, "matte }");
        for cursor in [at, at + 2, at + 5] {
            let o = index.at(FileId(0), cursor).expect("an occurrence");
            assert_eq!(index.symbol(o.symbol).name, "matte");
            assert_eq!(o.block, Some(BlockKind::Object));
        }
        assert!(index.at(FileId(0), at - 2).is_none());
        let key = index
            .mark_at(FileId(0), at - 3)
            .expect("the key `material`");
        assert_eq!(key.role, Role::Key);
        let kind = index
            .mark_at(FileId(0), offset(MAIN, "sphere"))
            .expect("sphere");
        assert_eq!(kind.role, Role::Kind);
        let block = index.block_at(FileId(0), at).expect("inside the object");
        assert_eq!(block.kind, BlockKind::Object);
    }

    #[test]
    fn a_document_with_syntax_errors_keeps_what_parsed() {
        let text = "scnc 1\nlet a = 1\nobject o { material \nlet b = a\n";
        let mut loader = MemLoader::new();
        loader.insert("/s/bad.scn", text.as_bytes());
        let index = SymbolIndex::build(Path::new("/s/bad.scn"), &loader);
        assert_eq!(written(&index, SymbolKind::Constant, "a").len(), 2);
        assert!(index.lookup(SymbolKind::Constant, "b").is_some());
    }

    #[test]
    fn a_duplicate_declares_the_first_symbol_again() {
        let text = "scnc 1\nlet a = 1\nlet a = 2\nlet true = 3\n";
        let mut loader = MemLoader::new();
        loader.insert("/s/d.scn", text.as_bytes());
        let index = SymbolIndex::build(Path::new("/s/d.scn"), &loader);
        assert_eq!(index.symbols().count(), 1);
        let a = written(&index, SymbolKind::Constant, "a");
        assert_eq!(a, [(0, 11, true), (0, 21, true)]);
    }
}
