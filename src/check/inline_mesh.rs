//! Stage 2, check: the body of `mesh NAME = inline { ... }` → `ir::InlineMesh`.
//!
//! Syntax: `mesh tri = inline { positions [(0,0,0) (1,0,0) (0,1,0)]  normals [...]
//! uvs [(0,0) (1,0) (0,1)]  indices [0 1 2] }`. `positions` and `indices` are required;
//! `normals` and `uvs`, when given, have one entry per position; every index is below the
//! number of positions. Arrays are read by [`super::array`] straight from the source text, so a
//! mesh of a million numbers never becomes a million expression nodes.

use super::array::{self, ArrayError};
use super::Checker;
use crate::diag::{Code, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::{Block, Expr, ExprKind};

/// The array values of an inline mesh, each with its span; `None` when the key is absent.
struct Arrays<'a> {
    positions: Option<(&'a Expr, Span)>,
    normals: Option<(&'a Expr, Span)>,
    uvs: Option<(&'a Expr, Span)>,
    indices: Option<(&'a Expr, Span)>,
    /// False when a key was given without a single value.
    ok: bool,
}

impl Checker<'_> {
    pub(super) fn inline_mesh(&mut self, body: &Block, name_span: Span) -> Option<ir::InlineMesh> {
        let keys = super::vocabulary::INLINE_MESH_KEYS;
        let props = self.split(body, "an inline mesh", keys, &[], &[]);
        let mut ok = true;
        let mut get = |cx: &mut Self, key: &str| -> Option<(&Expr, Span)> {
            let p = props.get(key)?;
            let e = cx.one(p, format_args!("{key} [ ... ]"));
            if e.is_none() {
                ok = false;
            }
            e.map(|e| (e, e.span))
        };
        let arrays = Arrays {
            positions: get(self, "positions"),
            normals: get(self, "normals"),
            uvs: get(self, "uvs"),
            indices: get(self, "indices"),
            ok,
        };
        self.inline_mesh_from(&arrays, name_span)
    }

    /// Reads the arrays and checks them against each other.
    fn inline_mesh_from(&mut self, a: &Arrays, name_span: Span) -> Option<ir::InlineMesh> {
        let mut ok = a.ok;
        let positions = a.positions.and_then(|(e, s)| {
            let r = array::vec3s(self.array_text(e, "positions")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let normals = a.normals.map(|(e, s)| {
            let r = array::vec3s(self.array_text(e, "normals")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let uvs = a.uvs.map(|(e, s)| {
            let r = array::vec2s(self.array_text(e, "uvs")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        let indices = a.indices.and_then(|(e, s)| {
            let r = array::triangles(self.array_text(e, "indices")?);
            r.map_err(|err| self.array_error(err, s)).ok()
        });
        for (key, present) in [
            ("positions", a.positions.is_some()),
            ("indices", a.indices.is_some()),
        ] {
            if !present {
                self.error(
                    Diagnostic::error(
                        Code::CheckMissingKey,
                        format!("an inline mesh needs `{key}`"),
                    )
                    .at(name_span, "incomplete mesh"),
                );
                ok = false;
            }
        }
        let mesh = ir::InlineMesh {
            positions: positions?,
            indices: indices?,
            normals: normals.unwrap_or(Some(Vec::new()))?,
            uvs: uvs.unwrap_or(Some(Vec::new()))?,
        };
        ok &= self.inline_indices_in_range(&mesh, a, name_span);
        ok &= self.inline_counts_match(&mesh, a, name_span);
        ok.then_some(mesh)
    }

    /// Every index names a position.
    fn inline_indices_in_range(&mut self, m: &ir::InlineMesh, a: &Arrays, name_span: Span) -> bool {
        let n = m.positions.len();
        let Some(bad) = m.indices.iter().flatten().find(|&&i| i as usize >= n) else {
            return true;
        };
        let span = a.indices.map_or(name_span, |(_, s)| s);
        self.error(
            Diagnostic::error(
                Code::CheckIndexOutOfRange,
                format!("index {bad} is out of range: there are {n} positions"),
            )
            .at(span, "in these indices")
            .help(format!("indices count from 0 and must be below {n}")),
        );
        false
    }

    /// `normals` and `uvs` have one entry per position (or none).
    fn inline_counts_match(&mut self, m: &ir::InlineMesh, a: &Arrays, name_span: Span) -> bool {
        let n = m.positions.len();
        let mut ok = true;
        for (key, len, span) in [
            ("normals", m.normals.len(), a.normals.map(|(_, s)| s)),
            ("uvs", m.uvs.len(), a.uvs.map(|(_, s)| s)),
        ] {
            if len != 0 && len != n {
                self.error(
                    Diagnostic::error(
                        Code::CheckLengthMismatch,
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
        ok
    }

    /// The text of an array value, or an error if the value is not `[ ... ]`.
    fn array_text(&mut self, e: &Expr, key: &str) -> Option<&str> {
        if !matches!(e.kind, ExprKind::Array) {
            self.error(
                Diagnostic::error(
                    Code::CheckWrongType,
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
        self.error(Diagnostic::error(Code::CheckBadArray, err.message).at(at, "here"));
    }
}
