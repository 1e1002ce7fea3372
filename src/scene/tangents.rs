//! Stage 3: per-vertex tangents from UVs, for `material m = phong { normal_map bumps }`.
//!
//! The convention is MikkTSpace's (what Blender, Substance, xNormal and glTF tools bake
//! against), in its essentials: each triangle's tangent and bitangent are the object-space
//! directions of increasing u and v (`∂p/∂u`, `∂p/∂v` from the UV parallelogram), projected
//! onto the plane of the vertex normal and normalised (so a stretched triangle does not
//! outweigh its neighbours), then accumulated at each corner weighted by the corner's angle.
//! The sum is orthonormalised against the normal again; `w` is the handedness: the bitangent
//! at shading time is `w · (n × t)`, with `n` and `t` interpolated (as the MikkTSpace pixel
//! shader does). Triangles whose UVs are degenerate contribute nothing; a vertex with no usable
//! triangle gets an arbitrary tangent perpendicular to its normal (its map is then arbitrary in
//! rotation, but still a unit normal, never NaN).
//!
//! Not reproduced: MikkTSpace splits vertices whose triangles disagree on handedness (mirrored
//! UV islands sharing a vertex); here such a vertex keeps the majority's.

use glam::{Vec3, Vec4};

use super::mesh::TriMesh;

/// One tangent per position (`mesh.uvs` must be one per position; empty otherwise).
pub fn vertex_tangents(mesh: &TriMesh) -> Vec<Vec4> {
    let n = mesh.positions.len();
    if mesh.uvs.len() != n {
        return Vec::new();
    }
    let normals = vertex_normals(mesh);
    let mut t_sum = vec![Vec3::ZERO; n];
    let mut b_sum = vec![Vec3::ZERO; n];
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|i| i as usize);
        let (p0, p1, p2) = (mesh.positions[a], mesh.positions[b], mesh.positions[c]);
        let (w0, w1, w2) = (mesh.uvs[a], mesh.uvs[b], mesh.uvs[c]);
        let (e1, e2) = (p1 - p0, p2 - p0);
        let (d1, d2) = (w1 - w0, w2 - w0);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        let dp_du = (e1 * d2.y - e2 * d1.y) / det;
        let dp_dv = (e2 * d1.x - e1 * d2.x) / det;
        for (k, &v) in [a, b, c].iter().enumerate() {
            let (here, prev, next) = match k {
                0 => (p0, p2, p1),
                1 => (p1, p0, p2),
                _ => (p2, p1, p0),
            };
            let angle = (next - here).angle_between(prev - here);
            if !angle.is_finite() {
                continue;
            }
            let nv = normals[v];
            let t = (dp_du - nv * nv.dot(dp_du)).normalize_or_zero();
            let bt = (dp_dv - nv * nv.dot(dp_dv)).normalize_or_zero();
            t_sum[v] += t * angle;
            b_sum[v] += bt * angle;
        }
    }
    (0..n)
        .map(|v| {
            let nv = normals[v];
            let mut t = (t_sum[v] - nv * nv.dot(t_sum[v])).normalize_or_zero();
            if t == Vec3::ZERO {
                t = nv.any_orthonormal_vector();
            }
            let sign = if nv.cross(t).dot(b_sum[v]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            t.extend(sign)
        })
        .collect()
}

/// The mesh's normals, or angle-weighted face normals when it has none (the shading normal is
/// then the face normal, and the tangent is re-orthogonalised against it at the hit anyway).
fn vertex_normals(mesh: &TriMesh) -> Vec<Vec3> {
    if mesh.normals.len() == mesh.positions.len() {
        return mesh.normals.clone();
    }
    let mut sum = vec![Vec3::ZERO; mesh.positions.len()];
    for tri in &mesh.triangles {
        let p = tri.map(|i| mesh.positions[i as usize]);
        let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        for k in 0..3 {
            let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
            if angle.is_finite() {
                sum[tri[k] as usize] += face * angle;
            }
        }
    }
    sum.into_iter()
        .map(|s| {
            let n = s.normalize_or_zero();
            if n == Vec3::ZERO {
                Vec3::Z
            } else {
                n
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::BuiltinShape;
    use crate::scene::shapes::tessellate;
    use glam::Vec2;

    #[test]
    fn a_quad_in_xz_has_tangent_along_u_and_right_handedness() {
        // u along +x, v along −z, normal +y: n × t = y × x = −z = ∂p/∂v, so w = +1.
        let mesh = TriMesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::new(0.0, 0.0, -1.0),
            ],
            normals: vec![Vec3::Y; 4],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
            triangles: vec![[0, 2, 1], [0, 3, 2]],
            ..TriMesh::default()
        };
        for t in vertex_tangents(&mesh) {
            assert!((t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-6, "{t}");
        }
        // Mirroring v flips the handedness only.
        let mut mirrored = mesh.clone();
        for uv in &mut mirrored.uvs {
            uv.y = 1.0 - uv.y;
        }
        for t in vertex_tangents(&mirrored) {
            assert!((t - Vec4::new(1.0, 0.0, 0.0, -1.0)).length() < 1e-6, "{t}");
        }
    }

    #[test]
    fn sphere_tangents_are_unit_and_perpendicular_to_the_normals() {
        let mesh = tessellate(&BuiltinShape::Sphere {
            radius: 2.0,
            segments: 16,
        });
        let tangents = vertex_tangents(&mesh);
        assert_eq!(tangents.len(), mesh.positions.len());
        for (t, n) in tangents.iter().zip(&mesh.normals) {
            let t3 = t.truncate();
            assert!((t3.length() - 1.0).abs() < 1e-4 && t3.dot(*n).abs() < 1e-4);
            assert!(t.w == 1.0 || t.w == -1.0);
        }
    }

    #[test]
    fn degenerate_uvs_give_finite_tangents() {
        let mesh = TriMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: Vec::new(),
            uvs: vec![Vec2::ZERO; 3],
            triangles: vec![[0, 1, 2]],
            ..TriMesh::default()
        };
        for t in vertex_tangents(&mesh) {
            assert!(t.is_finite() && (t.truncate().length() - 1.0).abs() < 1e-5);
            assert!(t.truncate().dot(Vec3::Z).abs() < 1e-5);
        }
    }
}
