//! Stage 2, check, while parsing: top-level `let`s, `object`s, `group`s, `material`s and
//! `mesh`es checked as soon as they are parsed, so that their AST never accumulates (a
//! generated scene of 80,000 placements otherwise held ≈ 1 KB of AST per placement until the
//! placement phase, which runs last; docs/frontend-bench.md).
//!
//! The driver offers every top-level statement, in the order the full check will see them
//! (includes expanded in place), to a [`PreCheck`]. It evaluates the `let`s with the check's
//! own code (`Checker::let_stmt`, `--frame` and `--define` applied as the check applies them)
//! for as long as every one of them evaluates with no diagnostic: each such constant has the
//! value the full check gives it, bit for bit, since the check evaluates the same `let`s in
//! the same order from the same state, and no later `let` can change it (the first declaration
//! of a name wins; a later one is an error). From the first `let` with a diagnostic on (a
//! redefinition, an error in its value or in a `--define`, a reserved name), no more `let`s
//! are evaluated early: the check evaluates that one and the rest itself, after the constants
//! taken from here (a prefix of the `let`s, so its state is the same). Constants the pre-check
//! never evaluated are unknown to it, and so is any name declared after the statement that
//! uses it.
//!
//! It records the material, mesh and group names declared so far as the check's tables will
//! (first declaration wins, statement order) and checks each `object` and `group` with the
//! placement phase's own code against them and the constants. One whose check emits no
//! diagnostic named only declarations and constants written before it (an unknown name is a
//! diagnostic), so its result is exactly what the placement phase would compute: it is kept
//! in [`Placed`] (its IR objects with table indices, the group names it declared) and its AST
//! dropped. A `material` that is the first of its name and lowers with no diagnostic and no
//! texture, and a `mesh` that is the first of its name, not an `obj` (whose material overrides
//! name materials), and lowers with no diagnostic, are kept as their IR likewise. Every other
//! statement goes on to the check as before (a forward reference, an error: their diagnostics
//! are the full check's). The check then takes the constants, declares the kept names and takes
//! the kept results in statement order among the others (`Checker::run`, `early/placed.rs`).

mod placed;

pub use placed::Placed;
pub(super) use placed::{kept_indices, merge_lowered, Undeclared};

use std::collections::HashMap;

use super::names::{Namespace, Table};
use super::Checker;
use crate::source::SourceMap;
use crate::syntax::{DeclKind, Expr, Stmt};
use placed::{Lowered, PlacedStmt};

/// The names a parse has declared so far, its constants, and what it placed and lowered.
#[derive(Debug, Default)]
pub struct PreCheck {
    frame: f64,
    /// The material, mesh and group tables are filled.
    tables: [Table; 6],
    /// The constants evaluated so far (the check's `lets` after the same `let`s).
    lets: super::Constants,
    /// `--define NAME=VALUE`: the value's expression, and whether a `let` used it.
    defines: HashMap<String, (Expr, bool)>,
    /// No more `let`s are evaluated here (one had a diagnostic, or a `--define` did not parse).
    lets_closed: bool,
    /// Top-level statements offered so far.
    offered: usize,
    placed: Placed,
}

impl PreCheck {
    /// A pre-check for a compile with the predefined constant `frame` and the `--define`s
    /// `defines` (name and value expression, as the check gets them; `defines_ok`: every
    /// define parsed with no diagnostic, else no `let` is evaluated early). Only their values
    /// are used here, never their spans' text.
    pub fn new(frame: f64, defines: Vec<(String, Expr)>, defines_ok: bool) -> PreCheck {
        PreCheck {
            frame,
            defines: defines.into_iter().map(|(n, e)| (n, (e, false))).collect(),
            lets_closed: !defines_ok,
            ..PreCheck::default()
        }
    }

    /// Room for more placed objects, `let`s, materials, meshes and groups (the driver counts
    /// their words in each file, so each list is allocated once instead of doubling).
    pub fn reserve(&mut self, objects: usize, lets: usize, decls: [usize; 3]) {
        let [materials, meshes, groups] = decls;
        self.placed.objects.reserve_exact(objects);
        self.placed.decls.lets.reserve_exact(lets);
        self.placed.decls.materials.reserve_exact(materials);
        self.placed.decls.meshes.reserve_exact(meshes);
        self.placed.group_names.reserve_exact(groups);
        self.lets.reserve(lets);
        self.tables[Namespace::Material as usize].reserve(materials);
        self.tables[Namespace::Mesh as usize].reserve(meshes);
        self.tables[Namespace::Group as usize].reserve(groups);
    }

