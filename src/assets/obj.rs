//! Wavefront OBJ loading for stage 3 (`mesh m = obj("meshes/m.obj")`).
//!
//! Input: the file's bytes, read by the caller through the [`Loader`](super::Loader) (tobj never
//! touches the disk: `load_obj_buf` gets an in-memory reader and a material loader that returns
//! no materials, so `mtllib` lines are ignored without error). Output: one merged [`ObjMesh`]
//! (every object and group of the file), triangulated, single-indexed, with normals and UVs kept
//! when every vertex has them. Validation of the geometry itself (NaN, degenerate triangles)
//! is the caller's job; this file only turns tobj's failures into [`ObjError`]s.

use std::io::Cursor;

use glam::{Vec2, Vec3};

/// Triangles as read from an OBJ file (object space, indices not yet range-checked here:
/// tobj checks face indices against the arrays it read).
#[derive(Debug, Clone, Default)]
pub struct ObjMesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub triangles: Vec<[u32; 3]>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ObjError {
    /// Syntax errors, unreadable text, invalid polygons.
    Corrupt(String),
    /// A face names a vertex, normal or UV that the file does not have.
    IndexOutOfRange(String),
}

pub fn parse_obj(bytes: &[u8]) -> Result<ObjMesh, ObjError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = Cursor::new(bytes);
    // tobj is third-party code fed user bytes: a panic inside it must become a diagnostic, not
    // abort the compile (or kill `scnc watch`).
    let loaded = std::panic::catch_unwind(move || {
        tobj::load_obj_buf(&mut reader, &options, |_| {
            Ok((Vec::new(), Default::default()))
        })
    })
    .map_err(|_| ObjError::Corrupt("the OBJ parser failed on this input".into()))?;
    let (models, _materials) = loaded.map_err(|e| match e {
        tobj::LoadError::FaceVertexOutOfBounds
        | tobj::LoadError::FaceNormalOutOfBounds
        | tobj::LoadError::FaceTexCoordOutOfBounds
        | tobj::LoadError::FaceColorOutOfBounds => ObjError::IndexOutOfRange(e.to_string()),
        other => ObjError::Corrupt(other.to_string()),
    })?;
    let mut out = ObjMesh::default();
    let all_normals = models
        .iter()
        .all(|m| m.mesh.normals.len() == m.mesh.positions.len());
    let all_uvs = models
        .iter()
        .all(|m| m.mesh.texcoords.len() / 2 == m.mesh.positions.len() / 3);
    for model in &models {
        let mesh = &model.mesh;
        let base = out.positions.len();
        let count = mesh.positions.len() / 3;
        out.positions.extend(
            mesh.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if all_normals {
            out.normals.extend(
                mesh.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        }
        if all_uvs {
            out.uvs.extend(
                mesh.texcoords
                    .chunks_exact(2)
                    .map(|t| Vec2::new(t[0], t[1])),
            );
        }
        for face in mesh.indices.chunks_exact(3) {
            if let Some(&bad) = face.iter().find(|&&i| i as usize >= count) {
                return Err(ObjError::IndexOutOfRange(format!(
                    "index {bad} with {count} vertices"
                )));
            }
            let global = |i: u32| (base + i as usize) as u32;
            out.triangles
                .push([global(face[0]), global(face[1]), global(face[2])]);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_is_triangulated_with_normals_and_uvs() {
        let text = b"mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                     vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
                     f 1/1/1 2/2/1 3/3/1 4/4/1\n";
        let m = parse_obj(text).expect("valid OBJ");
        assert_eq!(m.triangles.len(), 2);
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.uvs.len(), m.positions.len());
    }

    #[test]
    fn bad_inputs_are_errors_not_panics() {
        assert!(matches!(
            parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            Err(ObjError::IndexOutOfRange(_))
        ));
        assert!(matches!(
            parse_obj(b"v 0 zero 0\n"),
            Err(ObjError::Corrupt(_))
        ));
        assert!(parse_obj(b"\xff\xfe\x00garbage\nf 1 2 3\n").is_err());
    }
}
