//! Vertex normals an OBJ did not give (stage 3, asset decoding): in a file with some `vn`s, a
//! vertex without one (or with a zero or non-finite one) gets a normal from the faces around it.
//! No `.scn` syntax.

use glam::Vec3;

/// Vertices with no (or a zero or non-finite) normal get the area-weighted normal of the faces
/// around them, so that one corner without `vn` does not cost the whole mesh its normals.
pub(super) fn fill_missing_normals(positions: &[Vec3], tris: &[[u32; 3]], normals: &mut [Vec3]) {
    let bad = |n: Vec3| !n.is_finite() || n.length_squared() == 0.0;
    if !normals.iter().any(|&n| bad(n)) {
        return;
    }
    let missing: Vec<bool> = normals.iter().map(|&n| bad(n)).collect();
    for n in normals.iter_mut().filter(|n| bad(**n)) {
        *n = Vec3::ZERO;
    }
    for t in tris {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let face = (b - a).cross(c - a);
        if !face.is_finite() {
            continue;
        }
        for &i in t {
            if missing[i as usize] {
                normals[i as usize] += face;
            }
        }
    }
    for (n, _) in normals.iter_mut().zip(&missing).filter(|(_, &m)| m) {
        if n.length_squared() == 0.0 || !n.is_finite() {
            // A vertex no face uses: any unit vector will do.
            *n = Vec3::Z;
        }
    }
}
