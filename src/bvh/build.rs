//! Binned-SAH BVH construction over axis-aligned primitive boxes (triangles of one mesh, or
//! instances), output as a flat depth-first [`Node`] array plus the primitive order of the leaves.
//!
//! Binning: 16–32 bins over the centroid bounds per axis; the split of least
//! `area_left · blocks(n_left) + area_right · blocks(n_right)` wins, where `blocks(n)` counts the
//! groups of `block` primitives a leaf tests at once (4 for triangles, which the leaves test four
//! at a time; 1 for instances); a node becomes a leaf when that costs more than intersecting its
//! primitives (and it has at most [`MAX_LEAF`]). When SAH cannot split
//! (all centroids equal, non-finite areas, or below a depth bound) an object-median split on the
//! widest centroid axis takes over, so construction always terminates with bounded depth.
//!
//! Large subtrees are built in parallel with `rayon::join`; every decision depends only on the
//! input, so the tree is the same whatever the number of threads.

use glam::Vec3A;

use super::node::{Node, MAX_DEPTH, MAX_LEAF};
use crate::geom::Aabb;

/// Bounds of one primitive (finite; callers drop primitives with non-finite bounds).
#[derive(Debug, Clone, Copy)]
pub struct PrimBox {
    /// Lower corner.
    pub min: Vec3A,
    /// Upper corner.
    pub max: Vec3A,
}

impl PrimBox {
    fn doubled_centroid(&self) -> Vec3A {
        self.min + self.max
    }
}

/// A primitive to build over: its bounds and the caller's index. The builder reorders these in
/// place, so every pass over a node's primitives reads memory sequentially.
///
/// 32 bytes (Embree's layout: the id in the fourth lane of the lower corner): the references
/// are the largest temporary of a build, alive while the nodes are made, so their size is
/// the build's memory peak (two `Vec3A` and an id would take 48).
#[derive(Debug, Clone, Copy, bytemuck::Zeroable, bytemuck::Pod)]
#[repr(C, align(16))]
pub struct PrimRef {
    min: [f32; 3],
    /// The caller's index of the primitive (a triangle id, or an instance).
    pub id: u32,
    max: [f32; 3],
    _pad: u32,
}

impl PrimRef {
    /// Packs `bounds` and `id` into 32 bytes.
    pub fn new(bounds: PrimBox, id: u32) -> PrimRef {
        PrimRef {
            min: bounds.min.to_array(),
            id,
            max: bounds.max.to_array(),
            _pad: 0,
        }
    }

    /// The bounds, unpacked.
    #[inline]
    pub fn bounds(&self) -> PrimBox {
        PrimBox {
            min: Vec3A::from_array(self.min),
            max: Vec3A::from_array(self.max),
        }
    }
}

/// A built hierarchy: `nodes[0]` is the root (if any); leaves refer to `order[first..first+count]`,
/// which holds the caller's primitive indices.
#[derive(Debug, Default)]
pub struct Built {
    /// Depth-first binary nodes, `nodes[0]` the root; empty when there were no primitives.
    pub nodes: Vec<Node>,
    /// The callers' primitive ids in leaf order.
    pub order: Vec<u32>,
}

/// Subtrees with more primitives than this are built with `rayon::join`.
pub(super) const PARALLEL_MIN: usize = 8 * 1024;
/// Below this depth SAH decides; beyond it only median splits (so depth stays ≤ MAX_DEPTH).
const SAH_MAX_DEPTH: usize = MAX_DEPTH - 34;
/// Cost of one traversal step relative to one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// Builds a BVH over `refs`; the leaf order names their ids. `block` is how many primitives a
/// leaf test handles at once (its cost counts in blocks: 4 triangles cost what 1 does).
///
/// The nodes go into one zero-initialised array with room for the largest possible tree
/// (`2n − 1` nodes; fresh zero pages from the operating system, committed only when written).
/// A subtree built in parallel gets a fixed slot range of that array sized for its own largest
/// tree, so parallel tasks write disjoint slices: no per-task vectors, no copies, and the same
/// layout whatever the number of threads. Unused slots (gaps after parallel subtrees that came
/// out smaller than their bound) are never linked to and, being whole untouched pages mostly,
/// cost address space rather than memory.
pub fn build(mut refs: Vec<PrimRef>, block: u32) -> Built {
    if refs.is_empty() {
        return Built::default();
    }
    let mut nodes: Vec<Node> = bytemuck::zeroed_vec(slots_for(refs.len()));
    let used = build_node(&mut refs, 0, 0, &mut nodes, 0, block);
    nodes.truncate(used);
    Built {
        nodes,
        order: refs.iter().map(|r| r.id).collect(),
    }
}

/// Most nodes a tree over `n ≥ 1` primitives can have: one primitive per leaf, `2n − 1`.
pub(super) fn slots_for(n: usize) -> usize {
    2 * n - 1
}

