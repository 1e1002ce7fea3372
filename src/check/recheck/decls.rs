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
//! An `obj` mesh and an `image` texture are declarations like the others here (2026-11-26,
//! fifth session): the check reads no file (the path is resolved against the scene's
//! directory; the build loads and caches the file by path and content hash), so their IR is a
//! function of their text. An `obj` mesh's `material` overrides name materials and make them
//! used: a mesh the IR holds with any (before or after the edit) is put in by a re-compaction
//! ([`super::compact`], which maps them back by table index; sixth session). A normal map's
//! sRGB warning reads more than the declaration's own IR, and declines: it reads
//! whether the texture it names is an image decoded as sRGB: a texture whose answer changes
//! is declined when a material that names it has a `normal_map`
//! ([`CheckMemo::normal_maps_unchanged`]). Their IR holds a span in the declaration's value
//! (the file name): the old entries' spans are cleared before the others move
//! ([`CheckMemo::splice_decls`]), since they are replaced.
//!
//! Why the result is the full check's: a re-checked `let` with an unknown name, or that fails
//! (or failed) while another error stands, a renamed
//! statement, a redeclaration (not the first of its name), a material with a normal map (its warning reads the texture's IR), a `let` that a
//! `--define` overrides or that names a constant declared after it, and a constant named by
//! any other kind of statement (a camera, a light, the render block) make it decline. A `group`
//! that names a changed constant is checked again as an edited group is ([`super::groups`]:
//! its names kept in the group table, its uses of meshes and materials the same as before).
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
//!
//! This file decides whether an edit is one of these; the statements are checked again in
//! [`super::redo`] (a `let`'s value in [`super::reevaluate`]) and put in place in
//! [`super::splice_decls`].

use std::collections::BTreeMap;
use std::ops::Range;

use super::super::names::Namespace;
use super::super::StmtRecord;
use super::compact::Relowered;
use super::redo::{names_a_normal_map, redo};
use super::reevaluate::Failing;
use super::renamed::renamed;
use super::CheckMemo;
use crate::diag::Diagnostic;
use crate::ir;
use crate::source::{Shift, SourceMap, Span};
use crate::syntax::{DeclKind, Stmt};

/// What the re-check reads of the new text beyond the edited statements, found by the compile
/// (which keeps the statements' byte ranges): what names a name, and a statement by its place.
pub trait Dependents {
    /// The statements of the new text that name `name` (index among all top-level statements,
    /// and the statement parsed), in order; `None` when one cannot be parsed alone. It may
    /// give more than those that name it (a word in a comment or a string): those are checked
    /// again too.
    fn naming(&mut self, name: &str) -> Option<Vec<(usize, Stmt)>>;
    /// Top-level statement `i` of the new text (its index among all), parsed alone; `None`
    /// when it cannot be.
    fn statement(&mut self, i: usize) -> Option<Stmt>;
}

