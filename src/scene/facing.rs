//! Stage 3: does a one-sided area light face anything? (`light panel = area { quad … }` with
//! `two_sided false`, the default.) The build warns `scnc::build::light_faces_away` when every
//! triangle of the light has all the scene's geometry on or behind its plane: such a light
//! shows on camera but lights nothing, almost always a reversed corner order. Geometry is
//! represented by the corners of each instance's world bounds, so the test is conservative: it
//! never warns about a light that reaches any object.

use glam::Vec3;

use super::mesh::TriMesh;
use super::SceneInstance;

/// A one-sided emitter whose every triangle has all the scene's geometry (`boxes`, the corners
/// of each instance's world bounds, so conservative) on or behind its plane: it lights nothing.
/// False when there is no geometry at all (nothing to light is a different problem).
pub(super) fn faces_away(light: &[[Vec3; 3]], boxes: &[[Vec3; 8]]) -> bool {
    !boxes.is_empty()
        && light.iter().all(|[p0, p1, p2]| {
            let n = (*p1 - *p0).cross(*p2 - *p0);
            boxes.iter().flatten().all(|&c| n.dot(c - *p0) <= 0.0)
        })
}

/// World-space bounds of every instance placed so far (the objects, before any emitter).
/// Each mesh's bounds are found once, however many instances place it.
pub(super) fn world_boxes(meshes: &[TriMesh], instances: &[SceneInstance]) -> Vec<[Vec3; 8]> {
    let bounds: Vec<(Vec3, Vec3)> = meshes
        .iter()
        .map(|m| {
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            for t in &m.triangles {
                for &i in t {
                    lo = lo.min(m.positions[i as usize]);
                    hi = hi.max(m.positions[i as usize]);
                }
            }
            (lo, hi)
        })
        .collect();
    instances
        .iter()
        .filter_map(|inst| {
            let (lo, hi) = bounds[inst.mesh as usize];
            lo.cmple(hi).all().then(|| {
                std::array::from_fn(|k| {
                    let corner =
                        Vec3::select(glam::BVec3::new(k & 1 != 0, k & 2 != 0, k & 4 != 0), hi, lo);
                    inst.world_from_object.transform_point3(corner)
                })
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_away_only_when_all_geometry_is_behind_every_triangle() {
        let unit_box: [Vec3; 8] = std::array::from_fn(|k| {
            Vec3::new((k & 1) as f32, (k >> 1 & 1) as f32, (k >> 2 & 1) as f32)
        });
        // At y = 2: counter-clockwise seen from above faces up (away), the reverse faces down.
        let up = [[
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 1.0),
            Vec3::new(1.0, 2.0, 0.0),
        ]];
        let down = [[up[0][0], up[0][2], up[0][1]]];
        assert!(faces_away(&up, &[unit_box]));
        assert!(!faces_away(&down, &[unit_box]));
        assert!(!faces_away(&up, &[]));
        // A box reaching above the light's plane is in front of it.
        let tall = unit_box.map(|c| c * Vec3::new(1.0, 3.0, 1.0));
        assert!(!faces_away(&up, &[unit_box, tall]));
        // One triangle of a multi-triangle light facing the geometry is enough.
        assert!(!faces_away(&[up[0], down[0]], &[unit_box]));
    }
}
