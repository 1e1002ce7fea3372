//! The front end, incrementally: [`Incremental::compile`] gives exactly what [`super::compile_with`]
//! gives (the same IR, the same diagnostics with the same spans, codes and messages, in the same
//! order), parsing and checking again only what an edit changed when it can.
//!
//! It keeps the last compile's text, its top-level statements' byte ranges and the checker's
//! [`CheckMemo`]. After an edit of the scene file it parses only the statements around the
//! edited bytes ([`super::edit`]) and, when every statement that changed is a top-level
//! `object`, re-checks those alone ([`CheckMemo::recheck`]) and moves every other span by the
//! edit. When the changed statements are `let`s, `material`s, `mesh`es (an `obj` one with
//! material overrides too), `texture`s and `object`s, one for one and each keeping its name, it re-checks them and the statements that
//! name a constant whose value changed ([`CheckMemo::recheck_decls`], which finds them through
//! [`super::dependents`]). An edit of `group`s (and `object`s) that keeps the groups' names is
//! checked as an edit of objects is ([`CheckMemo::recheck_placements`]); a `material`, `mesh`
//! or `texture` renamed is checked with what names either name and what has an unknown-name
//! diagnostic of its kind (in [`CheckMemo::recheck_decls`]), and so is a `let` renamed, with
//! what names either name or has an unknown-name diagnostic. `let`s added or removed that nothing else names, in a scene without
//! a diagnostic, are checked alone ([`CheckMemo::add_or_remove_lets`]); so are the
//! settings edited, renamed, added or removed (every camera, light and render block lowered
//! again together: [`CheckMemo::recheck_settings`]), and `material`s,
//! `mesh`es and `texture`s added (a pasted block, `object`s with them) or removed (what names
//! them checked again; [`CheckMemo::add_or_remove_decl`]); the version header edited alone
//! (still `scnc 1`) only moves the spans; a second declaration of a `let`, `material`, `mesh`
//! or `texture` name edited, added or removed alone only gives or takes its duplicate-name
//! error ([`CheckMemo::recheck_redeclared`]). An edit that breaks the
//! syntax gets the full compile's diagnostics from the memo of the last text that parsed
//! ([`super::broken`]), which stays for the edit that fixes it (diffed against that text). Anything
//! else is a full compile, which is always correct: a file-level diagnostic (an include that
//! cannot be read or closes a cycle), an include added, removed or pointed at another file
//! but as `include_edit` takes it (its file's statements added or removed as a block, the
//! later files' ids renumbered when it is not read last (`file_ids`); an include of a file
//! read before it, which reads nothing; a retarget as a removal and an addition), a syntax
//! error in a scene with includes that loses a declaration or breaks two files (a syntax error
//! in one file of several is answered from that file's statements, seventh session) or one
//! [`super::broken`] declines, a `let` or `group` added or removed among declarations, an edit
//! of a light, a camera or the render block that gives or takes away a diagnostic, or made
//! while the scene has an error (or of a constant one of them names), a `let` that fails (or
//! failed) while another error stands, and any edit where a kept span would reach into the
//! edited bytes. An edit that makes a mesh or material used or unused, or a
//! declaration fail to lower or lower again, compacts the IR's indices again from the memo
//! (`check::recheck::compact`). `scnc watch` and `scnc lsp` compile through it;
//! `tests/incremental.rs` replays seeded edits and compares every result with a fresh compile.
//!
//! A scene with includes (2026-11-26, sixth session) keeps one memo over every file read: the
//! statements in the order the check reads them (an included file's where its include stands),
//! each with its file ([`super::files`]). Every included file is read again through the loader
//! (so `scnc watch` records it); each one that changed is an edit of its own statements, mapped
//! to the list's indices, its spans alone moving; the include statements' places move with
//! their file's edits ([`crate::source::ReadingOrder`], which the re-check asks where the full
//! check relies on statement order).

use std::path::Path;
use std::sync::Arc;

use super::broken;
use super::dependents;

mod file_ids;
mod include_edit;
use super::edit::{self, Region};
use super::files;
use super::{decode, reading_order, Driver, Overrides};
use crate::assets::Loader;
use crate::check::{check_tracked, CheckMemo, Placed, PreCheck};
use crate::diag::{Diagnostic, Staged};
use crate::ir;
use crate::source::{FileId, ReadingOrder, SourceMap};
use crate::syntax::{self, Stmt};