fn half_area(min: Vec3A, max: Vec3A) -> f32 {
    let e = max - min;
    e.x * e.y + e.y * e.z + e.z * e.x
}

fn to_aabb(min: Vec3A, max: Vec3A) -> Aabb {
    Aabb {
        min: min.into(),
        max: max.into(),
    }
}

/// Bounds of the primitives and of their (doubled) centroids.
fn bounds_of(refs: &[PrimRef]) -> (Vec3A, Vec3A, Vec3A, Vec3A) {
    let inf = Vec3A::splat(f32::INFINITY);
    let (mut lo, mut hi, mut clo, mut chi) = (inf, -inf, inf, -inf);
    for r in refs {
        let b = r.bounds();
        lo = lo.min(b.min);
        hi = hi.max(b.max);
        let c = b.doubled_centroid();
        clo = clo.min(c);
        chi = chi.max(c);
    }
    (lo, hi, clo, chi)
}

struct Split {
    axis: usize,
    /// Primitives whose bin is below this go left.
    bin: usize,
    cost: f32,
}

#[derive(Clone, Copy)]
struct Bin {
    min: Vec3A,
    max: Vec3A,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    min: Vec3A::splat(f32::INFINITY),
    max: Vec3A::splat(f32::NEG_INFINITY),
    count: 0,
};
const MAX_BINS: usize = 32;

/// Maps a doubled centroid to its bin on `axis`.
#[inline]
fn bin_of(c: Vec3A, axis: usize, clo: Vec3A, scale: Vec3A, bins: usize) -> usize {
    // A NaN or negative product saturates to 0 in the cast; the min keeps the top in range.
    (((c[axis] - clo[axis]) * scale[axis]) as usize).min(bins - 1)
}

/// Leaf-test cost of `n` primitives tested `block` at a time.
#[inline]
fn blocks(n: u32, block: u32) -> f32 {
    n.div_ceil(block) as f32
}

fn find_sah_split(refs: &[PrimRef], clo: Vec3A, chi: Vec3A, block: u32) -> Option<Split> {
    let bins = if refs.len() < 256 { 16 } else { MAX_BINS };
    let extent = chi - clo;
    let scale = Vec3A::splat(bins as f32 * (1.0 - 1e-6)) / extent;
    let mut table = [[EMPTY_BIN; MAX_BINS]; 3];
    for r in refs {
        let b = r.bounds();
        let c = b.doubled_centroid();
        for (axis, row) in table.iter_mut().enumerate() {
            let bin = &mut row[bin_of(c, axis, clo, scale, bins)];
            bin.min = bin.min.min(b.min);
            bin.max = bin.max.max(b.max);
            bin.count += 1;
        }
    }
    let mut best: Option<Split> = None;
    for (axis, row) in table.iter().enumerate() {
        if !(extent[axis] > 0.0 && scale[axis].is_finite()) {
            continue;
        }
        // right_cost[i]: cost of bins i.. on the right.
        let mut right_cost = [0.0f32; MAX_BINS];
        let (mut lo, mut hi, mut n) = (EMPTY_BIN.min, EMPTY_BIN.max, 0u32);
        for i in (1..bins).rev() {
            lo = lo.min(row[i].min);
            hi = hi.max(row[i].max);
            n += row[i].count;
            right_cost[i] = if n == 0 {
                f32::INFINITY
            } else {
                half_area(lo, hi) * blocks(n, block)
            };
        }
        let (mut lo, mut hi, mut n) = (EMPTY_BIN.min, EMPTY_BIN.max, 0u32);
        for i in 1..bins {
            lo = lo.min(row[i - 1].min);
            hi = hi.max(row[i - 1].max);
            n += row[i - 1].count;
            if n == 0 {
                continue;
            }
            let cost = half_area(lo, hi) * blocks(n, block) + right_cost[i];
            if cost < best.as_ref().map_or(f32::INFINITY, |s| s.cost) {
                best = Some(Split { axis, bin: i, cost });
            }
        }
    }
    best
}

/// Reorders `refs` so that the first half has the smaller centroids on the widest axis.
fn median_split(refs: &mut [PrimRef], clo: Vec3A, chi: Vec3A) -> (usize, usize) {
    let e = chi - clo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = refs.len() / 2;
    let key = |r: &PrimRef| r.bounds().doubled_centroid()[axis];
    refs.select_nth_unstable_by(mid, |a, b| key(a).total_cmp(&key(b)).then(a.id.cmp(&b.id)));
    (mid, axis)
}