    /// Takes the next top-level statement: `None` when it was placed or lowered (its AST is
    /// dropped), else the statement back, for the check.
    pub fn offer(&mut self, sources: &SourceMap, stmt: Stmt) -> Option<Stmt> {
        let index = self.offered as u32;
        self.offered += 1;
        let mut cx = Checker::new(sources);
        cx.frame = self.frame;
        cx.lets = std::mem::take(&mut self.lets);
        let kept = self.check(&mut cx, index, stmt);
        self.lets = std::mem::take(&mut cx.lets);
        kept
    }

    /// [`PreCheck::offer`] with the constants in `cx`.
    fn check(&mut self, cx: &mut Checker, index: u32, stmt: Stmt) -> Option<Stmt> {
        let decls = &mut self.placed.decls;
        match &stmt {
            Stmt::Let { name, value, span } if !self.lets_closed => {
                cx.defines = std::mem::take(&mut self.defines);
                cx.let_stmt(name, value);
                self.defines = std::mem::take(&mut cx.defines);
                if !cx.diags.is_empty() || !cx.poisoned.is_empty() {
                    // The check evaluates this `let` and every later one itself.
                    self.lets_closed = true;
                    if cx
                        .lets
                        .get(&name.name)
                        .is_some_and(|(_, at)| *at == name.span)
                    {
                        cx.lets.remove(&name.name);
                    }
                    return Some(stmt);
                }
                decls.lets.push((index, *span));
                None
            }
            Stmt::Decl(d) if d.kind == DeclKind::Material => {
                let table = &mut self.tables[Namespace::Material as usize];
                if table.declare(&d.name.name, d.name.span).is_some() {
                    return Some(stmt);
                }
                match cx.material(d) {
                    (Some(material), textures) if cx.diags.is_empty() && textures.is_empty() => {
                        decls.materials.push(Lowered {
                            at: index,
                            span: stmt.span(),
                            value: material,
                        });
                        None
                    }
                    _ => Some(stmt),
                }
            }
            Stmt::Decl(d) if d.kind == DeclKind::Mesh => {
                let table = &mut self.tables[Namespace::Mesh as usize];
                let first = table.declare(&d.name.name, d.name.span).is_none();
                if !first || d.ctor.args.is_some() {
                    // A duplicate, or `obj(...)` (or a kind written with arguments: an error).
                    return Some(stmt);
                }
                match cx.mesh(d) {
                    Some(mesh) if cx.diags.is_empty() => {
                        decls.meshes.push(Lowered {
                            at: index,
                            span: stmt.span(),
                            value: mesh,
                        });
                        None
                    }
                    _ => Some(stmt),
                }
            }
            Stmt::Object(_) | Stmt::Group(_) => self.place(cx, index, stmt),
            _ => Some(stmt),
        }
    }

    /// Checks a top-level `object` or `group`: `None` when it was placed.
    fn place(&mut self, cx: &mut Checker, index: u32, stmt: Stmt) -> Option<Stmt> {
        // Swapped in and out (the checker's own are empty): no tables made per statement.
        std::mem::swap(&mut cx.tables, &mut self.tables);
        let names_before = cx.tables[Namespace::Group as usize].spans.len();
        // Not counted: the pre-check has no use lists (the placement phase counts them).
        let _ = cx.placement(&stmt);
        std::mem::swap(&mut cx.tables, &mut self.tables);
        let failed =
            !cx.diags.is_empty() || matches!(stmt, Stmt::Object(_)) && cx.objects.is_empty();
        if failed {
            // Its names (a group's) stay declared, as the placement phase will declare them.
            return Some(stmt);
        }
        let names = &self.tables[Namespace::Group as usize].spans[names_before..];
        let placed = &mut self.placed;
        placed.stmts.push(PlacedStmt {
            at: index,
            objects: cx.objects.len() as u32,
            names: names.len() as u32,
        });
        if !names.is_empty() {
            placed.group_spans.push(stmt.span());
        }
        placed.group_names.extend_from_slice(names);
        placed.objects.append(&mut cx.objects);
        None
    }

    /// What was placed and lowered, with the constants evaluated (the tables are dropped).
    pub fn into_placed(self) -> Placed {
        let mut placed = self.placed;
        // Lists reserved by counting words may have room to spare (`object` in a comment).
        placed.stmts.shrink_to_fit();
        placed.objects.shrink_to_fit();
        placed.group_names.shrink_to_fit();
        placed.group_spans.shrink_to_fit();
        placed.decls.constants = self.lets;
        placed.decls.defines_used = (self.defines.into_iter())
            .filter_map(|(name, (_, used))| used.then_some(name))
            .collect();
        placed
    }
}
