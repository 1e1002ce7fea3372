//! Stage 2, check: what the pre-check ([`super::PreCheck`]) took while parsing — top-level
//! placements checked and declarations lowered, each with its place among all statements — and
//! how the check puts them back in statement order: the constants first (they are a prefix of
//! the `let`s), the lowered declarations' names among the others' as the first loop declares
//! them, their IR in the lowering phases, and the placed objects in the placement phase.

use super::super::names::Namespace;
use super::super::object::count_objects;
use super::super::{Checker, StmtRecord};
use crate::ir;
use crate::source::Span;
use crate::syntax::{Decl, Stmt};

/// Top-level statements the pre-check took while parsing, in statement order.
#[derive(Debug, Default)]
pub struct Placed {
    /// One per placed `object` or `group`, in order.
    pub(super) stmts: Vec<PlacedStmt>,
    /// Their IR objects (mesh and material as table indices), in order.
    pub(super) objects: Vec<ir::Object>,
    /// The names the placed `group`s declare (each group's, then its nested ones'), in order.
    pub(super) group_names: Vec<Span>,
    /// The placed `group` statements' spans, in order.
    pub(super) group_spans: Vec<Span>,
    /// Declarations lowered while parsing.
    pub(super) decls: LoweredDecls,
}

/// Declarations lowered while parsing.
#[derive(Debug, Default)]
pub(in crate::check) struct LoweredDecls {
    /// The `let`s evaluated, each with its index among all statements and its span: every
    /// `let` before the first one the pre-check could not evaluate as the check will.
    pub lets: Vec<(u32, Span)>,
    /// Their constants, as the check's `lets` holds them after the last of them.
    pub constants: crate::check::Constants,
    /// The `--define`s they used (by name).
    pub defines_used: Vec<String>,
    /// `material`s lowered (each the first of its name, no diagnostic, no texture).
    pub materials: Vec<Lowered<ir::Material>>,
    /// `mesh`es lowered (each the first of its name, no diagnostic, not an `obj`).
    pub meshes: Vec<Lowered<ir::Mesh>>,
}

/// A declaration lowered while parsing.
#[derive(Debug)]
pub(in crate::check) struct Lowered<T> {
    /// Its index among all top-level statements.
    pub at: u32,
    /// The whole statement.
    pub span: Span,
    /// Its IR (`name` and `span` are the declared name's, as in the check's table).
    pub value: T,
}

/// One placed statement of [`Placed`].
#[derive(Debug, Clone, Copy)]
pub(super) struct PlacedStmt {
    /// Its index among all top-level statements (those kept and those placed).
    pub at: u32,
    /// How many objects it placed (an `object`: one).
    pub objects: u32,
    /// How many group names it declared (an `object`: none; a group: at least its own).
    pub names: u32,
}

