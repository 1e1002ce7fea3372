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
//! a diagnostic, are checked alone ([`CheckMemo::add_or_remove_lets`]); so is a value edit of a
//! camera, a light or the render block, or a camera's or light's rename ([`CheckMemo::recheck_setting`]), and `material`s,
//! `mesh`es and `texture`s added (a pasted block) or removed ([`CheckMemo::add_or_remove_decl`]); the version header edited alone
//! (still `scnc 1`) only moves the spans. An edit that breaks the
//! syntax gets the full compile's diagnostics from the memo of the last text that parsed
//! ([`super::broken`]), which stays for the edit that fixes it (diffed against that text). Anything
//! else is a full compile, which is always correct: a scene with includes or a file-level
//! diagnostic, a syntax error [`super::broken`] declines, another statement added, removed or renamed among declarations, an edit of a
//! light, a camera or the render block that gives or takes away a diagnostic, or made while the
//! scene has an error (or of a constant one of them names), a `let` that fails (or failed) while another error
//! stands, and any edit where a kept span
//! would reach into the edited bytes. An edit that makes a mesh or material used or unused, or a
//! declaration fail to lower or lower again, compacts the IR's indices again from the memo
//! (`check::recheck::compact`). `scnc watch` and `scnc lsp` compile through it;
//! `tests/incremental.rs` replays seeded edits and compares every result with a fresh compile.

use std::path::Path;
use std::sync::Arc;

