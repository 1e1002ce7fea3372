//! Stage 3: render-ready triangle meshes in object space, and their validation.
//!
//! Every mesh source (`mesh m = obj("m.obj")`, `inline { ... }`, `quad`/`box`/`sphere`) ends up
//! as a [`TriMesh`]. [`TriMesh::validate`] is the one gate between user data and the renderer:
//! indices in range; degenerate triangles (zero or near-zero area, repeated vertices, a NaN or
//! infinite corner) dropped and counted, never handed to the BVH; positions no triangle uses any
//! more zeroed if not finite (so no bound or light table ever sees them); normals and UVs either
//! one per position or absent.

use glam::{Vec2, Vec3};

use crate::bvh::MeshRef;

/// Triangles sharing a vertex array. `normals` and `uvs` are empty or one per position.
#[derive(Debug, Clone, Default)]
pub struct TriMesh {
    /// Vertex positions, object space.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals (empty: the geometric normal is used).
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates (empty: none).
    pub uvs: Vec<Vec2>,
    /// Vertex indices, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// Material parts of an OBJ mesh (its `usemtl` names): empty for every other mesh.
    pub parts: Vec<MeshPart>,
    /// Per triangle, its index into `parts` (empty: every triangle is part 0).
    pub part_of: Vec<u32>,
}

/// One material of an OBJ mesh: its MTL material mapped to Phong, or `None` to use the
/// placing `object`'s material (faces before any `usemtl`, or a name no library defines).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPart {
    /// The `usemtl` name (`None`: faces before any `usemtl`).
    pub name: Option<String>,
    /// Its MTL material as Phong, when a library defines it.
    pub phong: Option<crate::assets::obj::phong::ObjPhong>,
    /// The MTL texture maps that render (decoded once, when the OBJ is loaded).
    pub maps: PartMaps,
}

/// Decoded MTL maps of one part: `map_Kd` and `map_Ks` (sRGB colour, replacing `Kd` / `Ks`)
/// and `norm` (a tangent-space normal map, data, strength from `-bm`). Mipmapped: they are
/// filtered with the default `anisotropic` filter and repeat wrapping (MTL's default
/// `-clamp off`).
#[derive(Debug, Clone, Default)]
pub struct PartMaps {
    /// `map_Kd`.
    pub diffuse: Option<std::sync::Arc<crate::shade::texture::image::ImageData>>,
    /// `map_Ks`.
    pub specular: Option<std::sync::Arc<crate::shade::texture::image::ImageData>>,
    /// `norm` and its strength.
    pub normal: Option<(std::sync::Arc<crate::shade::texture::image::ImageData>, f32)>,
}

impl PartialEq for PartMaps {
    fn eq(&self, o: &PartMaps) -> bool {
        use std::sync::Arc;
        let same = |a: &Option<Arc<_>>, b: &Option<Arc<_>>| match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            _ => false,
        };
        same(&self.diffuse, &o.diffuse)
            && same(&self.specular, &o.specular)
            && match (&self.normal, &o.normal) {
                (None, None) => true,
                (Some((a, x)), Some((b, y))) => Arc::ptr_eq(a, b) && x == y,
                _ => false,
            }
    }
}

impl PartMaps {
    /// Stores a decoded map under its MTL statement (`map_Kd`, `map_Ks`, else `norm`).
    pub fn set(
        &mut self,
        key: &str,
        data: std::sync::Arc<crate::shade::texture::image::ImageData>,
        bump_multiplier: f32,
    ) {
        match key {
            "map_Kd" => self.diffuse = Some(data),
            "map_Ks" => self.specular = Some(data),
            _ => self.normal = Some((data, bump_multiplier.clamp(0.0, 1.0))),
        }
    }

    /// Whether no map renders.
    pub fn is_empty(&self) -> bool {
        self.diffuse.is_none() && self.specular.is_none() && self.normal.is_none()
    }
}

/// Why a mesh cannot be rendered (converted into a `BuildError` by the caller, who knows the
/// mesh's name and span).
#[derive(Debug, Clone, PartialEq)]
pub enum MeshProblem {
    /// A triangle names a vertex that does not exist.
    IndexOutOfRange {
        /// Which triangle.
        triangle: usize,
        /// The index it uses.
        index: u32,
    },
    /// No triangle has an area.
    AllDegenerate {
        /// How many triangles there were.
        count: usize,
    },
}

/// A validated mesh and how many triangles were dropped as degenerate.
#[derive(Debug)]
pub struct Validated {
    /// The mesh without its degenerate triangles.
    pub mesh: TriMesh,
    /// Triangles dropped.
    pub dropped: usize,
    /// Triangles before dropping.
    pub total: usize,
}

