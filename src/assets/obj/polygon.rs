//! Polygon triangulation for OBJ faces (stage 3, asset decoding): `f 1 2 3 4 5 …` → triangles.
//! No `.scn` syntax.
//!
//! - Triangles pass through. Quads are split along the shorter diagonal, unless only the other
//!   one lies inside (a concave quad), so the two halves always cover the quad itself.
//! - Larger polygons are ear-clipped (Eberly, "Triangulation by Ear Clipping", 2002) in the
//!   plane of their Newell normal: an ear is a convex corner whose triangle contains no other
//!   corner. A fan, which is what most loaders do, covers area outside a concave polygon.
//!   When no ear exists (a self-intersecting polygon) the current corner is clipped anyway, so
//!   the loop always ends. Polygons above [`EAR_CLIP_MAX`] corners are fanned (the caller warns):
//!   ear clipping is quadratic, and such faces are in practice convex caps.
//! - Results of zero area (or with a NaN corner) are dropped and counted.
//! - A face that lists the same corners several times over is triangulated from its first loop,
//!   and every polygon of more than three corners has its triangles' area compared with its
//!   Newell area (both in [`polygon_check`](super::polygon_check); the caller warns).
//!
//! For a planar simple polygon the triangles' areas sum to the Newell area (tests below and in
//! `tests/obj_corpus.rs`).

use glam::{Vec2, Vec3};

use super::polygon_check::{area_mismatch, repeated_loop, AreaMismatch};

/// Largest polygon that is ear-clipped; larger ones are fanned.
pub const EAR_CLIP_MAX: usize = 4096;

/// What triangulating one polygon did, besides appending triangles.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Outcome {
    /// Triangles of zero area (or with a non-finite corner) dropped.
    pub dropped: usize,
    /// Too large to ear-clip: fanned.
    pub fanned: bool,
    /// How many of the corners were triangulated: all, or the first loop of a face that goes
    /// round the same corners several times.
    pub loop_len: usize,
    /// The triangles do not cover the polygon's Newell area (more than three corners only).
    pub area_mismatch: Option<AreaMismatch>,
}

/// Reusable buffers, so that a million faces allocate nothing.
#[derive(Debug, Default)]
pub struct Scratch {
    flat: Vec<Vec2>,
    prev: Vec<usize>,
    next: Vec<usize>,
}

/// The polygon's Newell normal: its direction is the plane's normal (counter-clockwise winding
/// in front) and its length is twice the area, for planar polygons.
pub fn newell(pts: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, &a) in pts.iter().enumerate() {
        let b = pts[(i + 1) % pts.len()];
        n += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n
}

/// Appends the triangles of polygon `pts` to `out`, as index triples into `pts`.
pub fn triangulate(pts: &[Vec3], out: &mut Vec<[u32; 3]>, scratch: &mut Scratch) -> Outcome {
    let loop_len = repeated_loop(pts).unwrap_or(pts.len());
    let first = out.len();
    let (mut o, exact) = triangulate_loop(&pts[..loop_len], out, scratch);
    o.loop_len = loop_len;
    if !exact {
        o.area_mismatch = area_mismatch(&pts[..loop_len], &out[first..]);
    }
    o
}