use super::broken;
use super::dependents;
use super::edit::{self, Region};
use super::{decode, reading_order, Driver, Overrides};
use crate::assets::Loader;
use crate::check::{check_tracked, CheckMemo, Placed, PreCheck};
use crate::diag::{Diagnostic, Staged};
use crate::ir;
use crate::source::{FileId, SourceMap};
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
    /// Its sources: the scene file (file 0) and the `--define` files after it.
    sources: SourceMap,
    /// The byte range of every top-level statement of the scene file, in order.
    spans: Vec<(u32, u32)>,
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
                if let Some(reuse) = memo.edit(bytes) {
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
                for (name, value) in std::mem::take(&mut d.pending_defines) {
                    d.add_define(&name, &value);
                }
                if !d.trackable() {
                    d.finish()
                } else {
                    let memo = d.into_memo(path);
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
    /// Whether the files read allow incremental compiles: one scene file (and the
    /// `--define`s) with no includes and no diagnostic of its own.
    fn trackable(&self) -> bool {
        let includes = self
            .statements
            .iter()
            .any(|s| matches!(s, Stmt::Include { .. }));
        self.diags.is_empty() && !includes
    }

    /// The full check, keeping a memo of it.
    fn into_memo(self, path: &Path) -> Memo {
        let Driver {
            sources,
            statements,
            frame,
            defines,
            pre,
            ..
        } = self;
        let placed = pre.map(PreCheck::into_placed).unwrap_or_default();
        let spans = statement_spans(&statements, &placed);
        let check = check_tracked(&statements, placed, &sources, frame, defines);
        Memo {
            path: path.to_path_buf(),
            sources,
            spans,
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

/// The byte range of every top-level statement, those `placed` included, in order.
fn statement_spans(statements: &[Stmt], placed: &Placed) -> Vec<(u32, u32)> {
    let mut spans = Vec::with_capacity(statements.len() + placed.len());
    let mut kept = statements.iter().map(|s| s.span());
    let mut early = placed.places().into_iter().peekable();
    for i in 0..statements.len() + placed.len() {
        let span = match early.next_if(|&(at, _)| at == i) {
            Some((_, span)) => Some(span),
            None => kept.next(),
        };
        spans.extend(span.map(|s| (s.start, s.end)));
    }
    spans
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

    /// Brings the memo to the new text `bytes` of the scene file, or `None` when only a full
    /// compile can (the memo is then spoiled).
    fn edit(&mut self, bytes: &[u8]) -> Option<Reuse> {
        self.broken = None;
        let text = decode(bytes).ok()?;
        if text.trim().is_empty() {
            return None;
        }
        let root = FileId(0);
        let old = self.sources.get(root).text.clone();
        let Some(region) = edit::region(root, &old, text, &self.spans) else {
            return Some(Reuse::Unchanged);
        };
        let Some(parsed) = syntax::parse_region(root, text, region.bytes.start, region.bytes.end)
        else {
            return self.broken(&old, text, &region);
        };
        let parsed_count = parsed.len();
        let (old_range, new) = edit::changed(&region, &self.spans, parsed);
        // The version header stays the first statement (the driver's check of it is not redone),
        // or is edited alone and stays one the driver takes: nothing else reads it.
        let header = old_range == (0..1) && matches!(&new[..], [s] if supported_header(s));
        if old_range.start == 0 && (!new.is_empty() || !old_range.is_empty()) && !header {
            return None;
        }
        let sources = self.new_sources(text);
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
            let old_stmts = self.parse_old(&old, old_range.clone())?;
            self.move_spans(&region, old_range.clone(), &new)?;
            let spans = &self.spans;
            let mut naming = |name: &str| dependents::naming(text, spans, name);
            let shift = &region.shift;
            let lets = (old_stmts.iter().chain(&new)).all(|s| matches!(s, Stmt::Let { .. }));
            let setting = match (&old_stmts[..], &new[..]) {
                ([old], [new]) if CheckMemo::same_setting(old, new) => Some((old, new)),
                _ => None,
            };
            let groups = (old_stmts.iter().chain(&new)).any(|s| matches!(s, Stmt::Group(_)));
            if let Some((old, new)) = setting {
                (self.check).recheck_setting(&sources, old, new, shift, &mut naming)?
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
    fn broken(&mut self, old: &str, text: &str, region: &Region) -> Option<Reuse> {
        let whole =
            *(self.chunks_whole).get_or_insert_with(|| broken::no_inner_resync(old, &self.spans));
        if !whole {
            return None;
        }
        let defines = self.sources.files().count() > 1;
        let (diags, parsed) = broken::diagnostics(
            text,
            old,
            &self.spans,
            region,
            &self.check.diagnostics,
            defines,
        )?;
        self.broken = Some((self.new_sources(text), diags));
        Some(Reuse::Statements { parsed, checked: 0 })
    }

    /// The old statements `range` (of the old text `old`), parsed again.
    fn parse_old(&self, old: &str, range: std::ops::Range<usize>) -> Option<Vec<Stmt>> {
        let start = match self.spans.get(range.start) {
            Some(&(s, _)) => s as usize,
            None => return range.is_empty().then(Vec::new),
        };
        let end = self
            .spans
            .get(range.end)
            .map_or(old.len(), |&(s, _)| s as usize);
        let parsed = syntax::parse_region(FileId(0), old, start, end)?;
        (parsed.len() == range.len()).then_some(parsed)
    }

    /// The sources of a compile of `text`: the scene file's entry with the new text, the
    /// `--define` files as they were.
    fn new_sources(&self, text: &str) -> SourceMap {
        let mut sources = SourceMap::new();
        for (id, f) in self.sources.files() {
            let content = if id == FileId(0) {
                std::sync::Arc::<str>::from(text)
            } else {
                f.text.clone()
            };
            sources.add(f.path.clone(), f.name.clone(), content);
        }
        sources
    }

    /// The statements' byte ranges after the edit: the changed ones replaced, later ones moved.
    fn move_spans(
        &mut self,
        region: &Region,
        old: std::ops::Range<usize>,
        new: &[Stmt],
    ) -> Option<()> {
        let shift = &region.shift;
        let replaced = new.iter().map(|s| (s.span().start, s.span().end));
        let at = old.start;
        self.spans.splice(old, []);
        for span in &mut self.spans {
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
        Some(())
    }
}
