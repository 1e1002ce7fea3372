//! Stage 2, check, incrementally: an edit of declarations that keep their names — a `let`'s
//! value, a `material`'s, a `mesh`'s or a `texture`'s properties (`let k = 3` → `let k = 4`,
//! `material m = phong { diffuse #f00 }` → `... #0f0 }`), and `object`s beside them — re-checked in place,
//! with every statement that names a constant whose value changed (found by name through
//! [`Dependents`]), and spliced into the [`CheckMemo`].
//!
//! A `let` whose value comes to fail (an error: the constant poisoned, as the check leaves it,
//! so that what names it fails quietly) or stops failing is taken when no other error stands
//! and its value names no unknown constant; its diagnostics lie in its own text and replace
//! its old ones, as a declaration's do.
//!
//! Why the result is the full check's: a re-checked `let` with an unknown name, or that fails
//! (or failed) while another error stands, a renamed
//! statement, a redeclaration (not the first of its name), an `obj` mesh, an `image` texture,
//! a material with a normal map (its warning reads the texture's IR), a `let` that a
//! `--define` overrides or that names a constant declared after it, and a constant named by
//! any other kind of statement (a camera, a light, a group, the render block) make it decline.
//! So the names and their table indices stay. A declaration's diagnostics (before the
//! placement phase: an albedo above 1, an unknown kind) lie in its own text; those of each
//! declaration checked again are replaced by its new ones (the order among statements is the
//! reading order's). A declaration that failed to lower (an error) or lowers again, or a
//! material that refers to other textures, changes what the IR holds: it is compacted again
//! ([`super::compact`]);
//! a `let` is evaluated again as the check evaluates it (the constants before it are the
//! check's), then the declarations and `object`s that name it, which the check lowers after
//! every `let`, against all constants. A texture, material or mesh keeps its table index and,
//! when what the IR holds is unchanged, its IR index: its IR entry is replaced there (or its
//! entry among the dropped ones). An `object` re-checked gives its diagnostics and IR
//! objects, put in place of its old ones in the placement phase's statement order.

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::names::Namespace;
use super::super::{Checker, StmtRecord};
use super::compact::Relowered;
use super::CheckMemo;
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{DeclKind, Expr, ExprKind, Item, Stmt};

/// The statements of the new text that name `name` (index among all top-level statements, and
/// the statement parsed), in order; `None` when one cannot be parsed alone. It may give more
/// than those that name it (a word in a comment or a string): those are checked again too.
pub type Dependents<'a> = dyn FnMut(&str) -> Option<Vec<(usize, Stmt)>> + 'a;

/// What a re-check of declarations and objects produced.
#[derive(Default)]
struct Redone {
    /// Per `object` statement checked again: its record, diagnostics and IR objects.
    objects: BTreeMap<usize, (StmtRecord, Vec<Diagnostic>, Vec<ir::Object>)>,
    /// Materials, meshes and textures lowered again.
    relowered: Relowered,
    /// Materials that now refer to other textures: (material, texture table indices).
    material_textures: Vec<(u32, Vec<usize>)>,
    /// The diagnostics of the declarations checked again (before the placement phase), and
    /// those declarations' spans (in the new text).
    early: Vec<Diagnostic>,
    early_spans: Vec<Span>,
    /// Statements checked again.
    checked: usize,
}

