//! The 8-wide BVH that queries run on: the binary SAH tree collapsed so that each node holds
//! up to eight children's boxes side by side (structure of arrays), which the slab test checks
//! four lanes at a time (two SSE halves; `isa.rs` has the one-register AVX2 form). 256 bytes
//! per node (four cache lines, 64-byte aligned), depth-first order.
//!
//! Stage: made by `collapse` from `build`'s binary [`Node`]s; read by `traverse.rs`.

use glam::{Vec3, Vec4};

use super::node::Node;
use crate::geom::{Aabb, Ray};

/// Children per node.
pub const WIDTH: usize = 8;

/// Up to eight children. `bounds` rows are `[min x, min y, min z, max x, max y, max z]`, one lane
/// per child; an unused lane has the empty box (`+∞` mins, `−∞` maxes), which no ray enters.
/// `child[k]` is a node index when `count[k] == 0`, else the first of `count[k]` primitives.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C, align(64))]
pub struct WideNode {
    /// The children's boxes: rows min x, y, z, max x, y, z; one lane per child.
    pub bounds: [[f32; WIDTH]; 6],
    /// Node index (interior child) or first primitive (leaf child); `u32::MAX` in an unused lane.
    pub child: [u32; WIDTH],
    /// Primitives of a leaf child; 0 for an interior child or an unused lane.
    pub count: [u32; WIDTH],
}

const EMPTY_NODE: WideNode = WideNode {
    bounds: [
        [f32::INFINITY; WIDTH],
        [f32::INFINITY; WIDTH],
        [f32::INFINITY; WIDTH],
        [f32::NEG_INFINITY; WIDTH],
        [f32::NEG_INFINITY; WIDTH],
        [f32::NEG_INFINITY; WIDTH],
    ],
    child: [u32::MAX; WIDTH],
    count: [0; WIDTH],
};

impl WideNode {
    /// Whether lane `k` holds a child.
    pub fn used(&self, k: usize) -> bool {
        self.child[k] != u32::MAX
    }

    /// Lane `k`'s box (empty for an unused lane).
    pub fn child_bounds(&self, k: usize) -> Aabb {
        let b = &self.bounds;
        Aabb {
            min: Vec3::new(b[0][k], b[1][k], b[2][k]),
            max: Vec3::new(b[3][k], b[4][k], b[5][k]),
        }
    }
}

/// A wide hierarchy. A tree that is a single leaf has no nodes and `root_count > 0`.
#[derive(Debug, Default, Clone)]
pub struct Wide {
    /// Depth-first nodes, `nodes[0]` the root; empty when the whole tree is one leaf or nothing.
    pub nodes: Vec<WideNode>,
    /// The root as a child reference: node 0 (`root_count == 0`) or a leaf.
    pub root_first: u32,
    /// Primitives of the root when it is a leaf; 0 when the root is node 0.
    pub root_count: u32,
    /// Bounds of the whole tree; `None` when it holds nothing.
    pub root_bounds: Option<Aabb>,
    /// Most traversal stack entries any ray can need: the largest sum over a root-to-leaf
    /// path of (children − 1). Picks the smallest fixed stack that fits.
    pub stack_need: usize,
}

/// Collapses a binary tree into a wide one: each wide node takes its binary node's children
/// and keeps opening the interior child of largest surface area until it has [`WIDTH`].
pub fn collapse(bin: &[Node]) -> Wide {
    let Some(root) = bin.first() else {
        return Wide::default();
    };
    let mut w = Wide {
        root_bounds: Some(root.bounds()),
        ..Wide::default()
    };
    if root.is_leaf() {
        w.root_first = root.index;
        w.root_count = root.count();
        return w;
    }
    w.nodes.reserve(bin.len() / 3 + 1);
    emit(bin, 0, &mut w.nodes);
    w.stack_need = stack_need(&w.nodes, 0);
    w
}

