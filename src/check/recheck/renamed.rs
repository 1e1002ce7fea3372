//! Stage 2, check, incrementally: a `material`, `mesh` or `texture` declaration renamed
//! (`material m1 = …` → `material m1x = …`), for [`CheckMemo::recheck_decls`] to check again
//! with every statement whose check the new name changes.
//!
//! Why the result is the full check's: a declaration's table index is its place among those
//! of its kind, which a rename keeps; so the table keeps its entry there, under the new name
//! (declined when another declaration has that name, when the old one was not the first of
//! its name, and while any name is declared twice: a rename could change which declaration is
//! the first). What reads the name is checked again: every statement that names the old name
//! (an object now gets an unknown name) or the new one (an unknown name now resolves), found
//! by the whole-word search, and every statement with an unknown-name diagnostic of the
//! namespace, whose did-you-mean lists its names (found by the unknown name, read at the
//! diagnostic's label). A `group` among them is checked twice (`redo::group_again`): once with
//! the table's entry named back, to count the uses its objects made under the old name (taken
//! out of the counts), once under the new name (kept). An area light among them is declined
//! (the re-check declines statements of that kind); an `obj` mesh whose material overrides
//! name the renamed material is lowered again. The IR is compacted again whatever the
//! edit changed, so that an unused declaration's warning carries the new name; the renamed
//! one's old IR entry (its spans in the edited bytes, which cannot move) is set aside while
//! every other span moves ([`SetAside`]), and the re-compaction puts the one lowered again in
//! its place.

use std::collections::BTreeMap;

use super::super::names::Namespace;
use super::{CheckMemo, Dependents};
use crate::diag::Code;
use crate::ir;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{DeclKind, Ident, Stmt};

/// The namespace, old and new name of a renamed declaration: `old` → `new` is a `material`,
/// `mesh` or `texture` given another name.
pub(super) fn renamed<'a>(
    old: &'a Stmt,
    new: &'a Stmt,
) -> Option<(Namespace, &'a Ident, &'a Ident)> {
    let (Stmt::Decl(a), Stmt::Decl(b)) = (old, new) else {
        return None;
    };
    let ns = match a.kind {
        DeclKind::Material => Namespace::Material,
        DeclKind::Mesh => Namespace::Mesh,
        DeclKind::Texture => Namespace::Texture,
        DeclKind::Light => return None,
    };
    (a.kind == b.kind && a.name.name != b.name.name).then_some((ns, &a.name, &b.name))
}

impl CheckMemo {
    /// Renames the table entry of `old` (at its span in the old text, the first of its name)
    /// in `ns` to `new`, at its place; its span is set to one the edit's shift keeps (the file's
    /// start) until [`CheckMemo::recheck_decls`] gives it `new`'s. The table index, or `None`
    /// when the rename must decline.
    pub(super) fn rename_entry(
        &mut self,
        ns: Namespace,
        old: &Ident,
        new: &Ident,
    ) -> Option<usize> {
        let twice = self
            .diagnostics
            .iter()
            .any(|d| d.code == Code::CheckDuplicateName);
        let table = &mut self.tables[ns as usize];
        let at = table.get(&old.name)?;
        let first = table.spans.get(at) == Some(&old.span);
        if twice || !first || table.get(&new.name).is_some() {
            return None;
        }
        table.remove_at(at);
        table.insert_at(at, &new.name, Span::new(new.span.file, 0, 0));
        Some(at)
    }

