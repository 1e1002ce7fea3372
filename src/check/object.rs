//! Stage 2, check: `object` and `group` statements → flattened `ir::Object`s in world space.
//!
//! Syntax: `object MESH { material NAME  transform { ... } }` places the mesh MESH (one mesh may
//! be placed many times; it is never copied). `group NAME { transform { ... }  object ... group
//! ... }` nests: an object's world matrix is `parent_group · ... · own transform`. Recursion depth
//! is bounded by the parser's nesting cap.

use glam::DMat4;

use super::names::Namespace;
use super::Checker;
use crate::diag::{Code, Diagnostic};
use crate::ir;
use crate::syntax::{Block, GroupStmt, Item, ObjectStmt, Stmt};

/// How many `object`s `stmts` place, nested ones included: the IR's object list is reserved
/// at once (80,000 placements would otherwise end in a list up to twice their size, and a copy
/// of half of it while it grows).
pub(super) fn count_objects(stmts: &[&Stmt]) -> usize {
    fn in_block(b: &Block) -> usize {
        b.items
            .iter()
            .map(|i| match i {
                Item::Object(_) => 1,
                Item::Group(g) => in_block(&g.body),
                Item::Value(_) | Item::Transform(_) => 0,
            })
            .sum()
    }
    stmts
        .iter()
        .map(|s| match s {
            Stmt::Object(_) => 1,
            Stmt::Group(g) => in_block(&g.body),
            _ => 0,
        })
        .sum()
}

impl Checker<'_> {
    /// Checks one top-level `object` or `group`; for an `object`, the mesh and material (table
    /// indices) it names, when they resolve.
    pub(super) fn placement(&mut self, stmt: &Stmt) -> (Option<usize>, Option<usize>) {
        match stmt {
            Stmt::Object(o) => self.object(o, DMat4::IDENTITY),
            Stmt::Group(g) => {
                self.group(g, DMat4::IDENTITY);
                (None, None)
            }
            _ => (None, None),
        }
    }

    fn object(&mut self, o: &ObjectStmt, parent: DMat4) -> (Option<usize>, Option<usize>) {
        let (mesh, material, object) = self.object_parts(o, parent);
        self.use_object(mesh, material);
        self.objects.extend(object);
        (mesh, material)
    }

    /// Counts a use of the mesh and the material an object named.
    pub(super) fn use_object(&mut self, mesh: Option<usize>, material: Option<usize>) {
        // The lists are empty in a pre-check (`early.rs`), which counts nothing.
        if let Some(m) = mesh.filter(|&m| m < self.mesh_uses.len()) {
            self.used_meshes[m] = true;
            self.mesh_uses[m] += 1;
        }
        if let Some(m) = material.filter(|&m| m < self.material_uses.len()) {
            self.used_materials[m] = true;
            self.material_uses[m] += 1;
        }
    }

    /// One `object` checked, without counting its uses: the mesh and the material (table
    /// indices) it names, when they resolve, and its IR object when nothing failed.
    pub(super) fn object_parts(
        &mut self,
        o: &ObjectStmt,
        parent: DMat4,
    ) -> (Option<usize>, Option<usize>, Option<ir::Object>) {
        let props = self.split(
            &o.body,
            "an object",
            super::vocabulary::OBJECT_KEYS,
            &[],
            &["transform"],
        );
        let local = self.transforms(&props.transforms, "an object");
        let mesh = self.resolve_ident(Namespace::Mesh, &o.mesh);
        let material = match props.get("material") {
            Some(p) => self
                .one(p, "material NAME")
                .and_then(|e| self.resolve(Namespace::Material, e)),
            None => {
                self.error(
                    Diagnostic::error(
                        Code::CheckMissingKey,
                        format!("object `{}` has no material", o.mesh.name),
                    )
                    .at(o.mesh.span, "no material")
                    .help("add `material NAME` inside the braces"),
                );
                None
            }
        };
        let object = match (mesh, material, local) {
            (Some(mesh), Some(material), Some(local)) => Some(ir::Object {
                mesh: mesh as u32,
                material: material as u32,
                world_from_object: parent * local,
                span: o.span,
            }),
            _ => None,
        };
        (mesh, material, object)
    }

    fn group(&mut self, g: &GroupStmt, parent: DMat4) {
        let _ = self.declare(Namespace::Group, &g.name.name, g.name.span);
        let props = self.split(
            &g.body,
            "a group",
            &[],
            &[],
            &["transform", "object", "group"],
        );
        let local = self
            .transforms(&props.transforms, "a group")
            .unwrap_or(DMat4::IDENTITY);
        let world = parent * local;
        for o in props.objects {
            let _ = self.object(o, world);
        }
        for child in props.groups {
            self.group(child, world);
        }
    }
}