fn stack_need(nodes: &[WideNode], i: usize) -> usize {
    let n = &nodes[i];
    let used = (0..WIDTH).filter(|&k| n.used(k)).count();
    let deepest = (0..WIDTH)
        .filter(|&k| n.used(k) && n.count[k] == 0)
        .map(|k| stack_need(nodes, n.child[k] as usize))
        .max()
        .unwrap_or(0);
    used - 1 + deepest
}

/// Writes the wide node for binary interior node `i` (and, after it, its subtrees); returns its
/// index.
fn emit(bin: &[Node], i: usize, out: &mut Vec<WideNode>) -> u32 {
    let mut kids = [0usize; WIDTH];
    kids[0] = i + 1;
    kids[1] = bin[i].index as usize;
    let mut n = 2;
    while n < WIDTH {
        // Open the interior child of largest area (the first such on ties).
        let mut open: Option<(usize, f32)> = None;
        for (pos, &k) in kids[..n].iter().enumerate() {
            if !bin[k].is_leaf() {
                let area = bin[k].bounds().surface_area();
                if open.is_none_or(|(_, a)| area > a) {
                    open = Some((pos, area));
                }
            }
        }
        let Some((pos, _)) = open else { break };
        let k = kids[pos];
        kids[pos] = k + 1;
        kids[n] = bin[k].index as usize;
        n += 1;
    }
    let kids = &kids[..n];
    let at = out.len();
    out.push(EMPTY_NODE);
    for (lane, &k) in kids.iter().enumerate() {
        let b = bin[k].bounds();
        let row = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
        for (r, v) in row.into_iter().enumerate() {
            out[at].bounds[r][lane] = v;
        }
        let (child, count) = if bin[k].is_leaf() {
            (bin[k].index, bin[k].count())
        } else {
            (emit(bin, k, out), 0)
        };
        out[at].child[lane] = child;
        out[at].count[lane] = count;
    }
    at as u32
}

/// The ray prepared for wide slab tests: per axis the origin and reciprocal direction in all
/// lanes, and which bounds row is the near plane (`min` for a positive direction, `max` for a
/// negative one; choosing by sign keeps an empty lane empty and needs no min/max).
#[derive(Debug, Clone, Copy)]
pub struct WideRay {
    org: [Vec4; 3],
    inv: [Vec4; 3],
    /// `inv` times [`EXIT_SLACK`] (made finite): the far planes' reciprocal, so the exit
    /// distance needs no multiplication of its own (see [`WideRay::hit`]).
    inv_far: [Vec4; 3],
    /// Per axis, the bounds row of the near plane.
    pub(super) near_row: [usize; 3],
    /// Per axis, the bounds row of the far plane.
    pub(super) far_row: [usize; 3],
    /// The direction's octant: bit `axis` set when its coordinate's sign bit is (−0 too).
    octant: u8,
}

/// The bounds rows of the near planes and of the far planes, per axis.
pub type Rows = ([usize; 3], [usize; 3]);

/// The [`Rows`] of a direction in `octant` (bit `axis` set for a negative coordinate: its near
/// plane is then the max row `axis + 3`, its far plane the min row).
pub const fn octant_rows(octant: usize) -> Rows {
    let (x, y, z) = (
        3 * (octant & 1),
        3 * ((octant >> 1) & 1),
        3 * ((octant >> 2) & 1),
    );
    ([x, 1 + y, 2 + z], [3 - x, 4 - y, 5 - z])
}

/// Slack on the exit distance for three roundings (Ize 2013); see `node.rs`.
pub(super) const EXIT_SLACK: f32 = 1.0 + 3.0 * f32::EPSILON / (1.0 - 1.5 * f32::EPSILON);

