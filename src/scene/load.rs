//! Stage 3: one mesh declaration → a validated [`TriMesh`] (`mesh m = obj("m.obj")`,
//! `inline { positions [...] indices [...] }`, `quad`/`box`/`sphere`). OBJ bytes come through the
//! [`Loader`]; every failure is a [`BuildError`] labelled at the path literal (OBJ) or the
//! declaration (inline and built-in meshes).

use super::mesh::{MeshProblem, TriMesh};
use super::BuildError;
use crate::assets::obj::{load_obj, report};
use crate::assets::Loader;
use crate::ir::{self, MeshSource};

/// Loads and validates one mesh; on success also returns the warnings to report (the OBJ's
/// own, degenerate triangles dropped, or no triangles at all).
pub fn load_mesh(
    decl: &ir::Mesh,
    loader: &dyn Loader,
) -> Result<(TriMesh, Vec<BuildError>), BuildError> {
    let mut obj_warnings = Vec::new();
    // Triangles the OBJ triangulation already dropped as degenerate: counted with the rest.
    let mut pre_dropped = 0;
    let (raw, span, written) = match &decl.source {
        MeshSource::Obj(path) => {
            let bytes = loader.read(&path.path).map_err(|source| {
                let (written, span) = (path.written.clone(), path.span);
                if source.kind() == std::io::ErrorKind::NotFound {
                    BuildError::Missing {
                        written,
                        span,
                        source,
                    }
                } else {
                    BuildError::Read {
                        written,
                        span,
                        source,
                    }
                }
            })?;
            let loaded = load_obj(&path.path, bytes.clone(), !decl.obj.ignore_mtl, loader)
                .map_err(|e| {
                    BuildError::Obj(Box::new(report::error_diagnostic(
                        &e,
                        &path.written,
                        &bytes,
                        Some(path.span),
                    )))
                })?;
            obj_warnings = report::warning_diagnostics(&loaded, &path.written, Some(path.span))
                .into_iter()
                .map(|d| BuildError::Obj(Box::new(d)))
                .collect();
            let (parts, part_of, map_warnings) =
                super::obj_parts::parts_of(&loaded, &path.written, path.span, loader);
            obj_warnings.extend(map_warnings);
            let obj = loaded.model;
            pre_dropped = obj.stats.degenerate_dropped;
            let mesh = TriMesh {
                positions: obj.positions,
                normals: obj.normals,
                uvs: obj.uvs,
                triangles: obj.triangles,
                parts,
                part_of,
            };
            (mesh, path.span, path.written.clone())
        }
        MeshSource::Inline(m) => {
            let mesh = TriMesh {
                positions: m.positions.clone(),
                normals: m.normals.clone(),
                uvs: m.uvs.clone(),
                triangles: m.indices.clone(),
                ..TriMesh::default()
            };
            (mesh, decl.span, decl.name.clone())
        }
        MeshSource::Builtin(shape) => (
            super::shapes::tessellate(shape),
            decl.span,
            decl.name.clone(),
        ),
    };
    let name = decl.name.clone();
    let v = raw.validate().map_err(|p| match p {
        MeshProblem::IndexOutOfRange { triangle, index } => BuildError::IndexOutOfRange {
            written,
            span,
            reason: format!("triangle {triangle} uses vertex {index}"),
        },
        MeshProblem::AllDegenerate { count } => BuildError::AllDegenerate {
            mesh: name.clone(),
            count: count + pre_dropped,
            span,
        },
    })?;
    let (dropped, total) = (v.dropped + pre_dropped, v.total + pre_dropped);
    if total > 0 && dropped == total {
        return Err(BuildError::AllDegenerate {
            mesh: name,
            count: total,
            span,
        });
    }
    let warning = if total == 0 {
        Some(BuildError::EmptyMesh { mesh: name, span })
    } else if dropped > 0 {
        Some(BuildError::SomeDegenerate {
            mesh: name,
            count: dropped,
            total,
            span,
        })
    } else {
        None
    };
    obj_warnings.extend(warning);
    Ok((v.mesh, obj_warnings))
}