/// [`triangulate`] for a polygon that goes round once; `true` when the triangles are known to
/// cover the Newell area without measuring it: a triangle, or a quad split along a diagonal
/// whose two halves both face along the Newell normal (their projected areas then add up to
/// it exactly). Quads are most faces of most files, and this keeps their cost as it was.
fn triangulate_loop(
    pts: &[Vec3],
    out: &mut Vec<[u32; 3]>,
    scratch: &mut Scratch,
) -> (Outcome, bool) {
    let mut o = Outcome::default();
    let mut exact = pts.len() <= 3;
    let mut emit = |t: [usize; 3], o: &mut Outcome| {
        if degenerate(pts[t[0]], pts[t[1]], pts[t[2]]) {
            o.dropped += 1;
        } else {
            out.push(t.map(|i| i as u32));
        }
    };
    match pts.len() {
        0..=2 => {}
        3 => emit([0, 1, 2], &mut o),
        4 => {
            let n = newell(pts);
            let inside = |a: usize, b: usize, c: usize| {
                (pts[b] - pts[a]).cross(pts[c] - pts[a]).dot(n) > 0.0
            };
            let a_ok = inside(0, 1, 2) && inside(0, 2, 3);
            let b_ok = inside(1, 2, 3) && inside(1, 3, 0);
            let a_shorter = pts[0].distance_squared(pts[2]) <= pts[1].distance_squared(pts[3]);
            exact = a_ok || b_ok;
            if b_ok && (!a_ok || !a_shorter) {
                emit([1, 2, 3], &mut o);
                emit([1, 3, 0], &mut o);
            } else {
                emit([0, 1, 2], &mut o);
                emit([0, 2, 3], &mut o);
            }
        }
        n if n > EAR_CLIP_MAX => {
            o.fanned = true;
            for i in 1..n - 1 {
                emit([0, i, i + 1], &mut o);
            }
        }
        _ => ear_clip(pts, scratch, |t| emit(t, &mut o)),
    }
    (o, exact)
}

fn degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let (e1, e2) = (b - a, c - a);
    let cross = e1.cross(e2).length();
    !(cross.is_finite() && cross > f32::EPSILON * e1.length() * e2.length())
}

/// 2D cross product of (b − a) and (c − a): positive for a counter-clockwise turn.
fn turn(a: Vec2, b: Vec2, c: Vec2) -> f32 {
    (b - a).perp_dot(c - a)
}

fn ear_clip(pts: &[Vec3], s: &mut Scratch, mut emit: impl FnMut([usize; 3])) {
    let n = pts.len();
    let normal = newell(pts);
    // Project onto the plane of the dominant normal axis, keeping counter-clockwise order.
    let a = normal.abs();
    let k = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let (mut u, mut v) = ((k + 1) % 3, (k + 2) % 3);
    if normal[k] < 0.0 {
        std::mem::swap(&mut u, &mut v);
    }
    s.flat.clear();
    s.flat.extend(pts.iter().map(|p| Vec2::new(p[u], p[v])));
    s.prev.clear();
    s.prev.extend((0..n).map(|i| (i + n - 1) % n));
    s.next.clear();
    s.next.extend((0..n).map(|i| (i + 1) % n));
    let (flat, prev, next) = (&s.flat, &mut s.prev, &mut s.next);

    let mut remaining = n;
    let mut cur = 0;
    let mut misses = 0;
    while remaining > 3 {
        let (p, q) = (prev[cur], next[cur]);
        let is_ear = misses > remaining || {
            let (a, b, c) = (flat[p], flat[cur], flat[q]);
            turn(a, b, c) > 0.0 && {
                let mut j = next[q];
                let mut clear = true;
                while j != p {
                    let x = flat[j];
                    if x != a && x != b && x != c && inside(a, b, c, x) {
                        clear = false;
                        break;
                    }
                    j = next[j];
                }
                clear
            }
        };
        if is_ear {
            emit([p, cur, q]);
            next[p] = q;
            prev[q] = p;
            remaining -= 1;
            misses = 0;
            cur = q;
        } else {
            misses += 1;
            cur = q;
        }
    }
    emit([prev[cur], cur, next[cur]]);
}

/// Whether `x` is inside or on triangle `abc` (counter-clockwise).
fn inside(a: Vec2, b: Vec2, c: Vec2, x: Vec2) -> bool {
    turn(a, b, x) >= 0.0 && turn(b, c, x) >= 0.0 && turn(c, a, x) >= 0.0
}