impl WideRay {
    /// Prepares `ray` for the slab tests, once per query. Built in vector form: one division
    /// for the three reciprocals (the fourth lane divides 1 by 1 and is never read), one
    /// `movmskps` for the direction's signs; the scalar form (three divisions, each with its
    /// own finiteness branch, and the rows chosen per axis) cost about a fifth of the per-ray
    /// set-up (docs/bvh.md, sixth session). The same bits: IEEE division and multiplication
    /// are the same per lane, and `copysign` is a bit operation.
    #[inline(always)]
    pub fn new(ray: &Ray) -> WideRay {
        let d = ray.dir.extend(1.0);
        // 1/±0 (or a reciprocal that overflows) becomes a huge finite value of the same sign,
        // so that (bound − origin)·inv is never 0·∞. The far planes' reciprocal carries the
        // exit slack; one that overflows stays the largest finite value of its sign.
        let huge = Vec4::splat(f32::MAX).copysign(d);
        let finite_or_huge = |i: Vec4| Vec4::select(i.abs().cmplt(Vec4::INFINITY), i, huge);
        let inv = finite_or_huge(Vec4::ONE / d);
        let inv_far = finite_or_huge(inv * EXIT_SLACK);
        // Bit `axis` set when the direction's sign bit is (−0 included): the near plane is
        // then the max row (`axis + 3`) and the far plane the min row. (The fourth lane is
        // +1, so bit 3 is clear.)
        let negative = d.is_negative_bitmask() as usize;
        let (near_row, far_row) = octant_rows(negative);
        let o = ray.origin;
        WideRay {
            org: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            inv_far: [
                Vec4::splat(inv_far.x),
                Vec4::splat(inv_far.y),
                Vec4::splat(inv_far.z),
            ],
            near_row,
            far_row,
            octant: negative as u8,
        }
    }

    /// The direction's octant (0–7): bit `axis` set when its coordinate is negative (−0 too).
    #[inline(always)]
    pub(super) fn octant(&self) -> usize {
        usize::from(self.octant)
    }

    /// The near and far bounds rows per axis, as chosen for this ray.
    #[inline(always)]
    pub(super) fn rows(&self) -> Rows {
        (self.near_row, self.far_row)
    }

    /// The origin's coordinate on `axis`.
    #[inline(always)]
    pub(super) fn origin(&self, axis: usize) -> f32 {
        self.org[axis].x
    }

    /// The (made finite) reciprocal of the direction's coordinate on `axis`.
    #[inline(always)]
    pub(super) fn inv_dir(&self, axis: usize) -> f32 {
        self.inv[axis].x
    }

    /// [`Self::inv_dir`] times [`EXIT_SLACK`] (made finite): the far planes' reciprocal.
    #[inline(always)]
    pub(super) fn inv_dir_far(&self, axis: usize) -> f32 {
        self.inv_far[axis].x
    }

    /// Entry distances of the children and the mask (bit k) of those entered in
    /// `(0, t_max)`: the slab test four lanes at a time. The exit distances are widened by
    /// [`EXIT_SLACK`] through the far planes' reciprocal and `t_max · EXIT_SLACK`, not by a
    /// multiplication after their `min`: the same four roundings per distance, so the same
    /// conservative bound (Ize 2013), one operation off the node's critical path, and the
    /// entry distances (which order the children) are unchanged.
    #[inline(always)]
    pub fn hit(&self, n: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        self.hit_rows(n, t_max, self.rows())
    }

    /// [`Self::hit`] with the near and far rows given (this ray's own, or its octant's as
    /// constants in a kernel specialised per octant).
    #[inline(always)]
    pub fn hit_rows(&self, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32) {
        let mut entry = [0.0f32; WIDTH];
        let mut mask = 0u32;
        for half in 0..WIDTH / 4 {
            let lanes = 4 * half..4 * half + 4;
            let mut tn = [Vec4::ZERO; 3];
            let mut tf = [Vec4::ZERO; 3];
            for axis in 0..3 {
                let (near, far) = (rows.0[axis], rows.1[axis]);
                let row = |r: usize| Vec4::from_slice(&n.bounds[r][lanes.clone()]);
                tn[axis] = (row(near) - self.org[axis]) * self.inv[axis];
                tf[axis] = (row(far) - self.org[axis]) * self.inv_far[axis];
            }
            // Reduced as a tree, not a chain (one max and one min shorter on the critical
            // path); no operand is NaN, so only the sign of a zero distance could depend on
            // the grouping, and no comparison sees it. The AVX2 form groups alike.
            let t_near = Vec4::ZERO.max(tn[0]).max(tn[1].max(tn[2]));
            let t_exit = Vec4::splat(t_max * EXIT_SLACK)
                .min(tf[0])
                .min(tf[1].min(tf[2]));
            mask |= t_near.cmple(t_exit).bitmask() << (4 * half);
            t_near.write_to_slice(&mut entry[lanes]);
        }
        (entry, mask)
    }