impl CheckMemo {
    /// Replaces the check of the statements `old` (indices into the old list; `old_stmts`, as
    /// parsed from the old text) by that of `new`, one for one, each the same declaration
    /// (kind and name) or an `object`; every other span moves by `shift`, and `sources` holds
    /// the new text. The number of statements checked again, or `None` when the result could
    /// differ from a full check's: the memo is then spoiled, and the caller checks in full.
    pub fn recheck_decls(
        &mut self,
        sources: &SourceMap,
        old: Range<usize>,
        old_stmts: &[Stmt],
        new: Vec<Stmt>,
        shift: &Shift,
        dependents: &mut Dependents,
    ) -> Option<usize> {
        let same = old_stmts.len() == new.len() && old.len() == new.len();
        if !same || self.records.len() < old.end {
            return None;
        }
        if !old_stmts
            .iter()
            .zip(&new)
            .all(|(o, n)| same_declaration(o, n))
        {
            return None;
        }
        // The old statements' own diagnostics go (their spans lie in the old text), then the
        // names and constants move to the new text: the re-check reports against them.
        let old_spans: Vec<Span> = old_stmts.iter().map(Stmt::span).collect();
        self.drop_early(&old_spans);
        if !self.shift_names(shift) {
            return None;
        }
        let was_used = (self.used_meshes(), self.used_materials());
        let changed = (old.start..).zip(new).collect();
        let mut cx = self.lend(sources);
        let textures = &self.material_textures;
        // A `let` may come to have a diagnostic, or lose one, only when no other error stands
        // (an unknown name's did-you-mean lists the constants, which such an edit changes).
        let clean = !self.diagnostics.iter().any(Diagnostic::is_error);
        let records = &self.records;
        let redone = redo(&mut cx, changed, records, textures, clean, dependents);
        self.take_back(&mut cx);
        let redone = redone?;
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        self.splice_decls(sources, redone, shift, used_changed)
    }

    /// Takes out the diagnostics before the placement phase whose primary span starts in one
    /// of `spans` (a statement's diagnostics lie in its own text).
    pub(super) fn drop_early(&mut self, spans: &[Span]) {
        let inside = |d: &Diagnostic| {
            let at = d.primary.as_ref().map(|l| l.span);
            at.is_some_and(|at| {
                (spans.iter()).any(|s| s.file == at.file && (s.start..s.end).contains(&at.start))
            })
        };
        let early = self.used_before.diags.min(self.diagnostics.len());
        let mut kept: Vec<Diagnostic> = self.diagnostics.drain(..early).collect();
        kept.retain(|d| !inside(d));
        self.used_before.diags = kept.len();
        self.diagnostics.splice(0..0, kept);
    }

    /// Moves the spans of the name tables and constants by `shift`.
    pub(super) fn shift_names(&mut self, shift: &Shift) -> bool {
        let mut ok = true;
        for span in self.lets.spans_mut() {
            ok &= shift.apply(span);
        }
        for t in &mut self.tables {
            for span in &mut t.spans {
                ok &= shift.apply(span);
            }
        }
        ok
    }

    /// Puts what was checked again in place of the old, moving every other span by `shift`.
    fn splice_decls(
        &mut self,
        sources: &SourceMap,
        redone: Redone,
        shift: &Shift,
        used_changed: bool,
    ) -> Option<usize> {
        let Redone {
            objects,
            mut relowered,
            material_textures,
            early,
            early_spans,
            checked,
        } = redone;
        let mut ok = true;
        // The diagnostics before the placement phase, the placement phase's, and those after.
        let before = self.used_before.diags;
        let placed: usize = self.records.iter().map(|r| r.diags as usize).sum();
        if before + placed > self.diagnostics.len() {
            return None;
        }
        let mut tail = self.diagnostics.split_off(before + placed);
        for d in &mut tail {
            ok &= d.shift_spans(shift);
        }
        let diags = self.diagnostics.split_off(before);
        for d in &mut self.diagnostics {
            ok &= d.shift_spans(shift);
        }
        // The statements checked again that depend on a changed constant: their old
        // diagnostics, now moved, give way to the new ones.
        self.drop_early(&early_spans);
        self.used_before.diags += early.len();
        let mut early_diags = std::mem::take(&mut self.diagnostics);
        early_diags.extend(early);
        let textures_changed = !material_textures.is_empty();
        let new_diags = objects.iter().map(|(&i, (_, d, _))| (i, d.clone()));
        let mut diags = merge_runs(
            diags,
            &self.records,
            |r| r.diags,
            new_diags,
            |d| d.shift_spans(shift),
        )?;
        early_diags.append(&mut diags);
        early_diags.append(&mut tail);
        self.diagnostics = early_diags;
        for (m, textures) in material_textures {
            let list = &mut self.material_textures;
            match (
                list.binary_search_by_key(&m, |(k, _)| *k),
                textures.is_empty(),
            ) {
                (Ok(at), true) => {
                    list.remove(at);
                }
                (Ok(at), false) => list[at].1 = textures,
                (Err(at), false) => list.insert(at, (m, textures)),
                (Err(_), true) => {}
            }
        }
        if let Some(scene) = &mut self.scene {
            let scene = std::sync::Arc::make_mut(scene);
            let old_objects = std::mem::take(&mut scene.objects);
            ok &= scene.shift_spans(shift);
            let (material_map, mesh_map) = (&self.material_map, &self.mesh_map);
            let new_objects = objects.iter().map(|(&i, (_, _, objects))| {
                let mut objects = objects.clone();
                for o in &mut objects {
                    o.mesh = mesh_map
                        .get(o.mesh as usize)
                        .copied()
                        .flatten()
                        .unwrap_or(0);
                    let material = material_map.get(o.material as usize).copied();
                    o.material = material.flatten().unwrap_or(0);
                }
                (i, objects)
            });
            scene.objects = merge_runs(
                old_objects,
                &self.records,
                |r| r.objects,
                new_objects,
                |o| shift.apply(&mut o.span),
            )?;
        }
        ok &= self.dropped.shift_spans(shift);
        for (i, (record, _, _)) in objects {
            *self.records.get_mut(i)? = record;
        }
        // Declarations now used or unused, lowered or not, textures now used or not: the IR's
        // indices change.
        if used_changed || textures_changed || !self.put_in_place(&mut relowered) {
            self.recompact(sources, relowered)?;
        }
        ok.then_some(checked)
    }
}