fn partition(refs: &mut [PrimRef], mut goes_left: impl FnMut(&PrimRef) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..refs.len() {
        if goes_left(&refs[i]) {
            refs.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

/// What [`build_node`] does at a node: make it a leaf, or split its primitives (reordered in
/// place) into `..mid` and `mid..` on `axis`. A function of the primitives (in their order) and
/// the depth alone, so a rebuild (`rebuild.rs`) can ask it of an earlier build's input too.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    Leaf,
    Split { mid: usize, axis: usize },
}

/// The node's bounds and [`Step`] for `refs` (at least one) at `depth`; a split leaves `refs`
/// partitioned.
pub(super) fn step(refs: &mut [PrimRef], depth: usize, block: u32) -> (Aabb, Step) {
    let n = refs.len();
    let (lo, hi, clo, chi) = bounds_of(refs);
    let bounds = to_aabb(lo, hi);
    if n == 1 {
        return (bounds, Step::Leaf);
    }
    let sah = if depth < SAH_MAX_DEPTH {
        find_sah_split(refs, clo, chi, block)
    } else {
        None
    };
    let leaf_cost = blocks(n as u32, block);
    let split_cost = sah
        .as_ref()
        .map(|s| TRAVERSAL_COST + s.cost / half_area(lo, hi));
    let sah_says_leaf = match split_cost {
        Some(c) => c.is_finite() && leaf_cost <= c,
        None => true,
    };
    if n <= MAX_LEAF as usize && sah_says_leaf {
        return (bounds, Step::Leaf);
    }
    let (mid, axis) = match sah {
        Some(s) => {
            let bins = if n < 256 { 16 } else { MAX_BINS };
            let scale = Vec3A::splat(bins as f32 * (1.0 - 1e-6)) / (chi - clo);
            let mid = partition(refs, |r| {
                bin_of(r.bounds().doubled_centroid(), s.axis, clo, scale, bins) < s.bin
            });
            if mid == 0 || mid == n {
                median_split(refs, clo, chi)
            } else {
                (mid, s.axis)
            }
        }
        None => median_split(refs, clo, chi),
    };
    (bounds, Step::Split { mid, axis })
}

/// Where a split node's second child starts, relative to the node: right after the first
/// child's largest possible tree for a subtree built in parallel (fixed slots, whatever the
/// threads), else right after the first child as built (`left_used` slots).
pub(super) fn right_start(n: usize, mid: usize, left_used: usize) -> usize {
    if n >= PARALLEL_MIN {
        1 + slots_for(mid)
    } else {
        1 + left_used
    }
}

/// Builds the subtree over `refs` (which sit at `base` in the final order) into `out`, whose
/// first slot is node `at` of the whole array and which has room for `slots_for(refs.len())`
/// nodes. Returns how many slots from the start of `out` the subtree spans.
pub(super) fn build_node(
    refs: &mut [PrimRef],
    base: u32,
    depth: usize,
    out: &mut [Node],
    at: u32,
    block: u32,
) -> usize {
    let n = refs.len();
    match step(refs, depth, block) {
        (bounds, Step::Leaf) => {
            out[0] = Node::leaf(&bounds, base, n as u32);
            1
        }
        (bounds, Step::Split { mid, axis }) => {
            let split = SplitNode {
                bounds,
                mid,
                axis,
                base,
                depth,
                at,
                block,
            };
            build_children(refs, &split, out)
        }
    }
}

/// A node split by [`step`], where it sits, for [`build_children`].
pub(super) struct SplitNode {
    pub bounds: Aabb,
    pub mid: usize,
    pub axis: usize,
    pub base: u32,
    pub depth: usize,
    pub at: u32,
    pub block: u32,
}

/// Builds both children of a split node (its `refs` partitioned at `split.mid`) and the node
/// itself into `out`; returns the slots spanned, as [`build_node`].
pub(super) fn build_children(refs: &mut [PrimRef], split: &SplitNode, out: &mut [Node]) -> usize {
    let &SplitNode {
        mid,
        base,
        depth,
        at,
        block,
        ..
    } = split;
    let n = refs.len();
    let (left, right) = refs.split_at_mut(mid);
    let right_base = base + mid as u32;
    let (head, rest) = out.split_at_mut(1);
    let spans = if n >= PARALLEL_MIN {
        // The right subtree starts where the left one's largest possible tree would end.
        let right_start = right_start(n, mid, 0);
        let (left_out, right_out) = rest.split_at_mut(right_start - 1);
        let (_, right_used) = rayon::join(
            || build_node(left, base, depth + 1, left_out, at + 1, block),
            || {
                build_node(
                    right,
                    right_base,
                    depth + 1,
                    right_out,
                    at + right_start as u32,
                    block,
                )
            },
        );
        (right_start, right_used)
    } else {
        let left_used = build_node(left, base, depth + 1, rest, at + 1, block);
        let right_start = right_start(n, mid, left_used);
        let right_out = &mut rest[left_used..];
        let right_used = build_node(
            right,
            right_base,
            depth + 1,
            right_out,
            at + right_start as u32,
            block,
        );
        (right_start, right_used)
    };
    head[0] = Node::interior(&split.bounds, at + spans.0 as u32, split.axis);
    spans.0 + spans.1
}