/// Sum of the triangles' areas.
pub fn area(pts: &[Vec3], tris: &[[u32; 3]]) -> f32 {
    tris.iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(pts: &[Vec3]) -> (Vec<[u32; 3]>, Outcome) {
        let mut out = Vec::new();
        let o = triangulate(pts, &mut out, &mut Scratch::default());
        (out, o)
    }

    /// A comb: a concave polygon whose fan from corner 0 covers area outside it.
    fn comb(teeth: usize) -> Vec<Vec3> {
        let mut p = vec![Vec3::new(0.0, 0.0, 0.0)];
        for i in 0..teeth {
            let x = i as f32;
            p.push(Vec3::new(x + 0.5, 0.0, 0.0));
        }
        p.push(Vec3::new(teeth as f32, 0.0, 0.0));
        for i in (0..teeth).rev() {
            let x = i as f32;
            p.push(Vec3::new(x + 1.0, 3.0, 0.0));
            p.push(Vec3::new(x + 0.5, 1.0, 0.0));
        }
        p.push(Vec3::new(0.0, 3.0, 0.0));
        p
    }

    #[test]
    fn concave_polygons_keep_their_newell_area() {
        for teeth in [2, 5, 30] {
            let pts = comb(teeth);
            let (tris, o) = run(&pts);
            assert_eq!(o.dropped, 0);
            let want = 0.5 * newell(&pts).length();
            let got = area(&pts, &tris);
            assert!((got - want).abs() < 1e-4 * want, "{teeth}: {got} vs {want}");
            assert_eq!(tris.len(), pts.len() - 2 - o.dropped);
            // The fan would cover more than the polygon.
            let fan: Vec<[u32; 3]> = (1..pts.len() as u32 - 1).map(|i| [0, i, i + 1]).collect();
            assert!(area(&pts, &fan) > 1.05 * want, "the comb must defeat a fan");
        }
    }

    #[test]
    fn clockwise_and_tilted_polygons_work_too() {
        let pts: Vec<Vec3> = comb(4)
            .into_iter()
            .rev()
            .map(|p| Vec3::new(p.x, 0.3 * p.y, p.y) + Vec3::splat(7.0))
            .collect();
        let (tris, _) = run(&pts);
        let want = 0.5 * newell(&pts).length();
        assert!((area(&pts, &tris) - want).abs() < 1e-3 * want);
    }

    #[test]
    fn quads_use_the_shorter_or_the_inside_diagonal() {
        let long = [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(4.0, 1.0, 0.0),
            Vec3::Y,
        ];
        let skew = [
            Vec3::ZERO,
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(4.0, 1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        assert_eq!(run(&skew).0, vec![[1, 2, 3], [1, 3, 0]]);
        assert_eq!(run(&long).0.len(), 2);
        // Concave dart: corner 3 is reflex, only the diagonal 1-3 is inside.
        let dart = [
            Vec3::ZERO,
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
        ];
        let (tris, _) = run(&dart);
        assert_eq!(tris, vec![[1, 2, 3], [1, 3, 0]]);
        let want = 0.5 * newell(&dart).length();
        assert!((area(&dart, &tris) - want).abs() < 1e-6);
    }

    #[test]
    fn degenerate_results_are_dropped_and_counted() {
        let line = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        assert_eq!(run(&line).1.dropped, 1);
        let collinear = [
            Vec3::ZERO,
            Vec3::X,
            2.0 * Vec3::X,
            Vec3::new(2.0, 1.0, 0.0),
            Vec3::Y,
        ];
        let (tris, o) = run(&collinear);
        assert_eq!(tris.len() + o.dropped, 3);
        let want = 0.5 * newell(&collinear).length();
        assert!((area(&collinear, &tris) - want).abs() < 1e-5);
    }

    #[test]
    fn a_face_wound_several_times_is_triangulated_once() {
        let comb = comb(3);
        let (once, o) = run(&comb);
        assert_eq!((o.loop_len, o.area_mismatch), (comb.len(), None));
        let (thrice, o) = run(&comb.repeat(3));
        assert_eq!(thrice, once, "the first loop, triangulated as alone");
        assert_eq!((o.loop_len, o.area_mismatch), (comb.len(), None));
    }

    #[test]
    fn self_intersecting_and_nan_polygons_terminate() {
        let bow = [
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::X,
            Vec3::Y,
            Vec3::new(0.5, 3.0, 0.0),
        ];
        let (tris, o) = run(&bow);
        assert!(tris.len() + o.dropped <= 3);
        assert!(
            o.area_mismatch.is_some(),
            "a bow tie has no exact triangulation"
        );
        let nan = [Vec3::ZERO, Vec3::X, Vec3::NAN, Vec3::Y, Vec3::ONE];
        let (tris, o) = run(&nan);
        assert_eq!(tris.len() + o.dropped, 3);
    }
}
