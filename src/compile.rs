//! The front-end driver: a `.scn` file (and its includes) → `ir::SceneDesc` + diagnostics.
//!
//! Reads every file through the [`Loader`] (so `scnc watch` sees includes), rejects binary and
//! non-UTF-8 input, parses each file, expands `include "file.scn"` in place (paths relative to
//! the including file; each file at most once; cycles reported with the include chain), checks
//! that every file starts with `scnc 1`, then runs `check::check` over all statements.
//!
//! [`compile`] is the stage entry of the pipeline: it returns the [`Staged`] shape of every
//! stage, the files it read going into a [`SourceMap`] the caller keeps for reporting (every
//! later stage's spans point into it). [`compile_file`] and [`compile_source`] bundle the two
//! into [`Compiled`] for callers that look at one compile on its own (tests, benches).
//! [`Incremental`] gives the same result again after an edit, parsing and checking only what
//! changed when it can (`scnc watch`, `scnc lsp`; see `compile/incremental.rs`).

use std::path::{Component, Path, PathBuf};

use crate::assets::Loader;
use crate::check;
use crate::diag::{Code, Diagnostic, Staged};
use crate::ir;
use crate::source::{FileId, SourceMap, Span};
use crate::syntax::{self, ExprKind, Stmt};

mod broken;
mod dependents;
#[cfg(test)]
mod early_tests;
mod edit;
mod files;
mod incremental;

pub use incremental::{Incremental, Reuse};

/// The only language version.
pub const VERSION: f64 = 1.0;
/// Deepest chain of nested includes.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// Everything one compile produced: [`compile`]'s result and its sources, side by side.
/// `scene` is `None` when any diagnostic is an error.
#[derive(Debug)]
pub struct Compiled {
    /// The scene file and its includes; every span of `diagnostics` points into it.
    pub sources: SourceMap,
    /// The checked scene, when nothing is an error.
    pub scene: Option<ir::SceneDesc>,
    /// Every error and warning, in reading order.
    pub diagnostics: Vec<Diagnostic>,
}

impl Compiled {
    /// Whether any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// The compile as a pipeline stage: its sources, and its [`Staged`] result.
    pub fn into_staged(self) -> (SourceMap, Staged<ir::SceneDesc>) {
        (self.sources, Staged::new(self.scene, self.diagnostics))
    }
}

/// Stage entry: compiles the scene file at `path`, reading it and its includes through
/// `loader`. `sources` receives every file read (it is replaced, so pass an empty map).
pub fn compile(path: &Path, loader: &dyn Loader, sources: &mut SourceMap) -> Staged<ir::SceneDesc> {
    compile_with(path, loader, sources, &Overrides::default())
}

/// What the command line sets in the scene's language.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overrides {
    /// The predefined constant `frame` (`--frame F`).
    pub frame: f64,
    /// `--define NAME=VALUE`, in order: each `VALUE` replaces `let NAME`'s expression.
    pub defines: Vec<(String, String)>,
}

/// [`compile`] with the command line's [`Overrides`]. Each define's value is parsed as the
/// source file `--define NAME` (`let NAME = VALUE`), so its diagnostics point into it.
pub fn compile_with(
    path: &Path,
    loader: &dyn Loader,
    sources: &mut SourceMap,
    overrides: &Overrides,
) -> Staged<ir::SceneDesc> {
    let d = Driver::checking(loader, overrides);
    let (read, staged) = d.compile_root(path).into_staged();
    *sources = read;
    staged
}

/// Compiles the scene file at `path`, reading it and its includes through `loader`.
pub fn compile_file(path: &Path, loader: &dyn Loader) -> Compiled {
    Driver::checking(loader, &Overrides::default()).compile_root(path)
}