/// How the last [`Incremental::compile`] went.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Reuse {
    /// Parsed and checked in full (the first compile, or an edit the fast path declines).
    #[default]
    Full,
    /// The text was the same: the last result again.
    Unchanged,
    /// Only the edited statements were parsed, and only they and what names a changed constant
    /// checked again.
    Statements {
        /// Statements parsed again (besides those found to name a changed constant).
        parsed: usize,
        /// Statements checked again.
        checked: usize,
    },
}

/// A front end that remembers its last compile of one scene file.
pub struct Incremental {
    overrides: Overrides,
    memo: Option<Memo>,
    /// How the last compile went.
    pub reuse: Reuse,
}

/// What a full compile left for the next edit.
struct Memo {
    /// The path compiled, as given.
    path: std::path::PathBuf,
    /// Its sources: the scene file (file 0), the files it includes, and the `--define` files.
    sources: SourceMap,
    /// How many of `sources`' files are scene files (the root and its includes, first).
    scene_files: usize,
    /// The byte range of every top-level statement, in the order the check reads them (an
    /// included file's where its include stands).
    spans: Vec<(u32, u32)>,
    /// The file of each statement of `spans`; empty when the scene is one file.
    files: Vec<FileId>,
    check: CheckMemo,
    /// Whether no line inside a statement starts where the error recovery would cut a chunk
    /// ([`broken::no_inner_resync`]); found when first needed.
    chunks_whole: Option<bool>,
    /// The last text compiled, when it had a syntax error that the memo answered (the memo
    /// itself stays that of the last text that parsed): its sources and diagnostics.
    broken: Option<(SourceMap, Vec<Diagnostic>)>,
}

impl Incremental {
    /// A front end compiling with `overrides` (`--frame`, `--define`).
    pub fn new(overrides: Overrides) -> Incremental {
        Incremental {
            overrides,
            memo: None,
            reuse: Reuse::Full,
        }
    }

    /// [`super::compile_with`] of `path`: the same result, incrementally when the last compile
    /// was of the same path and the edit allows it. The scene is shared with the memo (one
    /// copy, not two, while the caller holds it); dropping it before the next edit spares that
    /// edit a copy of the scene.
    pub fn compile(
        &mut self,
        path: &Path,
        loader: &dyn Loader,
        sources: &mut SourceMap,
    ) -> Staged<Arc<ir::SceneDesc>> {
        let bytes = loader.read(path);
        if let (Some(mut memo), Ok(bytes)) = (self.memo.take(), &bytes) {
            if memo.path == path {
                if let Some(reuse) = memo.update(bytes, loader) {
                    *sources = match &memo.broken {
                        Some((broken, _)) => broken.clone(),
                        None => memo.sources.clone(),
                    };
                    let result = memo.result();
                    self.reuse = reuse;
                    self.memo = Some(memo);
                    return result;
                }
            }
        }
        self.reuse = Reuse::Full;
        let mut d = Driver::checking(loader, &self.overrides);
        let compiled = match bytes {
            Ok(bytes) => {
                d.add_root(path, &path.display().to_string(), &bytes);
                let scene_files = d.sources.files().count();
                for (name, value) in std::mem::take(&mut d.pending_defines) {
                    d.add_define(&name, &value);
                }
                if !d.trackable() {
                    d.finish()
                } else {
                    let memo = d.into_memo(path, scene_files);
                    *sources = memo.sources.clone();
                    let result = memo.result();
                    self.memo = Some(memo);
                    return result;
                }
            }
            // Read again by the driver, which reports why it cannot be.
            Err(_) => d.compile_root(path),
        };
        let (read, staged) = compiled.into_staged();
        *sources = read;
        staged.map(Arc::new)
    }
}

impl Driver<'_> {
    /// Whether the files read allow incremental compiles: no diagnostic of the driver's own (a
    /// syntax error, an include that cannot be read or closes a cycle, a misplaced header).
    fn trackable(&self) -> bool {
        self.diags.is_empty()
    }

    /// The full check, keeping a memo of it; the first `scene_files` files read are the scene's.
    fn into_memo(self, path: &Path, scene_files: usize) -> Memo {
        let Driver {
            sources,
            statements,
            frame,
            defines,
            pre,
            included_at,
            ..
        } = self;
        let placed = pre.map(PreCheck::into_placed).unwrap_or_default();
        let (spans, files) = statement_spans(&statements, &placed, scene_files > 1);
        let mut check = check_tracked(&statements, placed, &sources, frame, defines);
        check.order = ReadingOrder::new(included_at);
        Memo {
            path: path.to_path_buf(),
            sources,
            scene_files,
            spans,
            files,
            check,
            chunks_whole: None,
            broken: None,
        }
    }
}