/// Checks the statements `changed` (index → new statement) again against the memo's state in
/// `cx`, then those that name a constant whose value changed: `None` when it must decline.
fn redo(
    cx: &mut Checker,
    changed: BTreeMap<usize, Stmt>,
    records: &[StmtRecord],
    material_textures: &[(u32, Vec<usize>)],
    clean: bool,
    dependents: &mut Dependents,
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
        let changed = reevaluate(cx, name, value, clean)?;
        // Its diagnostics lie in its own text, where the next re-check of it finds them.
        if !cx.diags.iter().all(|d| lies_in(d, *span)) {
            return None;
        }
        redone.early.append(&mut cx.diags);
        redone.early_spans.push(*span);
        if !changed {
            continue;
        }
        for (j, s) in dependents(&name.name)? {
            match s {
                // A `let` before this one cannot name it (the check would have reported it).
                Stmt::Let { .. } if j <= i => {}
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
            Stmt::Decl(d) if d.kind == DeclKind::Mesh && d.ctor.args.is_none() => {
                let at = declared_at(cx, Namespace::Mesh, d)?;
                let mesh = cx.mesh(d);
                redone.relowered.meshes.push((at, mesh));
            }
            // Not an image: a normal map's warning reads only an image's encoding.
            Stmt::Decl(d) if d.kind == DeclKind::Texture && d.ctor.args.is_none() => {
                let at = declared_at(cx, Namespace::Texture, d)?;
                let texture = cx.texture(d);
                redone.relowered.textures.push((at, texture));
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

/// Whether the primary label of `d` starts inside `span`.
fn lies_in(d: &Diagnostic, span: Span) -> bool {
    let inside = |l: &crate::diag::Label| {
        l.span.file == span.file && (span.start..span.end).contains(&l.span.start)
    };
    d.primary.as_ref().is_some_and(inside)
}

/// Evaluates the `let` of `name` again: whether its value changed (`None`: decline). Its
/// diagnostics are left in `cx`. A value that fails (an error, or a constant it names that
/// failed) leaves the constant poisoned, as the check does: later names of it fail quietly.
/// That, and a constant poisoned before the edit, is taken only in a scene with no other
/// error (`clean`), and not when the value names an unknown constant (its did-you-mean would
/// list constants declared after it, which the check has not evaluated yet).
fn reevaluate(
    cx: &mut Checker,
    name: &crate::syntax::Ident,
    value: &Expr,
    clean: bool,
) -> Option<bool> {
    let old = match cx.lets.get(&name.name) {
        Some((old, at)) => (*at == name.span).then(|| Some(old.clone()))?,
        // Failed before: the first `let` of its name (another would be in the table).
        None if clean && cx.poisoned.contains(&name.name) => None,
        None => return None,
    };
    let overridden = cx.defines.contains_key(&name.name);
    if overridden || !names_only_earlier(cx, value, name.span.start) {
        return None;
    }
    let new = cx.eval(value);
    let unknown = |d: &Diagnostic| d.code == crate::diag::Code::CheckUnknownName;
    let failed = new.is_none() || old.is_none();
    if (failed && !clean) || cx.diags.iter().any(unknown) {
        return None;
    }
    // Bit for bit (`-0` is not `0` in the IR), not `==`.
    if format!("{new:?}") == format!("{old:?}") {
        return Some(false);
    }
    match new {
        Some(new) => {
            cx.poisoned.remove(&name.name);
            cx.lets.insert(&name.name, new, name.span);
        }
        None => {
            cx.lets.remove(&name.name);
            cx.poisoned.insert(name.name.clone());
        }
    }
    Some(true)
}

/// Whether every constant `e` names was declared before `before` (in the full check, a later
/// one is unknown to it), and `e` holds no array (read from the text by its own parser).
pub(super) fn names_only_earlier(cx: &Checker, e: &Expr, before: u32) -> bool {
    match &e.kind {
        ExprKind::Name(n) => cx.lets.get(n).is_none_or(|(_, at)| at.start < before),
        ExprKind::Paren(e) | ExprKind::Neg(e) => names_only_earlier(cx, e, before),
        ExprKind::Tuple(es) => es.iter().all(|e| names_only_earlier(cx, e, before)),
        ExprKind::Call(c) => c.args.iter().all(|e| names_only_earlier(cx, e, before)),
        ExprKind::Binary { lhs, rhs, .. } => {
            names_only_earlier(cx, lhs, before) && names_only_earlier(cx, rhs, before)
        }
        ExprKind::Array | ExprKind::Error => false,
        ExprKind::Number { .. } | ExprKind::HexColor(_) | ExprKind::Str(_) => true,
    }
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

/// Whether `new` may stand in for `old` in [`CheckMemo::recheck_decls`]: the same `let`,
/// `material`, (not `obj`) `mesh` or (not `image`) `texture` by name, or two `object`s.
fn same_declaration(old: &Stmt, new: &Stmt) -> bool {
    match (old, new) {
        (Stmt::Let { name: a, .. }, Stmt::Let { name: b, .. }) => a.name == b.name,
        (Stmt::Decl(a), Stmt::Decl(b)) => {
            let kind = matches!(
                a.kind,
                DeclKind::Material | DeclKind::Mesh | DeclKind::Texture
            );
            let not_obj = a.ctor.args.is_none() && b.ctor.args.is_none();
            kind && a.kind == b.kind && a.name.name == b.name.name && not_obj
        }
        (Stmt::Object(_), Stmt::Object(_)) => true,
        _ => false,
    }
}

/// `items`, one run per statement (`count` of its record long, in statement order), with the
/// runs of the statements in `new` (index → run) put in place of theirs and every other item
/// kept where `keep` (which moves its spans) allows; `None` when the counts do not add up or
/// `keep` refuses one.
fn merge_runs<T>(
    items: Vec<T>,
    records: &[StmtRecord],
    count: fn(&StmtRecord) -> u32,
    new: impl Iterator<Item = (usize, Vec<T>)>,
    mut keep: impl FnMut(&mut T) -> bool,
) -> Option<Vec<T>> {
    let mut out = Vec::with_capacity(items.len());
    let mut items = items.into_iter();
    let mut ok = true;
    let mut next = 0;
    let mut take = |n: usize, out: &mut Vec<T>, items: &mut std::vec::IntoIter<T>| {
        for mut item in items.by_ref().take(n) {
            ok &= keep(&mut item);
            out.push(item);
        }
    };
    for (i, run) in new {
        let before: usize = records
            .get(next..i)?
            .iter()
            .map(|r| count(r) as usize)
            .sum();
        let old = count(records.get(i)?) as usize;
        if items.len() < before + old {
            return None;
        }
        take(before, &mut out, &mut items);
        items.by_ref().take(old).for_each(drop);
        out.extend(run);
        next = i + 1;
    }
    let rest = items.len();
    take(rest, &mut out, &mut items);
    ok.then_some(out)
}