    /// The statements (index → statement of the new text) whose check the rename of `old` to
    /// `new` in `ns` changes: those naming either name, and those with an unknown-name
    /// diagnostic of `ns` (its label moved by `shift` into the new text, which `sources`
    /// holds). `None` when one cannot be parsed alone or a label lies in the edited bytes.
    pub(super) fn rename_dependents(
        &self,
        sources: &SourceMap,
        ns: Namespace,
        names: &[&str],
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<BTreeMap<usize, Stmt>> {
        let lists = |code| lists_names_of(ns, code);
        self.naming_or_listing(sources, names, lists, shift, dependents)
    }

    /// The statements (index → statement of the new text) that name one of `names`, or carry
    /// a diagnostic whose code `lists` says may list them in its did-you-mean (the name it
    /// labels, moved by `shift` into the new text, searched for too). `None` when one cannot
    /// be parsed alone or a label lies in the edited bytes.
    pub(super) fn naming_or_listing(
        &self,
        sources: &SourceMap,
        names: &[&str],
        lists: impl Fn(Code) -> bool,
        shift: &Shift,
        dependents: &mut dyn Dependents,
    ) -> Option<BTreeMap<usize, Stmt>> {
        let mut words: Vec<String> = names.iter().map(|n| n.to_string()).collect();
        for d in self.diagnostics.iter().filter(|d| lists(d.code)) {
            let mut span = d.primary.as_ref()?.span;
            if !shift.apply(&mut span) {
                return None;
            }
            words.push(sources.snippet(span).to_string());
        }
        words.sort_unstable();
        words.dedup();
        let mut found = BTreeMap::new();
        for w in words {
            found.extend(dependents.naming(&w)?);
        }
        Some(found)
    }
}

/// Whether a diagnostic of code `code` may list the names of `ns` in its did-you-mean: an
/// unknown name of `ns`, and for textures also an unknown name in a material's colour, which
/// lists the textures and the constants (`unknown texture or constant`, an unknown-name
/// code that an unknown constant shares: such a statement is checked again for nothing).
fn lists_names_of(ns: Namespace, code: Code) -> bool {
    code == ns.unknown_code() || (ns == Namespace::Texture && code == Code::CheckUnknownName)
}

/// The renamed declaration's entry, taken out of the IR's list (its IR index and entry) or of
/// the dropped ones (its place there and entry).
pub(super) enum SetAside {
    Material(bool, usize, (u32, ir::Material)),
    Mesh(bool, usize, (u32, ir::Mesh)),
    Texture(bool, usize, (u32, ir::Texture)),
}

/// Entry `at` (table index) out of the IR's `list` (through `map`) or of `dropped`: whether it
/// was in the IR, its place, its table index and entry.
fn take_entry<T>(
    list: &mut Vec<T>,
    map: &[Option<u32>],
    dropped: &mut Vec<(u32, T)>,
    at: usize,
) -> Option<(bool, usize, (u32, T))> {
    if let Some(k) = map.get(at).copied().flatten() {
        let k = k as usize;
        return (k < list.len()).then(|| (true, k, (at as u32, list.remove(k))));
    }
    let place = dropped.iter().position(|(i, _)| *i as usize == at)?;
    Some((false, place, dropped.remove(place)))
}

/// An entry [`take_entry`] took, put back where it was.
fn put_entry<T>(list: &mut Vec<T>, dropped: &mut Vec<(u32, T)>, entry: (bool, usize, (u32, T))) {
    match entry {
        (true, k, (_, item)) => list.insert(k.min(list.len()), item),
        (false, place, item) => dropped.insert(place.min(dropped.len()), item),
    }
}

impl CheckMemo {
    /// Takes the entry of declaration `at` of `ns` out of the IR or the dropped declarations
    /// (`None` when it has none: it failed to lower).
    pub(super) fn set_aside(&mut self, ns: Namespace, at: usize) -> Option<SetAside> {
        let scene = std::sync::Arc::make_mut(self.scene.as_mut()?);
        let d = &mut self.dropped;
        Some(match ns {
            Namespace::Material => {
                let (i, k, e) = take_entry(
                    &mut scene.materials,
                    &self.material_map,
                    &mut d.materials,
                    at,
                )?;
                SetAside::Material(i, k, e)
            }
            Namespace::Mesh => {
                let (i, k, e) = take_entry(&mut scene.meshes, &self.mesh_map, &mut d.meshes, at)?;
                SetAside::Mesh(i, k, e)
            }
            _ => {
                let (i, k, e) =
                    take_entry(&mut scene.textures, &self.texture_map, &mut d.textures, at)?;
                SetAside::Texture(i, k, e)
            }
        })
    }

    /// Puts back what [`CheckMemo::set_aside`] took.
    pub(super) fn put_back(&mut self, aside: SetAside) {
        let Some(scene) = self.scene.as_mut().map(std::sync::Arc::make_mut) else {
            return;
        };
        let d = &mut self.dropped;
        match aside {
            SetAside::Material(i, k, e) => {
                put_entry(&mut scene.materials, &mut d.materials, (i, k, e))
            }
            SetAside::Mesh(i, k, e) => put_entry(&mut scene.meshes, &mut d.meshes, (i, k, e)),
            SetAside::Texture(i, k, e) => {
                put_entry(&mut scene.textures, &mut d.textures, (i, k, e))
            }
        }
    }
}