/// The statements of the scene file at `path` and of its includes, expanded as [`compile`]
/// expands them (paths relative to the including file, each file once, cycles cut), parsed but
/// not checked, with the files read. A statement lost to a syntax error is missing; everything
/// else is there. The language server indexes declared names and their uses in these.
pub fn parse_files(path: &Path, loader: &dyn Loader) -> (SourceMap, Vec<Stmt>) {
    let mut d = Driver::new(loader);
    if let Ok(bytes) = loader.read(path) {
        let name = path.display().to_string();
        d.add_root(path, &name, &bytes);
    }
    (d.sources, d.statements)
}

impl Driver<'_> {
    /// Reads the root file at `path` (a diagnostic if it cannot be) and compiles it.
    fn compile_root(mut self, path: &Path) -> Compiled {
        match self.loader.read(path) {
            Ok(bytes) => {
                let name = path.display().to_string();
                self.add_root(path, &name, &bytes);
            }
            Err(e) => self.diags.push(
                Diagnostic::error(Code::IoRead, format!("cannot read {}: {e}", path.display()))
                    .help("check the path"),
            ),
        }
        for (name, value) in std::mem::take(&mut self.pending_defines) {
            self.add_define(&name, &value);
        }
        self.finish()
    }
}

/// Compiles `text` as if it were the file `name` (includes resolve relative to `name`'s
/// directory through `loader`).
pub fn compile_source(name: &str, text: &str, loader: &dyn Loader) -> Compiled {
    let mut d = Driver::checking(loader, &Overrides::default());
    d.add_root(Path::new(name), name, text.as_bytes());
    d.finish()
}

struct Driver<'l> {
    loader: &'l dyn Loader,
    sources: SourceMap,
    diags: Vec<Diagnostic>,
    statements: Vec<Stmt>,
    /// Files on the include stack: (normalised path, span of the include that entered it).
    stack: Vec<(PathBuf, Option<Span>)>,
    /// The predefined constant `frame`.
    frame: f64,
    /// `--define`s not parsed yet (after the root file, which must be file 0).
    pending_defines: Vec<(String, String)>,
    /// `--define`s parsed: the name and the value's expression.
    defines: Vec<(String, syntax::Expr)>,
    /// Top-level statements are checked as they are parsed (`check::PreCheck`) while this is
    /// set: only until a file has a syntax error or any other diagnostic, which makes the
    /// driver start over without it.
    pre: Option<check::PreCheck>,
    /// The pre-check gave up part-way (statements it saw are lost): the compile starts over.
    aborted: bool,
    /// Per file id read, the file name of the include that read it (`None` for the root), for
    /// the incremental compile's [`crate::source::ReadingOrder`].
    included_at: Vec<Option<Span>>,
}

