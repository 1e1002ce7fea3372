//! Stage 2, check, incrementally: the statements of a declaration edit ([`super::decls`])
//! checked again against the memo's state — the `let`s first, in statement order, each
//! evaluated again ([`super::reevaluate`]) and followed by every statement that names it when
//! its value changed; then the declarations and `object`s, in statement order, against every
//! constant — with what each of them produced (IR, diagnostics, statement records) kept for
//! [`super::splice_decls`] to put in place.

use std::collections::BTreeMap;

use super::super::names::Namespace;
use super::super::{Checker, StmtRecord};
use super::decls::{Dependents, Redone};
use super::groups::declared_groups;
use super::redeclared::{declared, Declared};
use super::reevaluate::{reevaluate, Failing};
use crate::diag::Diagnostic;
use crate::source::Span;
use crate::syntax::{DeclKind, Item, Stmt};

/// Checks the statements `changed` (index → new statement) again against the memo's state in
/// `cx`, then those that name a constant whose value changed: `None` when it must decline.
/// `failing` says when a `let` may come to fail or stop failing; the `group`s at the indices
/// `fresh` had their uses of meshes and materials taken out of the counts before (a
/// declaration they name was added): they are counted as they are checked.
#[allow(clippy::too_many_arguments)] // the memo's parts, lent apart from the checker's
pub(super) fn redo(
    cx: &mut Checker,
    changed: BTreeMap<usize, Stmt>,
    records: &[StmtRecord],
    material_textures: &[(u32, Vec<usize>)],
    failing: Failing,
    dependents: &mut dyn Dependents,
    renaming: Option<(Namespace, usize, String)>,
    fresh: &[usize],
) -> Option<Redone> {
    let (mut lets, mut others): (BTreeMap<_, _>, BTreeMap<_, _>) = changed
        .into_iter()
        .partition(|(_, s)| matches!(s, Stmt::Let { .. }));
    let mut redone = Redone::default();
    // `let`s in statement order: each reads only constants before it.
    while let Some((i, stmt)) = lets.pop_first() {
        redone.checked += 1;
        let Stmt::Let { name, value, span } = &stmt else {
            return None;
        };
        let changed = reevaluate(cx, name, value, failing, dependents)?;
        // Its diagnostics lie in its own text, where the next re-check of it finds them.
        if !cx.diags.iter().all(|d| lies_in(d, *span)) {
            return None;
        }
        redone.early.append(&mut cx.diags);
        redone.early_spans.push(*span);
        if !changed {
            continue;
        }
        for (j, s) in dependents.naming(&name.name)? {
            match s {
                // A `let` before this one cannot name it (the check would have reported it).
                Stmt::Let { .. } if j <= i => {}
                // A second declaration of a name: the check read no more than its name.
                _ if a_later_declaration(cx, &s) => {}
                Stmt::Let { .. } => {
                    lets.entry(j).or_insert(s);
                }
                _ => {
                    others.entry(j).or_insert(s);
                }
            }
        }
    }
    // Declarations and objects, in statement order, against every constant.
    for (i, stmt) in others {
        redone.checked += 1;
        match &stmt {
            Stmt::Object(_) => {
                let old = *records.get(i)?;
                if !old.object {
                    return None;
                }
                let (mesh, material) = cx.placement(&stmt);
                forget_use(&mut cx.mesh_uses, old.mesh)?;
                forget_use(&mut cx.material_uses, old.material)?;
                let objects = std::mem::take(&mut cx.objects);
                let record = StmtRecord {
                    object: true,
                    setting: false,
                    diags: cx.diags.len() as u32,
                    objects: objects.len() as u32,
                    mesh: mesh.map(|m| m as u32),
                    material: material.map(|m| m as u32),
                };
                let diags = std::mem::take(&mut cx.diags);
                redone.objects.insert(i, (record, diags, objects));
            }
            Stmt::Decl(d) if d.kind == DeclKind::Material => {
                // A normal map's warning reads the texture's IR, which the memo does not keep.
                if names_a_normal_map(d) {
                    return None;
                }
                let at = declared_at(cx, Namespace::Material, d)?;
                let (material, textures) = cx.material(d);
                let old = material_textures.binary_search_by_key(&(at as u32), |(m, _)| *m);
                let old_textures = old.map_or(&[][..], |k| &material_textures[k].1);
                if textures != old_textures {
                    redone.material_textures.push((at as u32, textures));
                }
                redone.relowered.materials.push((at, material));
            }
            // An `obj` mesh too (its file is read by the build, not here), with material
            // overrides (table indices here; a mesh the IR holds with any is put in by a
            // re-compaction, which remaps them and gives the materials' used-ness).
            Stmt::Decl(d) if d.kind == DeclKind::Mesh => {
                let at = declared_at(cx, Namespace::Mesh, d)?;
                let mesh = cx.mesh(d);
                redone.relowered.meshes.push((at, mesh));
            }
            // An `image` too: a normal map's warning reads only whether it is one decoded as
            // sRGB, which `CheckMemo::recheck_decls` compares before and after.
            Stmt::Decl(d) if d.kind == DeclKind::Texture => {
                let at = declared_at(cx, Namespace::Texture, d)?;
                let texture = cx.texture(d);
                redone.relowered.textures.push((at, texture));
            }
            Stmt::Group(_) => {
                let old = *records.get(i)?;
                let counted = fresh.contains(&i);
                let again = group_again(cx, &stmt, old, renaming.as_ref(), counted);
                let (record, diags, objects) = again?;
                redone.objects.insert(i, (record, diags, objects));
                redone.group_spans.push(stmt.span());
            }
            // Checked after every declaration, once the rest is in place
            // with the other settings (`CheckMemo::settings_named`).
            Stmt::Camera { .. } | Stmt::Render { .. } => {
                redone.settings.push(stmt);
                continue;
            }
            Stmt::Decl(d) if d.kind == DeclKind::Light => {
                redone.settings.push(stmt);
                continue;
            }
            _ => return None,
        }
        if let Stmt::Decl(d) = &stmt {
            // Its diagnostics (before the placement phase) must lie in its own text, where
            // the next re-check of it finds them.
            if !cx.diags.iter().all(|e| lies_in(e, d.span)) {
                return None;
            }
            redone.early.append(&mut cx.diags);
            redone.early_spans.push(d.span);
        }
    }
    Some(redone)
}

