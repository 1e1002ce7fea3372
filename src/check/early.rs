//! Stage 2, check, while parsing: top-level `object`s, `group`s and `material`s checked as
//! soon as they are parsed, so that their AST never accumulates (a generated scene of 80,000
//! placements otherwise held ≈ 1 KB of AST per placement until the placement phase, which runs
//! last; docs/frontend-bench.md).
//!
//! The driver offers every top-level statement, in the order the full check will see them
//! (includes expanded in place), to a [`PreCheck`]. It records the material, mesh and group
//! names declared so far as the check's tables will (first declaration wins, statement order)
//! and checks each `object` and `group` with the placement phase's own code against them, with
//! no constants at all. One whose check emits no diagnostic named only declarations written
//! before it and no constant (an unknown name is a diagnostic), so its result is exactly what
//! the placement phase would compute: it is kept in [`Placed`] (its IR objects with table
//! indices, the group names it declared) and its AST dropped. A `material` that is the first of
//! its name and lowers with no diagnostic and no texture is kept as its IR material likewise.
//! Every other statement goes on to the check as before (a forward reference, a constant, an
//! error: their diagnostics are the full check's). The check then declares the kept names and
//! takes the kept results in statement order among the others (`Checker::run`,
//! [`Checker::placements`]).

use super::names::{Namespace, Table};
use super::object::count_objects;
use super::{Checker, StmtRecord};
use crate::ir;
use crate::source::{SourceMap, Span};
use crate::syntax::{DeclKind, Stmt};

/// Top-level placements checked while parsing, in statement order.
#[derive(Debug, Default)]
pub struct Placed {
    /// One per placed statement, in order.
    stmts: Vec<PlacedStmt>,
    /// Their IR objects (mesh and material as table indices), in order.
    objects: Vec<ir::Object>,
    /// The names the placed `group`s declare (each group's, then its nested ones'), in order.
    group_names: Vec<Span>,
    /// The placed `group` statements' spans, in order.
    group_spans: Vec<Span>,
    /// Materials lowered while parsing, in order.
    materials: Vec<PlacedMaterial>,
}

/// A `material` declaration lowered while parsing.
#[derive(Debug)]
pub(super) struct PlacedMaterial {
    /// Its index among all top-level statements.
    pub at: u32,
    /// The whole statement.
    pub span: Span,
    /// The material (`name` and `span` are the declared name's, as in the check's table).
    pub material: ir::Material,
}

/// One statement of [`Placed`].
#[derive(Debug, Clone, Copy)]
struct PlacedStmt {
    /// Its index among all top-level statements (those kept and those placed).
    at: u32,
    /// How many objects it placed (an `object`: one).
    objects: u32,
    /// How many group names it declared (an `object`: none; a group: at least its own).
    names: u32,
}

impl Placed {
    /// How many statements were placed (or lowered).
    pub fn len(&self) -> usize {
        self.stmts.len() + self.materials.len()
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
        places.extend(self.materials.iter().map(|m| (m.at as usize, m.span)));
        places.sort_unstable_by_key(|&(at, _)| at);
        places
    }

    /// The materials lowered while parsing; the rest.
    pub(super) fn take_materials(mut self) -> (Vec<PlacedMaterial>, Placed) {
        (std::mem::take(&mut self.materials), self)
    }
}

/// The names a parse has declared so far, and the placements it checked.
#[derive(Debug, Default)]
pub struct PreCheck {
    frame: f64,
    /// The material, mesh and group tables are filled.
    tables: [Table; 6],
    /// Top-level statements offered so far.
    offered: usize,
    placed: Placed,
}

impl PreCheck {
    /// A pre-check for a compile with the predefined constant `frame`.
    pub fn new(frame: f64) -> PreCheck {
        PreCheck {
            frame,
            ..PreCheck::default()
        }
    }

    /// Room for `n` more placed objects (the driver counts `object` words in each file, so
    /// the list is allocated once instead of doubling).
    pub fn reserve(&mut self, objects: usize, materials: usize) {
        self.placed.objects.reserve_exact(objects);
        self.placed.materials.reserve_exact(materials);
    }

    /// Takes the next top-level statement: `None` when it was placed (its AST is dropped),
    /// else the statement back, for the check.
    pub fn offer(&mut self, sources: &SourceMap, stmt: Stmt) -> Option<Stmt> {
        let index = self.offered as u32;
        self.offered += 1;
        match &stmt {
            Stmt::Decl(d) if d.kind == DeclKind::Material => {
                let table = &mut self.tables[Namespace::Material as usize];
                if table.declare(&d.name.name, d.name.span).is_some() {
                    return Some(stmt);
                }
                let mut cx = Checker::new(sources);
                cx.frame = self.frame;
                let (material, textures) = cx.material(d);
                return match material {
                    Some(material) if cx.diags.is_empty() && textures.is_empty() => {
                        let span = stmt.span();
                        let at = index;
                        self.placed
                            .materials
                            .push(PlacedMaterial { at, span, material });
                        None
                    }
                    _ => Some(stmt),
                };
            }
            Stmt::Decl(d) if d.kind == DeclKind::Mesh => {
                let _ = self.tables[Namespace::Mesh as usize].declare(&d.name.name, d.name.span);
                return Some(stmt);
            }
            Stmt::Object(_) | Stmt::Group(_) => {}
            _ => return Some(stmt),
        }
        let mut cx = Checker::new(sources);
        cx.frame = self.frame;
        cx.tables = std::mem::take(&mut self.tables);
        let names_before = cx.tables[Namespace::Group as usize].spans.len();
        // Not counted: the pre-check has no use lists (the placement phase counts them).
        let _ = cx.placement(&stmt);
        self.tables = std::mem::take(&mut cx.tables);
        let failed =
            !cx.diags.is_empty() || matches!(stmt, Stmt::Object(_)) && cx.objects.is_empty();
        if failed {
            // Its names (a group's) stay declared, as the placement phase will declare them.
            return Some(stmt);
        }
        let names = &self.tables[Namespace::Group as usize].spans[names_before..];
        self.placed.stmts.push(PlacedStmt {
            at: index,
            objects: cx.objects.len() as u32,
            names: names.len() as u32,
        });
        if !names.is_empty() {
            self.placed.group_spans.push(stmt.span());
        }
        self.placed.group_names.extend_from_slice(names);
        self.placed.objects.append(&mut cx.objects);
        None
    }

    /// What was placed (the tables are dropped).
    pub fn into_placed(self) -> Placed {
        self.placed
    }
}

/// The index among all `total` statements of each statement not placed (ascending).
pub(super) fn kept_indices(placed: &Placed, total: usize) -> impl Iterator<Item = usize> + '_ {
    let mut stmts = placed.stmts.iter().map(|p| p.at).peekable();
    let mut materials = placed.materials.iter().map(|m| m.at).peekable();
    (0..total).filter(move |&i| {
        let i = i as u32;
        stmts.next_if_eq(&i).is_none() & materials.next_if_eq(&i).is_none()
    })
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
    pub(super) fn placements(
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
            // Usually every placement was placed: the list becomes the IR's as it is.
            self.objects = objects;
            self.count_placed(&stmts, 0, &group_names, records);
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
    /// their groups' names (`names`, in order) and records each (with `records`).
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
            for &span in &names[n..n + s.names as usize] {
                let _ = self
                    .table(Namespace::Group)
                    .declare(sources.snippet(span), span);
            }
            let record = match (s.names, self.objects.get(o)) {
                (0, Some(object)) => StmtRecord {
                    object: true,
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