/// Whether `s` is a version header the driver reports nothing for (`scnc 1`).
fn supported_header(s: &Stmt) -> bool {
    let Stmt::Version { value, .. } = s else {
        return false;
    };
    matches!(value.kind, crate::syntax::ExprKind::Number { value, suffix: None } if value == super::VERSION)
}

/// The byte range of every top-level statement, those `placed` included, in order, and (when
/// `several` files are read) the file of each.
fn statement_spans(
    statements: &[Stmt],
    placed: &Placed,
    several: bool,
) -> (Vec<(u32, u32)>, Vec<FileId>) {
    let mut spans = Vec::with_capacity(statements.len() + placed.len());
    let mut files = Vec::new();
    let mut kept = statements.iter().map(|s| s.span());
    let mut early = placed.places().into_iter().peekable();
    for i in 0..statements.len() + placed.len() {
        let span = match early.next_if(|&(at, _)| at == i) {
            Some((_, span)) => Some(span),
            None => kept.next(),
        };
        spans.extend(span.map(|s| (s.start, s.end)));
        files.extend(span.filter(|_| several).map(|s| s.file));
    }
    (spans, files)
}

impl Memo {
    /// The compile's result: the check's diagnostics in reading order, and the scene unless
    /// one of them is an error.
    fn result(&self) -> Staged<Arc<ir::SceneDesc>> {
        if let Some((_, diags)) = &self.broken {
            return Staged::new(None, diags.clone());
        }
        let mut diags: Vec<Diagnostic> = self.check.diagnostics.clone();
        reading_order(&mut diags);
        let failed = diags.iter().any(Diagnostic::is_error);
        let scene = self.check.scene.as_ref().filter(|_| !failed).cloned();
        Staged::new(scene, diags)
    }

    /// Brings the memo to the scene's files as they are now: the root file's `bytes`, and each
    /// included file read again through `loader` (which records it: the watch set); each file
    /// that changed is an edit ([`Memo::edit`]), in the order read. `None` when only a full
    /// compile can (the memo is then spoiled).
    fn update(&mut self, bytes: &[u8], loader: &dyn Loader) -> Option<Reuse> {
        self.broken = None;
        let mut reuse = self.edit(FileId(0), bytes, loader)?;
        // An edit may add or remove an include, and with it the last file.
        let mut next = 1;
        while next < self.scene_files {
            let id = FileId(next as u32);
            next += 1;
            let path = self.sources.get(id).path.clone();
            let bytes = loader.read(&path).ok()?;
            let after_broken = self.broken.is_some();
            let edited = self.edit(id, &bytes, loader)?;
            // A file changed after one with a syntax error: that one's sources miss it.
            if after_broken && edited != Reuse::Unchanged {
                return None;
            }
            reuse = match (reuse, edited) {
                (Reuse::Unchanged, r) | (r, Reuse::Unchanged) => r,
                (
                    Reuse::Statements { parsed, checked },
                    Reuse::Statements {
                        parsed: p,
                        checked: c,
                    },
                ) => Reuse::Statements {
                    parsed: parsed + p,
                    checked: checked + c,
                },
                _ => return None,
            };
        }
        Some(reuse)
    }

