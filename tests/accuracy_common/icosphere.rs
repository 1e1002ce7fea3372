//! A closed test mesh for the accuracy tests: the icosahedron, subdivided, on the unit sphere.
//! Every edge is shared by exactly two triangles and every vertex by five or six, so a ray from
//! inside that escapes has slipped through a crack. The construction is the library's own
//! built-in `icosphere` mesh (the benchmark's vertex order), rounded to f32 once.

use glam::Vec3;

/// A unit icosphere: the icosahedron subdivided `levels` times, shared vertices (closed).
pub fn icosphere(levels: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (vertices, triangles) = scnc::scene::shapes::icosphere::unit_icosphere(levels);
    (vertices.iter().map(|v| v.as_vec3()).collect(), triangles)
}