impl Placed {
    /// How many statements were placed (or lowered).
    pub fn len(&self) -> usize {
        let d = &self.decls;
        self.stmts.len() + d.lets.len() + d.materials.len() + d.meshes.len()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The index among all statements of each placed (or lowered) one, and its span, in order.
    pub fn places(&self) -> Vec<(usize, Span)> {
        let (mut objects, mut groups) = (0, 0);
        let mut places: Vec<(usize, Span)> = self
            .stmts
            .iter()
            .filter_map(|p| {
                let span = if p.names == 0 {
                    self.objects.get(objects)?.span
                } else {
                    groups += 1;
                    *self.group_spans.get(groups - 1)?
                };
                objects += p.objects as usize;
                Some((p.at as usize, span))
            })
            .collect();
        let d = &self.decls;
        places.extend(d.lets.iter().map(|&(at, span)| (at as usize, span)));
        places.extend(d.materials.iter().map(|m| (m.at as usize, m.span)));
        places.extend(d.meshes.iter().map(|m| (m.at as usize, m.span)));
        places.sort_unstable_by_key(|&(at, _)| at);
        places
    }

    /// The declarations lowered while parsing; the rest.
    pub(in crate::check) fn take_decls(mut self) -> (LoweredDecls, Placed) {
        (std::mem::take(&mut self.decls), self)
    }
}

/// The index among all `total` statements of each statement not placed (ascending).
pub(in crate::check) fn kept_indices(placed: &Placed, total: usize) -> Vec<usize> {
    let mut taken = vec![false; total];
    let d = &placed.decls;
    let at = (placed.stmts.iter().map(|p| p.at))
        .chain(d.lets.iter().map(|&(at, _)| at))
        .chain(d.materials.iter().map(|m| m.at))
        .chain(d.meshes.iter().map(|m| m.at));
    for at in at {
        if let Some(t) = taken.get_mut(at as usize) {
            *t = true;
        }
    }
    (0..total).filter(|&i| !taken[i]).collect()
}

/// The IR of one namespace's declarations in table order: the lowered ones (`lowered`, in
/// order) where `decls` holds `None`, `lower`'s (given the position) for the others. When
/// every one was lowered (the usual case), the list of them becomes it where it lies.
pub(in crate::check) fn merge_lowered<T>(
    lowered: Vec<Lowered<T>>,
    decls: &[Option<&Decl>],
    mut lower: impl FnMut(usize, &Decl) -> Option<T>,
) -> Vec<Option<T>> {
    if decls.iter().all(Option::is_none) {
        return lowered.into_iter().map(|l| Some(l.value)).collect();
    }
    let mut lowered = lowered.into_iter();
    let mut out = Vec::with_capacity(decls.len());
    for (i, d) in decls.iter().enumerate() {
        out.push(match d {
            Some(d) => lower(i, d),
            None => lowered.next().map(|l| l.value),
        });
    }
    out
}

/// The lowered declarations whose names are not declared yet (indices into their lists).
#[derive(Debug, Default)]
pub(in crate::check) struct Undeclared {
    materials: usize,
    meshes: usize,
}

impl Checker<'_> {
    /// Starts the check with the constants the pre-check evaluated (all before any `let` the
    /// check evaluates itself, so this is the state the check reaches after them).
    pub(in crate::check) fn take_constants(&mut self, decls: &mut LoweredDecls) {
        self.lets = std::mem::take(&mut decls.constants);
        for name in std::mem::take(&mut decls.defines_used) {
            if let Some((_, used)) = self.defines.get_mut(&name) {
                *used = true;
            }
        }
    }

    /// Declares the names of the lowered declarations before statement `before` (as the first
    /// loop declares a kept one's), each with `None` in its namespace's list of declarations.
    /// None is a duplicate: each was the first of its name when the pre-check saw it.
    pub(in crate::check) fn declare_lowered(
        &mut self,
        decls: &LoweredDecls,
        next: &mut Undeclared,
        before: usize,
        lists: &mut [Vec<Option<&Decl>>; 4],
    ) {
        while let Some(m) = decls.materials.get(next.materials) {
            if m.at as usize >= before {
                break;
            }
            self.declare(Namespace::Material, &m.value.name, m.value.span);
            lists[Namespace::Material as usize].push(None);
            next.materials += 1;
        }
        while let Some(m) = decls.meshes.get(next.meshes) {
            if m.at as usize >= before {
                break;
            }
            self.declare(Namespace::Mesh, &m.value.name, m.value.span);
            lists[Namespace::Mesh as usize].push(None);
            next.meshes += 1;
        }
    }
}

/// The placed statements not yet put into the placement phase.
struct Pending {
    stmts: std::iter::Peekable<std::vec::IntoIter<PlacedStmt>>,
    objects: std::vec::IntoIter<ir::Object>,
    names: std::vec::IntoIter<Span>,
}