    /// Whether a box entered at `t_entry` may still hold a hit closer than `t_max`.
    #[inline(always)]
    pub fn still_open(t_entry: f32, t_max: f32) -> bool {
        t_entry <= t_max * EXIT_SLACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node_with(boxes: &[Aabb]) -> WideNode {
        let mut n = EMPTY_NODE;
        for (lane, b) in boxes.iter().enumerate() {
            let row = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
            for (r, v) in row.into_iter().enumerate() {
                n.bounds[r][lane] = v;
            }
            n.child[lane] = lane as u32;
            n.count[lane] = 1;
        }
        n
    }

    /// A ray through a corner of a box, computed exactly (dyadic origin and direction, so
    /// `origin + dir` is the corner itself): the box is touched at `t = 1`, so the slab test
    /// must enter it, with `t_max = 1` as well, whatever the rounding of the exit distances
    /// (the slack carried by the far reciprocal must keep the test conservative).
    #[test]
    fn slab_test_enters_every_box_a_ray_touches_at_a_corner() {
        let mut rng = crate::testing::SplitMix64(16);
        let mut dyadic = |scale: f32| (rng.next_u64() % 513) as f32 / 64.0 * scale - 4.0 * scale;
        for case in 0..20_000 {
            let o = Vec3::new(dyadic(1.0), dyadic(1.0), dyadic(1.0));
            let d = Vec3::new(dyadic(0.5), dyadic(0.5), dyadic(0.5));
            // A ray lying in a face's plane (a zero component) is the `0 · ∞` case, tested
            // above; here every component is nonzero.
            if d.cmpeq(Vec3::ZERO).any() {
                continue;
            }
            let corner = o + d;
            let size = Vec3::new(dyadic(0.25).abs(), dyadic(0.25).abs(), dyadic(0.25).abs());
            let (mut min, mut max) = (corner, corner);
            for axis in 0..3 {
                // The corner is a min or a max on each axis, at random.
                if (case >> axis) & 1 == 0 {
                    max[axis] += size[axis];
                } else {
                    min[axis] -= size[axis];
                }
            }
            let n = node_with(&[Aabb { min, max }]);
            let ray = WideRay::new(&Ray::new(o, d));
            for t_max in [1.0, f32::INFINITY] {
                let (_, mask) = ray.hit(&n, t_max);
                assert_eq!(
                    mask, 1,
                    "case {case}: o {o} d {d} box {min}..{max} t_max {t_max}"
                );
            }
        }
    }

    /// The vector-form [`WideRay::new`] against the scalar form it replaced, bit for bit:
    /// signed zeros, reciprocals that overflow (tiny components), and random directions.
    #[test]
    fn wide_ray_matches_the_scalar_construction() {
        let inv = |d: f32| {
            let i = 1.0 / d;
            if i.is_finite() {
                i
            } else {
                f32::MAX.copysign(d)
            }
        };
        let inv_far = |d: f32| {
            let i = inv(d) * EXIT_SLACK;
            if i.is_finite() {
                i
            } else {
                f32::MAX.copysign(d)
            }
        };
        let row = |d: f32, axis: usize| if d.is_sign_negative() { axis + 3 } else { axis };
        let mut rng = crate::testing::SplitMix64(61);
        let special = [
            0.0,
            -0.0,
            1e-39,
            -1e-39,
            2.9e-39,
            f32::MIN_POSITIVE,
            1.0,
            -3.5,
            1e38,
        ];
        for case in 0..20_000 {
            let mut pick = || {
                let r = rng.next_u64();
                if r.is_multiple_of(3) {
                    special[(r >> 8) as usize % special.len()]
                } else {
                    ((r >> 11) % 2001) as f32 / 1000.0 - 1.0
                }
            };
            let d = Vec3::new(pick(), pick(), pick());
            let o = Vec3::new(pick(), pick(), pick());
            let w = WideRay::new(&Ray::new(o, d));
            for axis in 0..3 {
                let (da, oa) = (d[axis], o[axis]);
                assert_eq!(w.origin(axis).to_bits(), oa.to_bits(), "case {case} d {d}");
                assert_eq!(
                    w.inv_dir(axis).to_bits(),
                    inv(da).to_bits(),
                    "case {case} d {d}"
                );
                assert_eq!(
                    w.inv_dir_far(axis).to_bits(),
                    inv_far(da).to_bits(),
                    "case {case} d {d}"
                );
                assert_eq!(w.near_row[axis], row(da, axis), "case {case} d {d}");
                assert_eq!(w.far_row[axis], row(-da, axis), "case {case} d {d}");
                assert_eq!(
                    (w.octant() >> axis) & 1 == 1,
                    da.is_sign_negative(),
                    "case {case} d {d}"
                );
                for lane in 1..4 {
                    assert_eq!(w.inv[axis][lane].to_bits(), inv(da).to_bits());
                    assert_eq!(w.inv_far[axis][lane].to_bits(), inv_far(da).to_bits());
                    assert_eq!(w.org[axis][lane].to_bits(), oa.to_bits());
                }
            }
        }
    }

    #[test]
    fn wide_node_is_four_cache_lines() {
        assert_eq!(std::mem::size_of::<WideNode>(), 256);
        assert_eq!(std::mem::align_of::<WideNode>(), 64);
    }

    #[test]
    fn slab_test_handles_flat_boxes_axis_parallel_rays_and_empty_lanes() {
        let flat = Aabb {
            min: Vec3::new(0.0, 0.0, 1.0),
            max: Vec3::new(1.0, 1.0, 1.0),
        };
        let behind = Aabb {
            min: Vec3::new(0.0, 0.0, 5.0),
            max: Vec3::new(1.0, 1.0, 6.0),
        };
        let n = node_with(&[flat, behind]);
        // Lanes 2 to 7 are empty and must never be entered, whatever the direction signs.
        for dir in [
            -Vec3::Z,
            Vec3::Z,
            Vec3::new(0.0, 0.0, -0.0) - Vec3::Z,
            Vec3::X,
        ] {
            let (_, mask) =
                WideRay::new(&Ray::new(Vec3::new(0.5, 0.5, 2.0), dir)).hit(&n, f32::INFINITY);
            assert_eq!(mask & !0b11, 0, "{dir}");
        }
        let down = WideRay::new(&Ray::new(Vec3::new(0.5, 0.5, 2.0), -Vec3::Z));
        let (t, mask) = down.hit(&n, f32::INFINITY);
        assert_eq!(
            mask, 0b01,
            "the flat box below is hit, the one above is not"
        );
        assert_eq!(t[0], 1.0);
        assert_eq!(down.hit(&n, 0.5).1, 0, "t_max cuts the flat box off");
        // Origin on the x = 0 face, moving along z only: 0 · ∞ must not make a NaN.
        let grazing = WideRay::new(&Ray::new(Vec3::new(0.0, 0.5, 0.0), Vec3::Z));
        assert_eq!(grazing.hit(&n, f32::INFINITY).1, 0b11);
        let outside = WideRay::new(&Ray::new(Vec3::new(-0.1, 0.5, 0.0), Vec3::Z));
        assert_eq!(outside.hit(&n, f32::INFINITY).1, 0);
    }
}