    /// Brings the memo to the new text `bytes` of the scene's file `file`, or `None` when only
    /// a full compile can (the memo is then spoiled).
    fn edit(&mut self, file: FileId, bytes: &[u8], loader: &dyn Loader) -> Option<Reuse> {
        let text = decode(bytes).ok()?;
        if text.trim().is_empty() {
            return None;
        }
        let old = self.sources.get(file).text.clone();
        if *old == *text {
            return Some(Reuse::Unchanged);
        }
        // One file: its statements are the list; else that file's, mapped to the list's.
        let several =
            (!self.files.is_empty()).then(|| files::of_file(&self.spans, &self.files, file));
        let spans = several.as_ref().map_or(&self.spans[..], |v| &v.spans[..]);
        let mut region = edit::region(file, &old, text, spans)?;
        let mut parsed = syntax::parse_region(file, text, region.bytes.start, region.bytes.end);
        if parsed.is_none() {
            // `// ` typed before a statement: the region must take that statement too.
            if let Some(wider) = edit::widened(&region, spans, text.len()) {
                parsed = syntax::parse_region(file, text, wider.bytes.start, wider.bytes.end);
                if parsed.is_some() {
                    region = wider;
                }
            }
        }
        let Some(parsed) = parsed else {
            // A scene of several files: that file's statements (seventh session).
            let view = several.as_ref().map(|v| &v.spans[..]);
            return self.broken(file, &old, text, &region, view);
        };
        let parsed_count = parsed.len();
        let (file_range, new) = edit::changed(&region, spans, parsed);
        // The version header stays the first statement (the driver's check of it is not redone),
        // or is edited alone and stays one the driver takes: nothing else reads it.
        let header = file_range == (0..1) && matches!(&new[..], [s] if supported_header(s));
        if file_range.start == 0 && (!new.is_empty() || !file_range.is_empty()) && !header {
            return None;
        }
        // An include added or removed changes which files the scene reads (`include_edit`).
        let include = |s: &Stmt| matches!(s, Stmt::Include { .. });
        let old_range = match &several {
            Some(view) => view.list_range(file_range.clone())?,
            None => file_range.clone(),
        };
        let sources = self.sources.with_edit(&region.shift, text);
        if self.chunks_whole == Some(true) {
            let whole = |s: &Stmt| {
                let span = s.span();
                text.get(span.start as usize..span.end as usize)
                    .is_some_and(broken::whole)
            };
            self.chunks_whole = new.iter().all(whole).then_some(true);
        }
        let checked = if header {
            self.move_spans(&region, old_range, &new)?;
            self.check.shift_spans(&region.shift).then_some(0)?
        } else if self.check.only_objects(old_range.clone(), &new) {
            if !(self.check).recheck(&sources, old_range.clone(), &new, &region.shift) {
                return None;
            }
            self.move_spans(&region, old_range, &new)?;
            new.len()
        } else {
            let old_stmts = parse_old(file, &old, spans, file_range)?;
            if old_stmts.iter().chain(&new).any(include) {
                let checked =
                    self.include_edit(file, loader, &region, old_range, &old_stmts, &new, sources);
                return Some(Reuse::Statements {
                    parsed: parsed_count,
                    checked: checked?,
                });
            }
            self.move_spans(&region, old_range.clone(), &new)?;
            let files = scene_texts(&self.spans, &self.files, self.scene_files, &sources);
            let mut naming = dependents::SceneStatements(files);
            let shift = &region.shift;
            let lets = (old_stmts.iter().chain(&new)).all(|s| matches!(s, Stmt::Let { .. }));
            let settings = (old_stmts.iter().chain(&new)).all(crate::check::is_setting);
            let groups = (old_stmts.iter().chain(&new)).any(|s| matches!(s, Stmt::Group(_)));
            let redeclared =
                self.check
                    .recheck_redeclared(old_range.clone(), &old_stmts, &new, shift);
            if let Some(checked) = redeclared {
                checked?
            } else if settings {
                let check = &mut self.check;
                check.recheck_settings(&sources, old_range, &old_stmts, &new, shift, &mut naming)?
            } else if groups {
                let old_sources = &self.sources;
                let check = &mut self.check;
                check.recheck_placements(
                    old_sources,
                    &sources,
                    old_range,
                    &old_stmts,
                    &new,
                    shift,
                )?
            } else if old_stmts.is_empty() != new.is_empty() {
                let add_or_remove = if lets {
                    CheckMemo::add_or_remove_lets
                } else {
                    CheckMemo::add_or_remove_decl
                };
                add_or_remove(
                    &mut self.check,
                    &sources,
                    old_range,
                    &old_stmts,
                    &new,
                    shift,
                    &mut naming,
                )?
            } else {
                let check = &mut self.check;
                check.recheck_decls(&sources, old_range, &old_stmts, new, shift, &mut naming)?
            }
        };
        self.sources = sources;
        Some(Reuse::Statements {
            parsed: parsed_count,
            checked,
        })
    }

