//! Stage 3: one mesh declaration → a validated [`TriMesh`] (`mesh m = obj("m.obj")`,
//! `inline { positions [...] indices [...] }`, `quad`/`box`/`sphere`). OBJ bytes come through the
//! [`Loader`]; every failure is a [`BuildError`] labelled at the path literal (OBJ) or the
//! declaration (inline and built-in meshes).

use super::mesh::{MeshProblem, TriMesh};
use super::BuildError;
use crate::assets::obj::{load_obj, report};
use crate::assets::Loader;
use crate::ir::{self, AssetPath, MeshSource};
use crate::source::Span;

/// Loads and validates one mesh; on success also returns the warnings to report (the OBJ's
/// own, degenerate triangles dropped, or no triangles at all).
pub fn load_mesh(
    decl: &ir::Mesh,
    loader: &dyn Loader,
) -> Result<(TriMesh, Vec<BuildError>), BuildError> {
    let raw = match &decl.source {
        MeshSource::Obj(path) => load_obj_mesh(decl, path, loader)?,
        MeshSource::Inline(m) => Raw {
            mesh: TriMesh {
                positions: m.positions.clone(),
                normals: m.normals.clone(),
                uvs: m.uvs.clone(),
                triangles: m.indices.clone(),
                ..TriMesh::default()
            },
            span: decl.span,
            written: decl.name.clone(),
            pre_dropped: 0,
            warnings: Vec::new(),
        },
        MeshSource::Builtin(shape) => Raw {
            mesh: super::shapes::tessellate(shape),
            span: decl.span,
            written: decl.name.clone(),
            pre_dropped: 0,
            warnings: Vec::new(),
        },
    };
    validate(&decl.name, raw)
}

/// A mesh as read, before validation.
struct Raw {
    mesh: TriMesh,
    /// Where problems are labelled: the path literal of an OBJ, else the declaration.
    span: Span,
    /// The file name as written (OBJ), else the mesh's name.
    written: String,
    /// Triangles the OBJ triangulation already dropped as degenerate: counted with the rest.
    pre_dropped: usize,
    /// The OBJ's own warnings and its material maps'.
    warnings: Vec<BuildError>,
}

/// Reads and parses an OBJ mesh with its parts (materials and their maps).
fn load_obj_mesh(
    decl: &ir::Mesh,
    path: &AssetPath,
    loader: &dyn Loader,
) -> Result<Raw, BuildError> {
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
    let loaded = load_obj(
        &path.path,
        bytes.clone(),
        !decl.obj_options().ignore_mtl,
        loader,
    )
    .map_err(|e| {
        BuildError::Obj(Box::new(report::error_diagnostic(
            &e,
            &path.written,
            &bytes,
            Some(path.span),
        )))
    })?;
    let mut warnings: Vec<BuildError> =
        report::warning_diagnostics(&loaded, &path.written, Some(path.span))
            .into_iter()
            .map(|d| BuildError::Obj(Box::new(d)))
            .collect();
    let (parts, part_of, map_warnings) =
        super::obj_parts::parts_of(&loaded, &path.written, path.span, loader);
    warnings.extend(map_warnings);
    let obj = loaded.model;
    Ok(Raw {
        pre_dropped: obj.stats.degenerate_dropped,
        mesh: TriMesh {
            positions: obj.positions,
            normals: obj.normals,
            uvs: obj.uvs,
            triangles: obj.triangles,
            parts,
            part_of,
        },
        span: path.span,
        written: path.written.clone(),
        warnings,
    })
}

/// Validates the mesh (indices in range, degenerate triangles dropped): an error when nothing
/// is left to render, a warning when something was dropped or the mesh is empty.
fn validate(name: &str, raw: Raw) -> Result<(TriMesh, Vec<BuildError>), BuildError> {
    let Raw {
        mesh,
        span,
        written,
        pre_dropped,
        mut warnings,
    } = raw;
    let v = mesh.validate().map_err(|p| match p {
        MeshProblem::IndexOutOfRange { triangle, index } => BuildError::IndexOutOfRange {
            written,
            span,
            reason: format!("triangle {triangle} uses vertex {index}"),
        },
        MeshProblem::AllDegenerate { count } => BuildError::AllDegenerate {
            mesh: name.to_string(),
            count: count + pre_dropped,
            span,
        },
    })?;
    let (dropped, total) = (v.dropped + pre_dropped, v.total + pre_dropped);
    let mesh = name.to_string();
    if total > 0 && dropped == total {
        return Err(BuildError::AllDegenerate {
            mesh,
            count: total,
            span,
        });
    }
    if total == 0 {
        warnings.push(BuildError::EmptyMesh { mesh, span });
    } else if dropped > 0 {
        warnings.push(BuildError::SomeDegenerate {
            mesh,
            count: dropped,
            total,
            span,
        });
    }
    Ok((v.mesh, warnings))
}