/// Whether a material declaration has a `normal_map` key.
pub(super) fn names_a_normal_map(d: &crate::syntax::Decl) -> bool {
    let items = d.body.iter().flat_map(|b| &b.items);
    items
        .into_iter()
        .any(|i| matches!(i, Item::Value(e) if e.as_name() == Some("normal_map")))
}

/// Whether `s` is a `let`, `material`, `mesh` or `texture` declared after the first of its
/// name (which the constants or its table hold at an earlier span of the same file): the
/// check gave it the duplicate-name error and neither evaluated nor lowered it, so a changed
/// constant it names changes nothing of it. Spans are compared within one file only, where
/// byte order is the reading order.
fn a_later_declaration(cx: &Checker, s: &Stmt) -> bool {
    let Some((kind, name)) = declared(s) else {
        return false;
    };
    let first = match kind {
        Declared::Let => cx.lets.get(&name.name).map(|(_, at)| *at),
        Declared::Table(ns) => {
            let table = &cx.tables[ns as usize];
            let at = table.get(&name.name);
            at.and_then(|at| table.spans.get(at).copied())
        }
    };
    first.is_some_and(|f| f.file == name.span.file && f.end <= name.span.start)
}

/// Whether the primary label of `d` starts inside `span`.
fn lies_in(d: &Diagnostic, span: Span) -> bool {
    let inside = |l: &crate::diag::Label| {
        l.span.file == span.file && (span.start..span.end).contains(&l.span.start)
    };
    d.primary.as_ref().is_some_and(inside)
}

/// The table index of the declaration `d`, if it is the one its name resolves to.
fn declared_at(cx: &Checker, ns: Namespace, d: &crate::syntax::Decl) -> Option<usize> {
    let table = &cx.tables[ns as usize];
    let at = table.get(&d.name.name)?;
    (table.spans.get(at) == Some(&d.name.span)).then_some(at)
}