impl<'l> Driver<'l> {
    fn new(loader: &'l dyn Loader) -> Driver<'l> {
        Driver {
            loader,
            sources: SourceMap::new(),
            diags: Vec::new(),
            statements: Vec::new(),
            stack: Vec::new(),
            frame: 0.0,
            pending_defines: Vec::new(),
            defines: Vec::new(),
            pre: None,
            aborted: false,
            included_at: Vec::new(),
        }
    }

    /// A driver that checks top-level statements while parsing (a compile, not an index),
    /// with the command line's `overrides` (the `--define`s are parsed after the root file).
    fn checking(loader: &'l dyn Loader, overrides: &Overrides) -> Driver<'l> {
        let mut d = Driver::new(loader);
        d.frame = overrides.frame;
        d.pending_defines.clone_from(&overrides.defines);
        // The pre-check needs the defines' values before the root file, which must be file 0:
        // it gets them parsed on their own, under a file id no source map holds (it evaluates
        // them, which reads no source text, and never reports: a diagnostic stops its `let`s).
        let mut defines = Vec::new();
        let mut defines_ok = true;
        for (name, value) in &overrides.defines {
            let text = define_text(name, value);
            let (parsed, diags) = parse_define(FileId(u32::MAX), &text);
            defines.extend(parsed);
            defines_ok &= diags.is_empty();
        }
        d.pre = Some(check::PreCheck::new(overrides.frame, defines, defines_ok));
        d
    }

    /// Parses `--define NAME=VALUE` as the source `let NAME = VALUE`.
    fn add_define(&mut self, name: &str, value: &str) {
        let label = format!("--define {name}");
        let id = self.sources.add(
            PathBuf::from(&label),
            &label,
            std::sync::Arc::<str>::from(define_text(name, value)),
        );
        let text = self.sources.get(id).text.clone();
        let (defines, diags) = parse_define(id, &text);
        self.diags.extend(diags);
        self.defines.extend(defines);
    }

    fn add_root(&mut self, path: &Path, name: &str, bytes: &[u8]) {
        self.add_file(normalise(path), name, bytes, None);
        if self.pre.is_some() && (self.aborted || !self.diags.is_empty()) {
            // Some file had a diagnostic: parse everything again the plain way, which reports
            // every diagnostic in its usual order and keeps every statement for the check.
            let mut again = Driver::new(self.loader);
            again.frame = self.frame;
            again.pending_defines = std::mem::take(&mut self.pending_defines);
            again.add_file(normalise(path), name, bytes, None);
            *self = again;
        }
    }

    /// Parses the file `id` statement by statement, handing each to the pre-check and
    /// expanding includes as they come; sets `aborted` on any diagnostic.
    fn add_streamed(&mut self, id: FileId, text: &str) {
        if let Some(pre) = &mut self.pre {
            let count = |word: &[u8]| memchr::memmem::find_iter(text.as_bytes(), word).count();
            let [materials, meshes, lets] = count_line_starts(text, [b"material", b"mesh", b"let"]);
            pre.reserve(count(b"object"), lets, [materials, meshes, count(b"group")]);
        }
        let mut first = true;
        let ok = syntax::parse_each(id, text, &mut |stmt| {
            if self.aborted {
                return;
            }
            if first {
                first = false;
                self.check_version(id, text, std::slice::from_ref(&stmt));
            } else if matches!(stmt, Stmt::Version { .. }) {
                self.aborted = true;
            }
            if let Stmt::Include { path, .. } = &stmt {
                self.include(id, path);
            }
            let kept = match &mut self.pre {
                Some(pre) => pre.offer(&self.sources, stmt),
                None => Some(stmt),
            };
            self.statements.extend(kept);
            self.aborted |= !self.diags.is_empty();
        });
        if first {
            self.check_version(id, text, &[]);
        }
        self.aborted |= !ok || !self.diags.is_empty();
    }

    /// Decodes, parses and expands one file. `from` is the include literal that named it.
    fn add_file(&mut self, path: PathBuf, name: &str, bytes: &[u8], from: Option<Span>) {
        let text = match decode(bytes) {
            Ok(t) => t,
            Err(why) => {
                let mut d = Diagnostic::error(
                    Code::SourceNotText,
                    format!("{name} is not a text file: {why}"),
                )
                .help("scene files are UTF-8 text; check that you named the .scn file");
                if let Some(span) = from {
                    d = d.at(span, "included here");
                }
                self.diags.push(d);
                return;
            }
        };
        // One copy of the text, straight into the source map.
        let id = self
            .sources
            .add(path.clone(), name, std::sync::Arc::<str>::from(text));
        let text = self.sources.get(id).text.clone();
        self.included_at.resize(id.0 as usize, None);
        self.included_at.push(from);
        if text.trim().is_empty() {
            let span = Span::new(id, 0, 0);
            self.diags.push(
                Diagnostic::error(Code::SyntaxEmpty, "empty scene: expected `scnc 1`")
                    .at(span, "file is empty")
                    .help("start the file with the version header `scnc 1`"),
            );
            return;
        }
        if self.pre.is_some() {
            self.stack.push((path, from));
            self.add_streamed(id, &text);
            self.stack.pop();
            return;
        }
        let (file, diags) = syntax::parse(id, &text).into_parts();
        self.diags.extend(diags);
        let file = file.unwrap_or_default();
        self.check_version(id, &text, &file.statements);
        self.stack.push((path, from));
        let includes = file
            .statements
            .iter()
            .any(|s| matches!(s, Stmt::Include { .. }));
        if self.statements.is_empty() && !includes {
            // The usual root file without includes: its statements move over, never two
            // arrays of them at once.
            self.statements = file.statements;
            self.stack.pop();
            return;
        }
        self.statements.reserve(file.statements.len());
        for stmt in file.statements {
            if let Stmt::Include { path, .. } = &stmt {
                self.include(id, path);
            }
            self.statements.push(stmt);
        }
        self.stack.pop();
    }

    fn check_version(&mut self, id: FileId, text: &str, stmts: &[Stmt]) {
        let first_offset = text.len() - text.trim_start().len();
        match stmts.first() {
            Some(Stmt::Version { value, .. }) => match value.kind {
                ExprKind::Number {
                    value: v,
                    suffix: None,
                } if v == VERSION => {}
                _ => self.diags.push(
                    Diagnostic::error(
                        Code::SyntaxUnsupportedVersion,
                        format!("unsupported version `{}`", self.sources.snippet(value.span)),
                    )
                    .at(value.span, "this version")
                    .help("this compiler reads `scnc 1`"),
                ),
            },
            first => {
                // Only blame the header if the file's first statement parsed (or nothing did).
                let starts_ok = first.is_none_or(|s| s.span().start as usize == first_offset);
                if starts_ok {
                    let end = text[first_offset..]
                        .find(char::is_whitespace)
                        .map_or(text.len(), |n| first_offset + n);
                    self.diags.push(
                        Diagnostic::error(
                            Code::SyntaxMissingVersion,
                            "the file does not start with the version header `scnc 1`",
                        )
                        .at(
                            Span::new(id, first_offset, end),
                            "expected `scnc 1` before this",
                        )
                        .help("add `scnc 1` as the first line"),
                    );
                }
            }
        }
        for s in stmts.iter().skip(1) {
            if let Stmt::Version { span, .. } = s {
                self.diags.push(
                    Diagnostic::error(
                        Code::SyntaxMisplacedVersion,
                        "`scnc` header after the start of the file",
                    )
                    .at(*span, "only allowed as the first statement"),
                );
            }
        }
    }

    fn include(&mut self, from_file: FileId, path_expr: &syntax::Expr) {
        let span = path_expr.span;
        let ExprKind::Str(written) = &path_expr.kind else {
            self.diags.push(
                Diagnostic::error(Code::IncludeNotAString, "`include` takes a file name")
                    .at(span, "expected a string")
                    .help("write `include \"common.scn\"`"),
            );
            return;
        };
        let dir = self
            .sources
            .get(from_file)
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let path = normalise(&dir.join(written));
        if let Some(pos) = self.stack.iter().position(|(p, _)| *p == path) {
            let mut d = Diagnostic::error(
                Code::IncludeCycle,
                format!("include cycle: `{written}` includes itself"),
            )
            .at(span, "this include closes the cycle");
            for (_, via) in self.stack[pos + 1..].iter().rev() {
                if let Some(via) = via {
                    d = d.also(*via, "included from here");
                }
            }
            self.diags
                .push(d.help("remove one of the includes in the chain"));
            return;
        }
        if self.sources.find(&path).is_some() {
            // Already included elsewhere: each file is read once.
            return;
        }
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            self.diags.push(
                Diagnostic::error(
                    Code::IncludeTooDeep,
                    format!("includes nested deeper than {MAX_INCLUDE_DEPTH}"),
                )
                .at(span, "here"),
            );
            return;
        }
        match self.loader.read(&path) {
            Ok(bytes) => {
                let name = path.display().to_string();
                self.add_file(path, &name, &bytes, Some(span));
            }
            Err(e) => self.diags.push(
                Diagnostic::error(
                    Code::IncludeNotFound,
                    format!("cannot read included file `{written}`"),
                )
                .at(
                    span,
                    match e.kind() {
                        std::io::ErrorKind::NotFound => {
                            format!("{} does not exist", path.display())
                        }
                        _ => format!("{}: {e}", path.display()),
                    },
                )
                .help("include paths are relative to the file that contains the include"),
            ),
        }
    }

    fn finish(self) -> Compiled {
        let Driver {
            sources,
            mut diags,
            statements,
            frame: self_frame,
            defines,
            pre,
            ..
        } = self;
        let placed = pre.map(check::PreCheck::into_placed).unwrap_or_default();
        let parse_failed = diags.iter().any(Diagnostic::is_error);
        let scene = if sources.files().next().is_some() {
            let (scene, check_diags) =
                check::check_placed(&statements, placed, &sources, self_frame, defines)
                    .into_parts();
            // When parsing failed, statements are missing: suppress checker errors that only
            // say something is missing, unknown or unused, which would be noise.
            diags.extend(
                check_diags
                    .into_iter()
                    .filter(|d| !parse_failed || !is_cascade(d.code)),
            );
            scene
        } else {
            None
        };
        reading_order(&mut diags);
        let failed = diags.iter().any(Diagnostic::is_error);
        Compiled {
            sources,
            scene: scene.filter(|_| !failed),
            diagnostics: diags,
        }
    }
}

/// How many times each of `words` follows a newline in `text` (as many as the matches of
/// `"\n" + word`), counted in one pass over the lines instead of one search per word.
fn count_line_starts<const N: usize>(text: &str, words: [&[u8]; N]) -> [usize; N] {
    let bytes = text.as_bytes();
    let mut counts = [0; N];
    for newline in memchr::memchr_iter(b'\n', bytes) {
        let line = &bytes[newline + 1..];
        for (count, word) in counts.iter_mut().zip(words) {
            *count += usize::from(line.starts_with(word));
        }
    }
    counts
}

/// The source a `--define NAME=VALUE` is parsed as.
fn define_text(name: &str, value: &str) -> String {
    format!("scnc 1\nlet {name} = {value}\n")
}

/// The `let`s of a `--define`'s source `text` (file `id`): each name with its value, and the
/// parse's diagnostics.
fn parse_define(id: FileId, text: &str) -> (Vec<(String, syntax::Expr)>, Vec<Diagnostic>) {
    let (file, diags) = syntax::parse(id, text).into_parts();
    let lets = file.into_iter().flat_map(|f| f.statements);
    let defines = lets
        .filter_map(|stmt| match stmt {
            Stmt::Let { name, value, .. } => Some((name.name.as_str().to_owned(), value)),
            _ => None,
        })
        .collect();
    (defines, diags)
}

/// Sorts diagnostics into reading order: by file, then position; those without a place last
/// (stable: the order they were found in among equals).
fn reading_order(diags: &mut [Diagnostic]) {
    diags.sort_by_key(|d| {
        d.primary
            .as_ref()
            .map_or((u32::MAX, u32::MAX), |l| (l.span.file.0, l.span.start))
    });
}

/// Checker codes that are only consequences of statements lost to syntax errors.
fn is_cascade(code: Code) -> bool {
    matches!(
        code,
        Code::CheckNoCamera
            | Code::CheckUnused
            | Code::CheckUnknownMaterial
            | Code::CheckUnknownMesh
            | Code::CheckUnknownTexture
            | Code::CheckUnknownCamera
            | Code::CheckUnknownName
    )
}

/// UTF-8 text without NUL bytes, or why not.
fn decode(bytes: &[u8]) -> Result<&str, String> {
    // memchr's search, not `contains`: a fifth of the time on an 8.8 MB scene (every edit in
    // `scnc watch` decodes the whole file).
    if memchr::memchr(0, bytes).is_some() {
        return Err("it contains NUL bytes (binary data)".into());
    }
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.strip_prefix('\u{feff}').unwrap_or(s)),
        Err(e) => Err(format!("invalid UTF-8 at byte {}", e.valid_up_to())),
    }
}

/// Removes `.` and resolves `..` lexically, so one file reached two ways is one path.
fn normalise(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}