/// What a re-check of declarations and objects produced.
#[derive(Default)]
pub(super) struct Redone {
    /// Per `object` statement checked again: its record, diagnostics and IR objects.
    pub(super) objects: BTreeMap<usize, (StmtRecord, Vec<Diagnostic>, Vec<ir::Object>)>,
    /// Materials, meshes and textures lowered again.
    pub(super) relowered: Relowered,
    /// Materials that now refer to other textures: (material, texture table indices).
    pub(super) material_textures: Vec<(u32, Vec<usize>)>,
    /// The diagnostics of the declarations checked again (before the placement phase), and
    /// those declarations' spans (in the new text).
    pub(super) early: Vec<Diagnostic>,
    pub(super) early_spans: Vec<Span>,
    /// The `group`s checked again (they name a changed constant): their spans.
    pub(super) group_spans: Vec<Span>,
    /// Statements checked again.
    pub(super) checked: usize,
    /// The declaration renamed, if one was (namespace and table index): the IR is compacted
    /// again (its unused warning names it).
    pub(super) renamed: Option<(Namespace, usize)>,
    /// The cameras, lights and render block that name a changed constant (new text).
    pub(super) settings: Vec<Stmt>,
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
        dependents: &mut dyn Dependents,
    ) -> Option<usize> {
        let same = old_stmts.len() == new.len() && old.len() == new.len();
        if !same || self.records.len() < old.end {
            return None;
        }
        if super::lets::renamed_let(old_stmts, &new) {
            return self.rename_let(sources, old, old_stmts, &new, shift, dependents);
        }
        let rename = match (old_stmts, &new[..]) {
            ([o], [n]) => renamed(o, n),
            _ => None,
        };
        let same_names = (old_stmts.iter().zip(&new)).all(|(o, n)| same_declaration(o, n));
        if rename.is_none() && !same_names {
            return None;
        }
        // A renamed declaration: its table entry takes the new name, and what reads either
        // name is checked again.
        let mut changed = BTreeMap::new();
        let mut renamed_at = None;
        let mut renaming = None;
        if let Some((ns, was, now)) = rename {
            let at = self.rename_entry(ns, was, now)?;
            let names = [was.name.as_str(), now.name.as_str()];
            changed = self.rename_dependents(sources, ns, &names, shift, dependents)?;
            renamed_at = Some((ns, at, now.span));
            renaming = Some((ns, at, was.name.as_str().to_owned()));
        }
        // The old statements' own diagnostics go (their spans lie in the old text), then the
        // names and constants move to the new text: the re-check reports against them.
        let old_spans: Vec<Span> = old_stmts.iter().map(Stmt::span).collect();
        self.drop_early(&old_spans);
        if !self.shift_names(shift) {
            return None;
        }
        if let Some((ns, at, span)) = renamed_at {
            *self.tables[ns as usize].spans.get_mut(at)? = span;
        }
        let was_used = (self.used_meshes(), self.used_materials());
        changed.extend((old.start..).zip(new));
        let mut cx = self.lend(sources);
        let textures = &self.material_textures;
        // A `let` may come to have a diagnostic, or lose one, only when no other error stands
        // (an unknown name's did-you-mean lists the constants, which such an edit changes).
        let failing = match self.diagnostics.iter().any(Diagnostic::is_error) {
            true => Failing::Declined,
            false => Failing::Clean,
        };
        let records = &self.records;
        let redone = redo(
            &mut cx,
            changed,
            records,
            textures,
            failing,
            dependents,
            renaming,
            &[],
        );
        self.take_back(&mut cx);
        let mut redone = redone?;
        self.normal_maps_unchanged(&redone.relowered.textures, dependents)?;
        redone.renamed = renamed_at.map(|(ns, at, _)| (ns, at));
        let used_changed = was_used != (self.used_meshes(), self.used_materials());
        let settings = self.settings_named(sources, &mut redone, false, dependents)?;
        self.splice_decls(sources, redone, shift, used_changed, settings)
    }
}

impl CheckMemo {
    /// `Some` when no material's normal-map warning changes with the textures `relowered`
    /// (table index, new IR): the warning reads only whether a texture is an image decoded as
    /// sRGB, so a texture whose answer stays needs nothing; one whose answer changes is taken
    /// only when no material that names it (whole-word search) has a `normal_map`.
    pub(super) fn normal_maps_unchanged(
        &self,
        relowered: &[(usize, Option<ir::Texture>)],
        dependents: &mut dyn Dependents,
    ) -> Option<()> {
        let scene = self.scene.as_ref()?;
        for (at, new) in relowered {
            let old = match self.texture_map.get(*at).copied().flatten() {
                Some(k) => scene.textures.get(k as usize),
                None => (self.dropped.textures.iter())
                    .find(|(i, _)| *i as usize == *at)
                    .map(|(_, t)| t),
            };
            if srgb_image(old) == srgb_image(new.as_ref()) {
                continue;
            }
            let name = self.tables[Namespace::Texture as usize].name(*at);
            let normal_map = |(_, s): &(usize, Stmt)| matches!(s, Stmt::Decl(d) if d.kind == DeclKind::Material && names_a_normal_map(d));
            if dependents.naming(name)?.iter().any(normal_map) {
                return None;
            }
        }
        Some(())
    }
}

/// Whether `t` is an image texture decoded as sRGB (what a normal map's warning reads).
fn srgb_image(t: Option<&ir::Texture>) -> bool {
    matches!(
        t,
        Some(ir::Texture {
            source: ir::TextureSource::Image {
                encoding: ir::TextureEncoding::Srgb,
                ..
            },
            ..
        })
    )
}

/// Whether `new` may stand in for `old` in [`CheckMemo::recheck_decls`]: the same `let`,
/// `material`, `mesh` (an `obj` one with material overrides too) or `texture` by name, or two
/// `object`s.
fn same_declaration(old: &Stmt, new: &Stmt) -> bool {
    match (old, new) {
        (Stmt::Let { name: a, .. }, Stmt::Let { name: b, .. }) => a.name == b.name,
        (Stmt::Decl(a), Stmt::Decl(b)) => {
            let kind = matches!(
                a.kind,
                DeclKind::Material | DeclKind::Mesh | DeclKind::Texture
            );
            kind && a.kind == b.kind && a.name.name == b.name.name
        }
        (Stmt::Object(_), Stmt::Object(_)) => true,
        _ => false,
    }
}
