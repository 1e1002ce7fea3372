//! Stage 3: one mesh declaration → a validated [`TriMesh`] (`mesh m = obj("m.obj")`,
//! `inline { positions [...] indices [...] }`, `quad`/`box`/`sphere`). OBJ bytes come through the
//! [`Loader`]; every failure is a [`BuildError`] labelled at the path literal (OBJ) or the
//! declaration (inline and built-in meshes).

use super::mesh::{MeshProblem, TriMesh};
use super::BuildError;
use crate::assets::obj::{parse_obj, ObjError};
use crate::assets::Loader;
use crate::ir::{self, MeshSource};

/// Loads and validates one mesh; on success also returns the warning to report, if any
/// (degenerate triangles dropped, or no triangles at all).
pub fn load_mesh(
    decl: &ir::Mesh,
    loader: &dyn Loader,
) -> Result<(TriMesh, Option<BuildError>), BuildError> {
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
            let obj = parse_obj(&bytes).map_err(|e| match e {
                ObjError::Corrupt(reason) => BuildError::CorruptObj {
                    written: path.written.clone(),
                    span: path.span,
                    reason,
                },
                ObjError::IndexOutOfRange(reason) => BuildError::IndexOutOfRange {
                    written: path.written.clone(),
                    span: path.span,
                    reason,
                },
            })?;
            let mesh = TriMesh {
                positions: obj.positions,
                normals: obj.normals,
                uvs: obj.uvs,
                triangles: obj.triangles,
            };
            (mesh, path.span, path.written.clone())
        }
        MeshSource::Inline(m) => {
            let mesh = TriMesh {
                positions: m.positions.clone(),
                normals: m.normals.clone(),
                uvs: m.uvs.clone(),
                triangles: m.indices.clone(),
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
            count,
            span,
        },
    })?;
    let warning = if v.total == 0 {
        Some(BuildError::EmptyMesh { mesh: name, span })
    } else if v.dropped > 0 {
        Some(BuildError::SomeDegenerate {
            mesh: name,
            count: v.dropped,
            total: v.total,
            span,
        })
    } else {
        None
    };
    Ok((v.mesh, warning))
}
