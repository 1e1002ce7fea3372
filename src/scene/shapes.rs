//! Stage 3: tessellation of the built-in shapes into [`TriMesh`]es with normals and UVs.
//!
//! Syntax: `mesh floor = quad { size (2, 2) }`, `mesh crate = box { size (1, 1, 1) }`,
//! `mesh ball = sphere { radius 1  segments 48 }`, `mesh gem = icosphere { subdivisions 5
//! radius 1 }` (the icosphere lives in `shapes/icosphere.rs`). All shapes are centred at the origin and
//! wound counter-clockwise seen from outside, so `(p1 − p0) × (p2 − p0)` points outwards (this
//! matters for one-sided area lights).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::mesh::TriMesh;
use crate::ir::BuiltinShape;

pub mod icosphere;

/// The triangles of a built-in shape (`quad`, `box`, `sphere`, `icosphere`), in its own space
/// (centred at the origin).
pub fn tessellate(shape: &BuiltinShape) -> TriMesh {
    match *shape {
        BuiltinShape::Quad { size } => {
            let mut m = TriMesh::default();
            push_face(
                &mut m,
                Vec3::ZERO,
                Vec3::X * size.x / 2.0,
                -Vec3::Z * size.y / 2.0,
            );
            m
        }
        BuiltinShape::Box { size } => {
            let h = size / 2.0;
            let mut m = TriMesh::default();
            // (normal axis, u axis, v axis) with u × v = normal.
            let faces = [
                (Vec3::X, -Vec3::Z, Vec3::Y),
                (-Vec3::X, Vec3::Z, Vec3::Y),
                (Vec3::Y, Vec3::X, -Vec3::Z),
                (-Vec3::Y, Vec3::X, Vec3::Z),
                (Vec3::Z, Vec3::X, Vec3::Y),
                (-Vec3::Z, -Vec3::X, Vec3::Y),
            ];
            for (n, u, v) in faces {
                push_face(&mut m, n * h, u * h, v * h);
            }
            m
        }
        BuiltinShape::Sphere { radius, segments } => sphere(radius, segments),
        BuiltinShape::Icosphere {
            radius,
            subdivisions,
        } => icosphere::icosphere(radius, subdivisions),
    }
}

/// A rectangle `centre ± half_u ± half_v`, facing `half_u × half_v`, with UVs over [0, 1]².
fn push_face(m: &mut TriMesh, centre: Vec3, half_u: Vec3, half_v: Vec3) {
    let base = m.positions.len() as u32;
    let normal = half_u.cross(half_v).normalize_or_zero();
    for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        m.positions.push(centre + su * half_u + sv * half_v);
        m.normals.push(normal);
        m.uvs.push(Vec2::new((su + 1.0) / 2.0, (sv + 1.0) / 2.0));
    }
    m.triangles.push([base, base + 1, base + 2]);
    m.triangles.push([base, base + 2, base + 3]);
}

/// A UV sphere: `segments` columns (at least 3), `segments / 2` rings (at least 2). The seam
/// column is duplicated so UVs do not wrap; each pole has one vertex per column (same position,
/// its own u) and one triangle per column, so no triangle is degenerate.
fn sphere(radius: f32, segments: u32) -> TriMesh {
    let cols = segments.max(3);
    let rings = (cols / 2).max(2);
    let mut m = TriMesh::default();
    for k in 0..=rings {
        let theta = PI * k as f32 / rings as f32;
        for j in 0..=cols {
            let phi = 2.0 * PI * j as f32 / cols as f32;
            let dir = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let u = if k == 0 || k == rings {
                ((j as f32 + 0.5) / cols as f32).min(1.0)
            } else {
                j as f32 / cols as f32
            };
            m.positions.push(radius * dir);
            m.normals.push(dir);
            m.uvs.push(Vec2::new(u, 1.0 - k as f32 / rings as f32));
        }
    }
    let at = |k: u32, j: u32| k * (cols + 1) + j;
    for k in 0..rings {
        for j in 0..cols {
            let (a, b, c, d) = (at(k, j), at(k + 1, j), at(k + 1, j + 1), at(k, j + 1));
            // Triangles touching a pole keep only the side with two distinct ring vertices.
            if k + 1 < rings {
                m.triangles.push([a, c, b]);
            }
            if k > 0 {
                m.triangles.push([a, d, c]);
            }
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::is_degenerate;

    fn check_outward(m: &TriMesh, outward: impl Fn(Vec3) -> Vec3) -> f32 {
        let mut area = 0.0;
        for &[a, b, c] in &m.triangles {
            assert!(!is_degenerate(&m.positions, [a, b, c]));
            let (p0, p1, p2) = (
                m.positions[a as usize],
                m.positions[b as usize],
                m.positions[c as usize],
            );
            let n = (p1 - p0).cross(p2 - p0);
            let centroid = (p0 + p1 + p2) / 3.0;
            assert!(n.dot(outward(centroid)) > 0.0, "triangle faces inwards");
            for i in [a, b, c] {
                assert!(
                    n.dot(m.normals[i as usize]) > 0.0,
                    "vertex normal disagrees"
                );
                let uv = m.uvs[i as usize];
                assert!((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y));
            }
            area += n.length() / 2.0;
        }
        area
    }

    #[test]
    fn quad_faces_up_with_full_uvs() {
        let m = tessellate(&BuiltinShape::Quad {
            size: Vec2::new(2.0, 3.0),
        });
        let area = check_outward(&m, |_| Vec3::Y);
        assert!((area - 6.0).abs() < 1e-5);
        assert!(m.uvs.contains(&Vec2::ZERO) && m.uvs.contains(&Vec2::ONE));
    }

    #[test]
    fn box_faces_point_outwards() {
        let m = tessellate(&BuiltinShape::Box {
            size: Vec3::new(1.0, 2.0, 3.0),
        });
        assert_eq!(m.triangles.len(), 12);
        let area = check_outward(&m, |c| c);
        assert!((area - 2.0 * (2.0 + 6.0 + 3.0)).abs() < 1e-4);
    }

    #[test]
    fn sphere_has_no_degenerate_triangles_and_converges_in_area() {
        for segments in [3, 4, 7, 48] {
            let m = tessellate(&BuiltinShape::Sphere {
                radius: 2.0,
                segments,
            });
            let rings = (segments.max(3) / 2).max(2);
            assert_eq!(m.triangles.len() as u32, 2 * segments * (rings - 1));
            let area = check_outward(&m, |c| c);
            if segments == 48 {
                let exact = 4.0 * PI * 4.0;
                assert!((area - exact).abs() / exact < 0.01, "area {area}");
            }
        }
    }
}
