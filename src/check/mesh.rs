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

use super::array::{self, ArrayError};
use super::Checker;
use crate::diag::{suggest, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::{Block, Decl, Expr, ExprKind};

use super::vocabulary::MESH_KINDS as KINDS;

impl Checker<'_> {
    pub(super) fn mesh(&mut self, d: &Decl) -> Option<ir::Mesh> {
        let empty = Block {
            items: Vec::new(),
            span: d.span,
        };
        let body = d.body.as_ref().unwrap_or(&empty);
        let mut obj = ir::ObjOptions::default();
        let source = match (d.ctor.name.name.as_str(), &d.ctor.args) {
            ("obj", Some(args)) => {
                obj = self.obj_options(body);
                match args.as_slice() {
                    [one] => ir::MeshSource::Obj(self.asset_path(one)?),
                    _ => {
                        self.error(
                            Diagnostic::error(
                                "scnc::check::wrong_arity",
                                "`obj` takes one file name",
                            )
                            .at(d.ctor.span, "here")
                            .help("write `obj(\"file.obj\")`"),
                        );
                        return None;
                    }
                }
            }
            ("inline", None) => ir::MeshSource::Inline(self.inline_mesh(body, d.name.span)?),
            ("sphere", None) => {
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
                ir::MeshSource::Builtin(ir::BuiltinShape::Sphere {
                    radius: radius? as f32,
                    segments: segments? as u32,
                })
            }
            ("icosphere", None) => ir::MeshSource::Builtin(self.icosphere(body)?),
            ("quad", None) => {
                let props = self.split(body, "a quad", super::vocabulary::QUAD_KEYS, &[], &[]);
                let size = match props.get("size") {
                    None => Some(glam::DVec2::ONE),
                    Some(p) => self.one(p, "size (2, 2)").and_then(|e| {
                        let s = self.vec2_or_num(e)?;
                        self.positive_size(e, s.min_element())?;
                        Some(s)
                    }),
                };
                ir::MeshSource::Builtin(ir::BuiltinShape::Quad {
                    size: size?.as_vec2(),
                })
            }
            ("box", None) => {
                let props = self.split(body, "a box", super::vocabulary::BOX_KEYS, &[], &[]);
                let size = match props.get("size") {
                    None => Some(glam::DVec3::ONE),
                    Some(p) => self.one(p, "size (1, 1, 1)").and_then(|e| {
                        let s = self.vec3_or_num(e)?;
                        self.positive_size(e, s.min_element())?;
                        Some(s)
                    }),
                };
                ir::MeshSource::Builtin(ir::BuiltinShape::Box {
                    size: size?.as_vec3(),
                })
            }
            (name, _) => {
                let help = if KINDS.contains(&name) {
                    "write `obj(\"file.obj\")`, or `inline`, `sphere`, `icosphere`, `quad`, `box` with a block"
                        .to_string()
                } else {
                    suggest::help_for(name, KINDS, "mesh kinds")
                };
                self.error(
                    Diagnostic::error(
                        "scnc::check::unknown_mesh_kind",
                        format!("unknown mesh kind `{name}`"),
                    )
                    .at(d.ctor.span, "not a mesh kind")
                    .help(help),
                );
                return None;
            }
        };
        Some(ir::Mesh {
            name: d.name.name.clone(),
            source,
            span: d.name.span,
            obj,
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
            let Some(v) = self.arity(p, 2, "material \"name in the OBJ\" NAME") else {
                continue;
            };
            let obj_name = match &v[0].kind {
                ExprKind::Str(s) => s.clone(),
                ExprKind::Name(n) => n.clone(),
                _ => {
                    self.error(
                        Diagnostic::error(
                            "scnc::check::expected_name",
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

    /// The text of an array value, or an error if the value is not `[ ... ]`.
    fn array_text(&mut self, e: &Expr, key: &str) -> Option<&str> {
        if !matches!(e.kind, ExprKind::Array) {
            self.error(
                Diagnostic::error(
                    "scnc::check::wrong_type",
                    format!("`{key}` takes an array `[ ... ]`"),
                )
                .at(e.span, "not an array"),
            );
            return None;
        }
        Some(self.sources.snippet(e.span))
    }

    fn array_error(&mut self, err: ArrayError, span: Span) {
        let at = err.span(span);
        self.error(Diagnostic::error("scnc::check::bad_array", err.message).at(at, "here"));
    }

    pub(super) fn inline_mesh(&mut self, body: &Block, name_span: Span) -> Option<ir::InlineMesh> {
        let keys = super::vocabulary::INLINE_MESH_KEYS;
        let props = self.split(body, "an inline mesh", keys, &[], &[]);
        let mut ok = true;
        let mut get = |cx: &mut Self, key: &str| -> Option<(&Expr, Span)> {
            let p = props.get(key)?;
            let e = cx.one(p, &format!("{key} [ ... ]"));
            if e.is_none() {
                ok = false;
            }
            e.map(|e| (e, e.span))
        };
        let pos = get(self, "positions");
        let nor = get(self, "normals");
        let uv = get(self, "uvs");
        let idx = get(self, "indices");
        let positions = pos.and_then(|(e, s)| {
            let r = array::vec3s(self.array_text(e, "positions")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let normals = nor.map(|(e, s)| {
            let r = array::vec3s(self.array_text(e, "normals")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let uvs = uv.map(|(e, s)| {
            let r = array::vec2s(self.array_text(e, "uvs")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let indices = idx.and_then(|(e, s)| {
            let r = array::triangles(self.array_text(e, "indices")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        for (key, present) in [("positions", pos.is_some()), ("indices", idx.is_some())] {
            if !present {
                self.error(
                    Diagnostic::error(
                        "scnc::check::missing_key",
                        format!("an inline mesh needs `{key}`"),
                    )
                    .at(name_span, "incomplete mesh"),
                );
                ok = false;
            }
        }
        let (positions, indices) = (positions?, indices?);
        let normals = match normals {
            Some(n) => n?,
            None => Vec::new(),
        };
        let uvs = match uvs {
            Some(u) => u?,
            None => Vec::new(),
        };
        let n = positions.len();
        if let Some(bad) = indices.iter().flatten().find(|&&i| i as usize >= n) {
            let span = idx.map_or(name_span, |(_, s)| s);
            self.error(
                Diagnostic::error(
                    "scnc::check::index_out_of_range",
                    format!("index {bad} is out of range: there are {n} positions"),
                )
                .at(span, "in these indices")
                .help(format!("indices count from 0 and must be below {n}")),
            );
            ok = false;
        }
        for (key, len, span) in [
            ("normals", normals.len(), nor.map(|(_, s)| s)),
            ("uvs", uvs.len(), uv.map(|(_, s)| s)),
        ] {
            if len != 0 && len != n {
                self.error(
                    Diagnostic::error(
                        "scnc::check::length_mismatch",
                        format!("{len} {key} for {n} positions"),
                    )
                    .at(span.unwrap_or(name_span), "wrong count")
                    .help(format!(
                        "give exactly one of the {key} per position, or none"
                    )),
                );
                ok = false;
            }
        }
        ok.then_some(ir::InlineMesh {
            positions,
            normals,
            uvs,
            indices,
        })
    }
}