    /// A syntax error in `text` (edited from the last text that parsed, `old`, in `region`):
    /// the full compile's diagnostics when the memo tells them ([`broken::diagnostics`]),
    /// kept in [`Memo::broken`] while the memo stays that of `old`.
    /// In a scene of several files, `view` is the edited file's statements (`file`): its
    /// chunks are found afresh, and a declaration lost is declined (what names it, or declares
    /// its name too, may be in another file).
    fn broken(
        &mut self,
        file: FileId,
        old: &str,
        text: &str,
        region: &Region,
        view: Option<&[(u32, u32)]>,
    ) -> Option<Reuse> {
        let (spans, by_name) = match view {
            None => {
                let whole = *(self.chunks_whole)
                    .get_or_insert_with(|| broken::no_inner_resync(old, &self.spans));
                let defines = self.sources.files().count() > 1;
                (whole.then_some(&self.spans[..])?, Some(defines))
            }
            Some(spans) => (broken::no_inner_resync(old, spans).then_some(spans)?, None),
        };
        let (diags, parsed) =
            broken::diagnostics(text, old, spans, region, &self.check.diagnostics, by_name)?;
        self.broken = Some((self.new_sources(file, text), diags));
        Some(Reuse::Statements { parsed, checked: 0 })
    }

    /// The sources after an edit of `file` to `text`: that file's entry with the new text, the
    /// others as they were.
    fn new_sources(&self, file: FileId, text: &str) -> SourceMap {
        self.sources.with_text(file, text)
    }

    /// The statements' byte ranges after the edit: the changed ones (`old`, list indices)
    /// replaced, later ones of the edited file moved, and the includes' places with them.
    fn move_spans(
        &mut self,
        region: &Region,
        old: std::ops::Range<usize>,
        new: &[Stmt],
    ) -> Option<()> {
        let shift = &region.shift;
        let replaced = new.iter().map(|s| (s.span().start, s.span().end));
        let at = old.start;
        self.spans.splice(old.clone(), []);
        let several = !self.files.is_empty();
        if several {
            self.files.splice(old, []);
        }
        for (i, span) in self.spans.iter_mut().enumerate() {
            if several && self.files[i] != shift.file {
                continue;
            }
            let mut s = crate::source::Span {
                file: shift.file,
                start: span.0,
                end: span.1,
            };
            if !shift.apply(&mut s) {
                return None;
            }
            *span = (s.start, s.end);
        }
        let tail = self.spans.split_off(at);
        self.spans.extend(replaced);
        self.spans.extend(tail);
        if several {
            let tail = self.files.split_off(at);
            // The edited file's, or an included file's added with its include.
            self.files.extend(new.iter().map(|s| s.span().file));
            self.files.extend(tail);
        }
        self.check.order.shift(shift).then_some(())
    }
}

/// The old statements `range` of `file` (of its old text `old`, its statements at `spans`),
/// parsed again.
fn parse_old(
    file: FileId,
    old: &str,
    spans: &[(u32, u32)],
    range: std::ops::Range<usize>,
) -> Option<Vec<Stmt>> {
    let start = match spans.get(range.start) {
        Some(&(s, _)) => s as usize,
        None => return range.is_empty().then(Vec::new),
    };
    let end = spans.get(range.end).map_or(old.len(), |&(s, _)| s as usize);
    let parsed = syntax::parse_region(file, old, start, end)?;
    (parsed.len() == range.len()).then_some(parsed)
}

/// Each scene file of `sources` (the new text) with its statements, for the search of what
/// names a name ([`dependents::naming`]): the memo's one list when the scene is one file (`files` empty).
fn scene_texts<'a>(
    spans: &'a [(u32, u32)],
    files: &[FileId],
    scene_files: usize,
    sources: &'a SourceMap,
) -> Vec<dependents::FileText<'a>> {
    let text = |id: FileId| &*sources.get(id).text;
    if files.is_empty() {
        return vec![dependents::FileText {
            file: FileId(0),
            text: text(FileId(0)),
            spans: std::borrow::Cow::Borrowed(spans),
            list: None,
        }];
    }
    (0..scene_files)
        .map(|i| {
            let file = FileId(i as u32);
            let view = files::of_file(spans, files, file);
            dependents::FileText {
                file,
                text: text(file),
                spans: std::borrow::Cow::Owned(view.spans),
                list: Some(view.flat),
            }
        })
        .collect()
}
