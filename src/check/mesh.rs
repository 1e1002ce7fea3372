//! Stage 2, check: `mesh NAME = ...` → `ir::Mesh`.
//!
//! Syntax: `mesh tall = obj("meshes/tall.obj")`; `mesh tri = inline { positions [(0,0,0)
//! (1,0,0) (0,1,0)]  normals [...]  uvs [(0,0) (1,0) (0,1)]  indices [0 1 2] }`;
//! `mesh ball = sphere { radius 1  segments 48 }` (defaults 1 and 32; segments 3..=4096);
//! `mesh gem = icosphere { subdivisions 5  radius 1 }` (see `icosphere.rs`);
//! `mesh floor = quad { size (2, 2) }` (xz-plane facing +y; default 1 × 1);
//! `mesh crate = box { size (1, 1, 1) }` (default unit cube). A number for `size` means all sides.
//! Triangles are front-facing where their winding is counter-clockwise seen from the front:
//! normal = (p1 − p0) × (p2 − p0).

use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::syntax::{Block, Decl, Expr, ExprKind};

use super::vocabulary::{MeshKind, Word, MESH_KINDS as KINDS};

impl Checker<'_> {
    pub(super) fn mesh(&mut self, d: &Decl) -> Option<ir::Mesh> {
        let empty = Block {
            items: Vec::new(),
            span: d.span,
        };
        let body = d.body.as_ref().unwrap_or(&empty);
        let mut obj = ir::ObjOptions::default();
        let name = d.ctor.name.name.as_str();
        let source = match (MeshKind::from_word(name), &d.ctor.args) {
            (Some(MeshKind::Obj), Some(args)) => {
                obj = self.obj_options(body);
                ir::MeshSource::Obj(Box::new(self.obj_file(args, d)?))
            }
            (Some(MeshKind::Inline), None) => {
                ir::MeshSource::Inline(Box::new(self.inline_mesh(body, d.name.span)?))
            }
            (Some(MeshKind::Sphere), None) => ir::MeshSource::Builtin(self.sphere(body)?),
            (Some(MeshKind::Icosphere), None) => ir::MeshSource::Builtin(self.icosphere(body)?),
            (Some(MeshKind::Quad), None) => ir::MeshSource::Builtin(self.quad(body)?),
            (Some(MeshKind::Box), None) => ir::MeshSource::Builtin(self.box_shape(body)?),
            (kind, _) => {
                self.unknown_mesh_kind(d, name, kind.is_some());
                return None;
            }
        };
        Some(ir::Mesh {
            name: d.name.name.as_str().to_owned(),
            source,
            span: d.name.span,
            obj: (!obj.is_default()).then(|| Box::new(obj)),
        })
    }

    /// `obj("file.obj")`: exactly one file name.
    fn obj_file(&mut self, args: &[Expr], d: &Decl) -> Option<ir::AssetPath> {
        if let [one] = args {
            return self.asset_path(one);
        }
        self.error(
            Diagnostic::error(Code::CheckWrongArity, "`obj` takes one file name")
                .at(d.ctor.span, "here")
                .help("write `obj(\"file.obj\")`"),
        );
        None
    }

    /// A word that is no mesh kind, or a kind written in the wrong form (`sphere("x")`).
    fn unknown_mesh_kind(&mut self, d: &Decl, name: &str, is_kind: bool) {
        let help = if is_kind {
            "write `obj(\"file.obj\")`, or `inline`, `sphere`, `icosphere`, `quad`, `box` with a block"
                .to_string()
        } else {
            suggest::help_for(name, KINDS, "mesh kinds")
        };
        self.error(
            Diagnostic::error(
                Code::CheckUnknownMeshKind,
                format!("unknown mesh kind `{name}`"),
            )
            .at(d.ctor.span, "not a mesh kind")
            .help(help),
        );
    }

    /// `sphere { radius 1  segments 32 }`.
    fn sphere(&mut self, body: &Block) -> Option<ir::BuiltinShape> {
        let props = self.split(body, "a sphere", super::vocabulary::SPHERE_KEYS, &[], &[]);
        let radius = match props.get("radius") {
            None => Some(1.0),
            Some(p) => self
                .one(p, "radius 1")
                .and_then(|e| self.positive(e, "radius")),
        };
        let segments = match props.get("segments") {
            None => Some(32),
            Some(p) => self
                .one(p, "segments 48")
                .and_then(|e| self.int_in(e, 3, 4096, "segments")),
        };
        Some(ir::BuiltinShape::Sphere {
            radius: radius? as f32,
            segments: segments? as u32,
        })
    }

    /// `quad { size (2, 2) }`.
    fn quad(&mut self, body: &Block) -> Option<ir::BuiltinShape> {
        let props = self.split(body, "a quad", super::vocabulary::QUAD_KEYS, &[], &[]);
        let size = match props.get("size") {
            None => glam::DVec2::ONE,
            Some(p) => {
                let e = self.one(p, "size (2, 2)")?;
                let s = self.vec2_or_num(e)?;
                self.positive_size(e, s.min_element())?;
                s
            }
        };
        Some(ir::BuiltinShape::Quad {
            size: size.as_vec2(),
        })
    }

    /// `box { size (1, 1, 1) }`.
    fn box_shape(&mut self, body: &Block) -> Option<ir::BuiltinShape> {
        let props = self.split(body, "a box", super::vocabulary::BOX_KEYS, &[], &[]);
        let size = match props.get("size") {
            None => glam::DVec3::ONE,
            Some(p) => {
                let e = self.one(p, "size (1, 1, 1)")?;
                let s = self.vec3_or_num(e)?;
                self.positive_size(e, s.min_element())?;
                s
            }
        };
        Some(ir::BuiltinShape::Box {
            size: size.as_vec3(),
        })
    }

    /// `{ material "name in the OBJ" SCN_MATERIAL ...  mtl false }` of an `obj(...)` mesh.
    fn obj_options(&mut self, body: &Block) -> ir::ObjOptions {
        let props = self.split(
            body,
            "an obj mesh",
            super::vocabulary::OBJ_MESH_KEYS,
            &["material"],
            &[],
        );
        let mut out = ir::ObjOptions::default();
        for p in props.props.iter().filter(|p| p.key == "material") {
            let Some(v) = self.arity::<2>(p, "material \"name in the OBJ\" NAME") else {
                continue;
            };
            let obj_name = match &v[0].kind {
                ExprKind::Str(s) => s.clone(),
                ExprKind::Name(n) => n.as_str().to_owned(),
                _ => {
                    self.error(
                        Diagnostic::error(
                            Code::CheckExpectedName,
                            "expected the OBJ's material name (`usemtl` name)",
                        )
                        .at(v[0].span, "not a name")
                        .help("quote names with spaces: `material \"roof tiles\" slate`"),
                    );
                    continue;
                }
            };
            if let Some(m) = self.resolve(super::names::Namespace::Material, v[1]) {
                out.materials.push(ir::ObjMaterialOverride {
                    obj_name,
                    material: m as u32,
                    span: p.span(),
                });
            }
        }
        if let Some(p) = props.get("mtl") {
            if let Some(b) = self.one(p, "mtl false").and_then(|e| self.boolean(e)) {
                out.ignore_mtl = !b;
            }
        }
        out
    }

    fn positive_size(&mut self, e: &Expr, min: f64) -> Option<()> {
        if min <= 0.0 {
            self.out_of_range(e.span, &format!("size must be greater than 0, found {min}"));
            return None;
        }
        Some(())
    }
}
