//! Stage 3: `mesh ball = icosphere { subdivisions 5  radius 0.6 }` → a flat-shaded [`TriMesh`].
//!
//! The benchmark's icosphere, vertex for vertex and face for face (`icosphere(level)` in
//! bench/scenes/gen.py, checked against a fixture that script wrote: tests/fixtures/icosphere-gen-py.json):
//! the 12 vertices of an icosahedron normalised onto the unit sphere, then `subdivisions` times
//! every triangle `(a, b, c)` split into `(a, ab, ca) (b, bc, ab) (c, ca, bc) (ab, bc, ca)` with
//! each edge's midpoint pushed onto the sphere once, in first-use order. The arithmetic runs in
//! f64 in the script's order, so the vertices round to the same f32 values as the script's.
//! No normals and no UVs: the benchmark's OBJs have none, so both render flat-shaded with the
//! geometric normal. Wound counter-clockwise seen from outside.

use std::collections::HashMap;

use glam::DVec3;

use crate::scene::mesh::TriMesh;

/// The icosahedron's faces, as the script lists them.
const FACES: [[u32; 3]; 20] = [
    [0, 11, 5],
    [0, 5, 1],
    [0, 1, 7],
    [0, 7, 10],
    [0, 10, 11],
    [1, 5, 9],
    [5, 11, 4],
    [11, 10, 2],
    [10, 7, 6],
    [7, 1, 8],
    [3, 9, 4],
    [3, 4, 2],
    [3, 2, 6],
    [3, 6, 8],
    [3, 8, 9],
    [4, 9, 5],
    [2, 4, 11],
    [6, 2, 10],
    [8, 6, 7],
    [9, 8, 1],
];

/// `v / |v|` with the script's summation order (`sum(x * x for x in v)`, left to right).
fn normalised(v: DVec3) -> DVec3 {
    let length = (v.x * v.x + v.y * v.y + v.z * v.z).sqrt();
    DVec3::new(v.x / length, v.y / length, v.z / length)
}

/// The unit icosphere in f64: vertices (in the script's order) and faces.
pub fn unit_icosphere(subdivisions: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.powf(0.5)) / 2.0;
    let corners = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ];
    let mut vertices: Vec<DVec3> = corners
        .iter()
        .map(|&(x, y, z)| normalised(DVec3::new(x, y, z)))
        .collect();
    let mut faces = FACES.to_vec();
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::with_capacity(faces.len() * 2);
        let mut split = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let mut mid = |p: u32, q: u32| {
                *midpoints.entry((p.min(q), p.max(q))).or_insert_with(|| {
                    let (u, v) = (vertices[p as usize], vertices[q as usize]);
                    let m = DVec3::new((u.x + v.x) / 2.0, (u.y + v.y) / 2.0, (u.z + v.z) / 2.0);
                    vertices.push(normalised(m));
                    (vertices.len() - 1) as u32
                })
            };
            let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
            split.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = split;
    }
    (vertices, faces)
}

/// The icosphere of the given circumradius, in f32 (scaled in f64, rounded once).
pub fn icosphere(radius: f32, subdivisions: u32) -> TriMesh {
    let (vertices, triangles) = unit_icosphere(subdivisions);
    let r = f64::from(radius);
    TriMesh {
        positions: vertices.iter().map(|v| (*v * r).as_vec3()).collect(),
        triangles,
        ..TriMesh::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_closure_and_outward_winding() {
        for n in 0..=3 {
            let m = icosphere(2.0, n);
            let faces = 20 * 4usize.pow(n);
            assert_eq!(m.triangles.len(), faces);
            // Euler: V − E + F = 2 with E = 3F/2.
            assert_eq!(m.positions.len(), 2 + faces / 2);
            for &[a, b, c] in &m.triangles {
                let [p0, p1, p2] = [a, b, c].map(|i| m.positions[i as usize]);
                let n = (p1 - p0).cross(p2 - p0);
                assert!(n.dot(p0 + p1 + p2) > 0.0, "triangle faces inwards");
            }
            for p in &m.positions {
                assert!((p.length() - 2.0).abs() < 1e-6);
            }
        }
    }
}
