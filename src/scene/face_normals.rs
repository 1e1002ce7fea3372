//! Stage 3: per-triangle unit face normals, computed once at the build for the meshes that are
//! placed unmoved (an identity `transform`, as every one of cornell's), so a camera ray's hit
//! (`shade::surface::seen_hit`) reads its geometric normal instead of normalising a cross
//! product on each sample's chain (a square root and a division: a fifth of the hit's
//! reconstruction, docs/speed.md).
//!
//! The normals are [`face_normal`] of the corners `q + 0` exactly as the hit's reconstruction
//! forms them for an unmoved placement, so they are the same bits it would compute. A mesh that
//! only moved placements use gets none (its world-space normals differ per placement, and the
//! reconstruction computes them as before).

use glam::{Affine3A, Vec3};

use super::mesh::TriMesh;
use super::SceneInstance;
use crate::shade::surface::face_normal;

/// Per mesh: the unit face normals of its triangles in world space for an identity placement
/// (indexed like `TriMesh::triangles`), or empty where no placement is unmoved.
pub fn unmoved_face_normals(meshes: &[TriMesh], instances: &[SceneInstance]) -> Vec<Vec<Vec3>> {
    let mut normals = vec![Vec::new(); meshes.len()];
    for inst in instances {
        if inst.world_from_object != Affine3A::IDENTITY {
            continue;
        }
        let (Some(mesh), Some(out)) = (
            meshes.get(inst.mesh as usize),
            normals.get_mut(inst.mesh as usize),
        ) else {
            continue;
        };
        if out.is_empty() {
            *out = mesh_face_normals(mesh);
        }
    }
    normals
}

/// The face normal of every triangle of `mesh`, its corners as the hit's reconstruction forms
/// them for an unmoved placement (`q + 0`); zero for a triangle with an index out of range (the
/// reconstruction never reaches one: it finds no triangle there).
fn mesh_face_normals(mesh: &TriMesh) -> Vec<Vec3> {
    mesh.triangles
        .iter()
        .map(|tri| {
            let mut corners = [Vec3::ZERO; 3];
            for (c, &i) in corners.iter_mut().zip(tri) {
                match mesh.positions.get(i as usize) {
                    Some(&q) => *c = q + Vec3::ZERO,
                    None => return Vec3::ZERO,
                }
            }
            face_normal(corners)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Surface;
    use glam::Mat3;

    fn mesh() -> TriMesh {
        TriMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 3.0),
                Vec3::new(-0.0, 1.0, 0.5),
            ],
            normals: Vec::new(),
            uvs: Vec::new(),
            triangles: vec![[0, 1, 2], [0, 2, 1], [1, 2, 3], [0, 1, 9]],
            parts: Vec::new(),
            part_of: Vec::new(),
        }
    }

    fn placed(mesh: u32, world_from_object: Affine3A) -> SceneInstance {
        SceneInstance {
            mesh,
            surface: Surface::Material(0),
            world_from_object,
            normal_from_object: Mat3::IDENTITY,
            part_base: u32::MAX,
        }
    }

    #[test]
    fn unmoved_meshes_get_the_normals_of_their_corners_and_moved_ones_none() {
        let meshes = [mesh(), mesh()];
        let moved = Affine3A::from_translation(Vec3::X);
        let normals = unmoved_face_normals(
            &meshes,
            &[
                placed(0, Affine3A::IDENTITY),
                placed(1, moved),
                placed(7, Affine3A::IDENTITY),
            ],
        );
        assert_eq!(normals.len(), 2);
        assert!(normals[1].is_empty());
        let n = &normals[0];
        assert_eq!(n.len(), 4);
        // Counter-clockwise (0, 1, 2) seen from below: (2, 0, 0) × (0, 0, 3) = (0, −6, 0).
        assert_eq!(n[0], Vec3::NEG_Y);
        assert_eq!(n[1], Vec3::Y);
        let p = &meshes[0].positions;
        let expected = (p[2] - p[1]).cross(p[3] - p[1]).normalize();
        assert!((n[2] - expected).length() < 1e-6 && (n[2].length() - 1.0).abs() < 1e-6);
        // An index out of range: no normal, no panic.
        assert_eq!(n[3], Vec3::ZERO);
    }
}