impl Checker<'_> {
    /// The placement phase: `placements` (statement index and statement: every `object` and
    /// `group` not placed) checked, and `placed` put among them, in statement order.
    pub(in crate::check) fn placements(
        &mut self,
        placements: Vec<(usize, &Stmt)>,
        placed: Placed,
        mut records: Option<&mut Vec<StmtRecord>>,
    ) {
        let Placed {
            stmts,
            objects,
            group_names,
            ..
        } = placed;
        if placements.is_empty() && self.objects.is_empty() {
            // Usually every placement was placed: the list becomes the IR's as it is. The
            // group names are declared only for a memo: nothing else reads them any more.
            self.objects = objects;
            let names = if records.is_some() {
                &group_names[..]
            } else {
                &[]
            };
            self.count_placed(&stmts, 0, names, records);
            return;
        }
        let deferred: Vec<&Stmt> = placements.iter().map(|(_, s)| *s).collect();
        self.objects
            .reserve_exact(count_objects(&deferred) + objects.len());
        drop(deferred);
        let mut pending = Pending {
            stmts: stmts.into_iter().peekable(),
            objects: objects.into_iter(),
            names: group_names.into_iter(),
        };
        for (i, stmt) in placements {
            self.put_placed(&mut pending, i, records.as_deref_mut());
            let (diags, objects) = (self.diags.len(), self.objects.len());
            let (mesh, material) = self.placement(stmt);
            if let Some(record) = records.as_mut().and_then(|r| r.get_mut(i)) {
                *record = StmtRecord {
                    object: matches!(stmt, Stmt::Object(_)),
                    setting: false,
                    diags: (self.diags.len() - diags) as u32,
                    objects: (self.objects.len() - objects) as u32,
                    mesh: mesh.map(|m| m as u32),
                    material: material.map(|m| m as u32),
                };
            }
        }
        self.put_placed(&mut pending, usize::MAX, records);
    }

    /// Puts the pending placed statements before statement `before` into the IR.
    fn put_placed(
        &mut self,
        p: &mut Pending,
        before: usize,
        records: Option<&mut Vec<StmtRecord>>,
    ) {
        let from = self.objects.len();
        let mut stmts = Vec::new();
        let mut names = Vec::new();
        while let Some(s) = p.stmts.next_if(|s| (s.at as usize) < before) {
            self.objects
                .extend(p.objects.by_ref().take(s.objects as usize));
            names.extend(p.names.by_ref().take(s.names as usize));
            stmts.push(s);
        }
        self.count_placed(&stmts, from, &names, records);
    }

    /// Counts the uses of placed statements' objects (from `self.objects[from..]`), declares
    /// their groups' names (`names`, in order, if given) and records each (with `records`).
    fn count_placed(
        &mut self,
        stmts: &[PlacedStmt],
        from: usize,
        names: &[Span],
        mut records: Option<&mut Vec<StmtRecord>>,
    ) {
        let sources = self.sources;
        let (mut o, mut n) = (from, 0);
        for s in stmts {
            let objects = o..o + s.objects as usize;
            for k in objects.clone() {
                let (mesh, material) = (self.objects[k].mesh, self.objects[k].material);
                self.use_object(Some(mesh as usize), Some(material as usize));
            }
            for &span in names.get(n..n + s.names as usize).unwrap_or_default() {
                let _ = self
                    .table(Namespace::Group)
                    .declare(sources.snippet(span), span);
            }
            let record = match (s.names, self.objects.get(o)) {
                (0, Some(object)) => StmtRecord {
                    object: true,
                    setting: false,
                    diags: 0,
                    objects: 1,
                    mesh: Some(object.mesh),
                    material: Some(object.material),
                },
                _ => StmtRecord {
                    objects: s.objects,
                    ..StmtRecord::default()
                },
            };
            if let Some(r) = records.as_mut().and_then(|r| r.get_mut(s.at as usize)) {
                *r = record;
            }
            (o, n) = (objects.end, n + s.names as usize);
        }
    }
}