/// One use fewer of the declaration `at` (`None` when it had none: the memo is not this one).
fn forget_use(uses: &mut [u32], at: Option<u32>) -> Option<()> {
    if let Some(at) = at {
        let n = uses.get_mut(at as usize)?;
        *n = n.checked_sub(1)?;
    }
    Some(())
}

/// A `group` that names a changed constant or a renamed declaration (its text unchanged,
/// moved: its names are the table's at their spans already) checked again, as
/// [`super::groups`] checks an edited one: against an empty group table (its names must each
/// be the first of theirs). Its uses of meshes and materials: with no rename, the same as
/// before (the same names resolve the same way), so put back as they were; with `renaming`
/// (the namespace, table index and old name of a declaration the table now holds under its
/// new name), those it counted under the old name (the group checked once more with the
/// table's entry named back, its output thrown away) are taken out and those under the new
/// name kept. With `fresh` (its uses were taken out before: a declaration it names was added),
/// its uses are counted as it is checked. Its record, diagnostics and objects (table indices).
fn group_again(
    cx: &mut Checker,
    stmt: &Stmt,
    old: StmtRecord,
    renaming: Option<&(Namespace, usize, String)>,
    fresh: bool,
) -> Option<(StmtRecord, Vec<Diagnostic>, Vec<crate::ir::Object>)> {
    let groups = &cx.tables[Namespace::Group as usize];
    let first = |(name, span): (&str, Span)| {
        groups
            .get(name)
            .is_some_and(|at| groups.spans.get(at) == Some(&span))
    };
    if old.object
        || !declared_groups(std::slice::from_ref(stmt))
            .into_iter()
            .all(first)
    {
        return None;
    }
    let uses = (cx.mesh_uses.clone(), cx.material_uses.clone());
    let groups = std::mem::take(&mut cx.tables[Namespace::Group as usize]);
    match renaming {
        None if fresh => {
            let _ = cx.placement(stmt);
        }
        None => {
            let _ = cx.placement(stmt);
            (cx.mesh_uses, cx.material_uses) = uses;
        }
        Some((ns, at, was)) => {
            let (diags, objects) = (cx.diags.len(), cx.objects.len());
            let now = rename_at(cx, *ns, *at, was)?;
            let _ = cx.placement(stmt);
            rename_at(cx, *ns, *at, &now)?;
            // The names it declared go with its output (checked again below).
            cx.tables[Namespace::Group as usize] = Default::default();
            cx.diags.truncate(diags);
            cx.objects.truncate(objects);
            // Its uses under the old name out of the counts (they hold them), the new in.
            forget_counted(&mut cx.mesh_uses, &uses.0)?;
            forget_counted(&mut cx.material_uses, &uses.1)?;
            let _ = cx.placement(stmt);
        }
    }
    cx.tables[Namespace::Group as usize] = groups;
    let objects = std::mem::take(&mut cx.objects);
    let diags = std::mem::take(&mut cx.diags);
    let record = StmtRecord {
        object: false,
        setting: false,
        diags: diags.len() as u32,
        objects: objects.len() as u32,
        mesh: None,
        material: None,
    };
    Some((record, diags, objects))
}

/// Names entry `at` of `ns`'s table `name` (its span kept): the name it had.
fn rename_at(cx: &mut Checker, ns: Namespace, at: usize, name: &str) -> Option<String> {
    let table = &mut cx.tables[ns as usize];
    let span = *table.spans.get(at)?;
    let had = table.name(at).to_string();
    table.remove_at(at);
    table.insert_at(at, name, span);
    Some(had)
}

/// The counts `uses` (those `before`, plus what one check of a group counted since) set to
/// `before` less that group's count: its uses under the old name, which `before` holds.
fn forget_counted(uses: &mut [u32], before: &[u32]) -> Option<()> {
    (uses.len() == before.len()).then_some(())?;
    for (u, &b) in uses.iter_mut().zip(before) {
        let counted = u.checked_sub(b)?;
        *u = b.checked_sub(counted)?;
    }
    Some(())
}
