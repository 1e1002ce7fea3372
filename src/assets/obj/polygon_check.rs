//! Polygon sanity for OBJ faces (stage 3, asset decoding): what [`polygon`](super::polygon)
//! needs to know before and after triangulating one `f …` line, and the per-file warnings it
//! leads to. No `.scn` syntax.
//!
//! - **Repeated windings**: `f 1 2 3 4 1 2 3 4 1 2 3 4` (as buffer-overflow test files write)
//!   goes round the same corners several times. Ear clipping the whole list yields overlapping
//!   triangles whose area matches neither the polygon nor its winding; the face is triangulated
//!   once, from its first loop, with a warning.
//! - **Area mismatch**: a planar simple polygon's triangles, projected on the plane of its Newell
//!   normal, cover exactly its Newell area, whatever the triangulation and even when the polygon
//!   is warped. A self-intersecting or folded polygon cannot be triangulated so (its triangles
//!   overlap or flip), which this measures in f64, relative to the first corner so that the test
//!   holds far from the origin.

use glam::{DVec3, Vec3};

use super::{Note, Place};
use crate::diag::Code;

/// Relative difference between triangulated and Newell area above which a face is reported:
/// far above f64 rounding, far below any real overlap.
pub const AREA_TOLERANCE: f64 = 1e-4;

/// The length of the loop `pts` repeats, if it lists the same corners (by position) at least
/// twice over; `None` for an ordinary polygon.
pub fn repeated_loop(pts: &[Vec3]) -> Option<usize> {
    let n = pts.len();
    (3..=n / 2).find(|&p| pts[p..].iter().zip(pts).all(|(a, b)| a == b))
}

/// A face whose triangles do not cover its Newell area.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaMismatch {
    /// Sum of the triangles' areas projected on the polygon's plane (unsigned).
    pub triangulated: f64,
    /// Half the length of the polygon's Newell vector.
    pub newell: f64,
}

/// Compares the triangles `tris` (indices into `pts`) with the polygon's Newell area.
pub fn area_mismatch(pts: &[Vec3], tris: &[[u32; 3]]) -> Option<AreaMismatch> {
    let origin = pts.first()?.as_dvec3();
    let at = |i: usize| pts.get(i).map_or(DVec3::ZERO, |p| p.as_dvec3() - origin);
    let vector_area: DVec3 = (0..pts.len())
        .map(|i| at(i).cross(at((i + 1) % pts.len())))
        .sum();
    let unit = vector_area.normalize_or_zero();
    let triangulated: f64 = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| at(i as usize));
            let cross = (b - a).cross(c - a);
            // A polygon with no net area (a symmetric figure eight) has no plane: unsigned area.
            0.5 * if unit == DVec3::ZERO {
                cross.length()
            } else {
                cross.dot(unit).abs()
            }
        })
        .sum();
    let newell = 0.5 * vector_area.length();
    let off = (triangulated - newell).abs() > AREA_TOLERANCE * triangulated.max(newell);
    (off && triangulated.is_finite()).then_some(AreaMismatch {
        triangulated,
        newell,
    })
}

/// The first face of a file with each problem, and how many faces had it.
#[derive(Debug, Default)]
pub struct PolygonWarnings {
    /// (line of the first, its loop length, its corner count, faces so far).
    rewound: Option<(Place, usize, usize, usize)>,
    /// (line of the first, its mismatch, faces so far).
    mismatched: Option<(Place, AreaMismatch, usize)>,
}

impl PolygonWarnings {
    /// Notes one face's outcome (`corners` as written, the loop it was triangulated from).
    pub fn record(
        &mut self,
        at: Place,
        corners: usize,
        loop_len: usize,
        mismatch: Option<AreaMismatch>,
    ) {
        if loop_len < corners {
            self.rewound.get_or_insert((at, loop_len, corners, 0)).3 += 1;
        }
        if let Some(m) = mismatch {
            self.mismatched.get_or_insert((at, m, 0)).2 += 1;
        }
    }

    /// The warnings, each at the first face it concerns.
    pub fn notes(&self) -> Vec<Note> {
        let mut out = Vec::new();
        if let Some((at, loop_len, corners, count)) = self.rewound {
            out.push(
                Note::warning(
                    Code::ObjPolygonRewound,
                    format!(
                        "{} goes round the same {loop_len} corners again ({corners} corners \
                         listed); it was triangulated once",
                        faces(count, "this face", "face")
                    ),
                    at,
                )
                .help("list each corner of a face once"),
            );
        }
        if let Some((at, m, count)) = self.mismatched {
            out.push(
                Note::warning(
                    Code::ObjPolygonArea,
                    format!(
                        "{}: its triangles cover {:.6} but its Newell area is {:.6} \
                         (self-intersecting or folded), so some of them overlap",
                        faces(count, "this face cannot be triangulated exactly", "face"),
                        m.triangulated,
                        m.newell
                    ),
                    at,
                )
                .help("split the face into simple (non-self-intersecting) polygons"),
            );
        }
        out
    }
}

/// "this face" for one, "N faces (the first here)" for more.
fn faces(count: usize, one: &str, noun: &str) -> String {
    if count == 1 {
        one.to_string()
    } else {
        format!("{count} {noun}s (the first here)")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_loops_are_found_and_ordinary_polygons_are_not() {
        let sq = [Vec3::ZERO, Vec3::X, Vec3::ONE, Vec3::Y];
        assert_eq!(repeated_loop(&sq), None);
        assert_eq!(repeated_loop(&sq.repeat(3)), Some(4));
        // Two and a half times round: still the same corners again.
        let mut partial = sq.repeat(2);
        partial.extend(&sq[..2]);
        assert_eq!(repeated_loop(&partial), Some(4));
        // A pentagon that revisits one corner is not a repeated loop.
        let revisit = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::ONE,
            Vec3::ZERO,
            Vec3::Y,
            Vec3::NEG_X,
        ];
        assert_eq!(repeated_loop(&revisit), None);
    }

    #[test]
    fn a_good_triangulation_matches_far_from_the_origin_and_a_bow_tie_does_not() {
        let far = Vec3::splat(1e6);
        let sq = [
            far,
            far + Vec3::X,
            far + Vec3::new(1.0, 1.0, 0.3),
            far + Vec3::Y,
        ];
        assert_eq!(area_mismatch(&sq, &[[0, 1, 2], [0, 2, 3]]), None);
        let bow = [Vec3::ZERO, Vec3::ONE.with_z(0.0), Vec3::X, Vec3::Y];
        let m = area_mismatch(&bow, &[[0, 1, 2], [0, 2, 3]]).expect("a bow tie cannot match");
        assert!(m.triangulated > m.newell, "{m:?}");
    }
}