impl TriMesh {
    /// The geometry the BVH builds over.
    pub fn as_mesh_ref(&self) -> MeshRef<'_> {
        MeshRef {
            positions: &self.positions,
            triangles: &self.triangles,
        }
    }

    /// Checks indices and positions, drops degenerate triangles, discards unusable normal/UV
    /// arrays (wrong length) and replaces non-finite or zero normals by none at all.
    pub fn validate(mut self) -> Result<Validated, MeshProblem> {
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= n) {
                return Err(MeshProblem::IndexOutOfRange { triangle: t, index });
            }
        }
        if self.normals.len() != n
            || self
                .normals
                .iter()
                .any(|v| !v.is_finite() || v.length_squared() == 0.0)
        {
            self.normals.clear();
        }
        for v in &mut self.normals {
            *v = v.normalize();
        }
        if self.uvs.len() != n {
            self.uvs.clear();
        }
        for uv in &mut self.uvs {
            if !uv.is_finite() {
                *uv = Vec2::ZERO;
            }
        }
        let total = self.triangles.len();
        let positions = &self.positions;
        if self.part_of.len() == total {
            let mut kept = 0;
            for i in 0..total {
                if !is_degenerate(positions, self.triangles[i]) {
                    self.triangles[kept] = self.triangles[i];
                    self.part_of[kept] = self.part_of[i];
                    kept += 1;
                }
            }
            self.triangles.truncate(kept);
            self.part_of.truncate(kept);
        } else {
            self.part_of.clear();
            self.triangles.retain(|t| !is_degenerate(positions, *t));
        }
        let dropped = total - self.triangles.len();
        // Every triangle left has finite corners; a non-finite position is now unused.
        for p in &mut self.positions {
            if !p.is_finite() {
                *p = Vec3::ZERO;
            }
        }
        if total > 0 && self.triangles.is_empty() {
            return Err(MeshProblem::AllDegenerate { count: total });
        }
        Ok(Validated {
            mesh: self,
            dropped,
            total,
        })
    }
}

/// Zero area, or so close to it that the normal's direction is meaningless (the sine of the
/// angle between the two edges is below f32 epsilon), or a corner that is NaN or infinite (the
/// cross product is then not finite). Indices must be in range.
pub fn is_degenerate(positions: &[Vec3], [a, b, c]: [u32; 3]) -> bool {
    let p = |i: u32| positions[i as usize];
    let (e1, e2) = (p(b) - p(a), p(c) - p(a));
    let cross = e1.cross(e2).length();
    !(cross.is_finite() && cross > f32::EPSILON * e1.length() * e2.length())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri_mesh(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> TriMesh {
        TriMesh {
            positions,
            triangles,
            ..TriMesh::default()
        }
    }

    #[test]
    fn drops_degenerate_and_counts_them() {
        let m = tri_mesh(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, 2.0 * Vec3::X],
            vec![[0, 1, 2], [0, 1, 3], [1, 1, 2]],
        );
        let v = m.validate().expect("one good triangle remains");
        assert_eq!((v.dropped, v.total, v.mesh.triangles.len()), (2, 3, 1));
    }

    #[test]
    fn nan_and_infinite_corners_are_dropped_and_zeroed() {
        let m = tri_mesh(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::new(f32::NAN, 0.0, 0.0),
                Vec3::new(0.0, f32::INFINITY, 0.0),
            ],
            vec![[0, 1, 2], [0, 1, 3], [4, 1, 2], [3, 4, 0]],
        );
        let v = m.validate().expect("one good triangle remains");
        assert_eq!((v.dropped, v.total), (3, 4));
        assert_eq!(v.mesh.triangles, vec![[0, 1, 2]]);
        assert!(v.mesh.positions.iter().all(|p| p.is_finite()));
    }

    #[test]
    fn reports_bad_index_nan_and_all_degenerate() {
        let bad = tri_mesh(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 3]]);
        assert_eq!(
            bad.validate().unwrap_err(),
            MeshProblem::IndexOutOfRange {
                triangle: 0,
                index: 3
            }
        );
        let nan = tri_mesh(
            vec![Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y],
            vec![[0, 1, 2]],
        );
        assert_eq!(
            nan.validate().unwrap_err(),
            MeshProblem::AllDegenerate { count: 1 }
        );
        let flat = tri_mesh(vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X], vec![[0, 1, 2]]);
        assert_eq!(
            flat.validate().unwrap_err(),
            MeshProblem::AllDegenerate { count: 1 }
        );
    }

    #[test]
    fn tiny_and_huge_triangles_are_not_degenerate() {
        for s in [1e-4_f32, 1e5] {
            let m = tri_mesh(vec![Vec3::ZERO, s * Vec3::X, s * Vec3::Y], vec![[0, 1, 2]]);
            assert_eq!(m.validate().expect("valid").dropped, 0, "scale {s}");
        }
    }
}
