//! A BVH build that reuses an earlier build's subtrees: the same [`Built`] as
//! [`build`](super::build::build) over the same primitives, bit for bit, in time that grows
//! with what changed. Stage: the top level of `TwoLevel`, rebuilt when `scnc watch` moves
//! one `object` among 100,000 (`scene::BuildCache`).
//!
//! The builder's tree is a function of its input (primitive boxes and ids, in order): each
//! node's [`step`] (leaf, or a split and the partition it leaves) depends only on the node's
//! primitives in their order and its depth. So the earlier input is walked beside the new one:
//! at a node where both steps agree and leave the same ids at the same places, the children's
//! inputs pair up place by place again; a child whose primitives are bitwise the earlier
//! ones is the earlier subtree, copied (its second-child links moved to where it now sits).
//! Where they part (a box moved across a bin, the bounds grew), that subtree is built as
//! `build` builds it. A one-instance move rebuilds the nodes on its path and copies the rest.

use super::build::{
    build, build_children, right_start, slots_for, step, Built, PrimRef, SplitNode, Step,
    PARALLEL_MIN,
};
use super::node::Node;

/// What an earlier [`build`] was given and made: its primitives in input order, its nodes and
/// its leaf order.
#[derive(Debug, Default)]
pub struct Trace {
    refs: Vec<PrimRef>,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Trace {
    /// The trace of a build over `refs` (as given to it) that made `built`.
    pub fn new(refs: Vec<PrimRef>, built: Built) -> Trace {
        Trace {
            refs,
            nodes: built.nodes,
            order: built.order,
        }
    }

    /// The nodes the build made.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The leaf order the build made.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Bytes it holds (it is kept between builds).
    pub fn bytes(&self) -> usize {
        self.refs.len() * std::mem::size_of::<PrimRef>()
            + self.nodes.len() * std::mem::size_of::<Node>()
            + self.order.len() * 4
    }
}

/// Bitwise equality (a NaN box is the same box again; `-0.0` is not `0.0`).
fn same(a: &PrimRef, b: &PrimRef) -> bool {
    bytemuck::bytes_of(a) == bytemuck::bytes_of(b)
}

/// [`build`] over `refs`, reusing `earlier`'s subtrees where the input is unchanged: the
/// same nodes and order as `build(refs, block)`.
pub fn build_like(refs: Vec<PrimRef>, block: u32, earlier: &Trace) -> Built {
    let n = refs.len();
    if n == 0 || n != earlier.refs.len() || earlier.nodes.is_empty() {
        return build(refs, block);
    }
    let mut refs = refs;
    let mut old = earlier.refs.clone();
    let mut nodes: Vec<Node> = bytemuck::zeroed_vec(slots_for(n));
    let walk = Walk { earlier, block };
    let used = walk.node(&mut refs, &mut old, 0, 0, &mut nodes, 0, 0);
    nodes.truncate(used);
    Built {
        nodes,
        order: refs.iter().map(|r| r.id).collect(),
    }
}

struct Walk<'a> {
    earlier: &'a Trace,
    block: u32,
}

impl Walk<'_> {
    /// The subtree over `refs` (sitting at `base`, node `at`), beside the earlier build's
    /// `old` (the same places) whose node was `old_at`; returns the slots spanned.
    #[allow(clippy::too_many_arguments)] // reason: build_node's arguments and the earlier node's
    fn node(
        &self,
        refs: &mut [PrimRef],
        old: &mut [PrimRef],
        base: u32,
        depth: usize,
        out: &mut [Node],
        at: u32,
        old_at: u32,
    ) -> usize {
        let n = refs.len();
        if refs.iter().zip(old.iter()).all(|(a, b)| same(a, b)) {
            // The earlier subtree, and the leaf order it left.
            let ids = &self.earlier.order[base as usize..base as usize + n];
            for (r, &id) in refs.iter_mut().zip(ids) {
                r.id = id;
            }
            return self.copy(old_at, out, at);
        }
        // Both inputs stepped at once on a large node (the two cores a full build would use;
        // each step is a function of its own input, so the result does not depend on it).
        let block = self.block;
        let ((bounds, new_step), (_, old_step)) = if n >= PARALLEL_MIN {
            rayon::join(|| step(refs, depth, block), || step(old, depth, block))
        } else {
            (step(refs, depth, block), step(old, depth, block))
        };
        let Step::Split { mid, axis } = new_step else {
            out[0] = Node::leaf(&bounds, base, n as u32);
            return 1;
        };
        let earlier_node = self.earlier.nodes.get(old_at as usize);
        let paired = old_step == new_step
            && earlier_node.is_some_and(|e| !e.is_leaf())
            && refs.iter().zip(old.iter()).all(|(a, b)| a.id == b.id);
        let (Some(earlier_node), true) = (earlier_node, paired) else {
            let split = SplitNode {
                bounds,
                mid,
                axis,
                base,
                depth,
                at,
                block: self.block,
            };
            return build_children(refs, &split, out);
        };
        let (left, right) = refs.split_at_mut(mid);
        let (old_left, old_right) = old.split_at_mut(mid);
        let (head, rest) = out.split_at_mut(1);
        let left_used = self.node(left, old_left, base, depth + 1, rest, at + 1, old_at + 1);
        let right_at = right_start(n, mid, left_used);
        let right_used = self.node(
            right,
            old_right,
            base + mid as u32,
            depth + 1,
            &mut rest[right_at - 1..],
            at + right_at as u32,
            earlier_node.index,
        );
        head[0] = Node::interior(&bounds, at + right_at as u32, axis);
        right_at + right_used
    }

    /// The earlier subtree at `old_at` written at node `at` (`out` from there); returns the
    /// slots it spans, as the build that made it returned.
    fn copy(&self, old_at: u32, out: &mut [Node], at: u32) -> usize {
        let node = self.earlier.nodes[old_at as usize];
        if node.is_leaf() {
            out[0] = node;
            return 1;
        }
        debug_assert!(node.index > old_at, "a second child comes after its parent");
        let right_at = node.index.saturating_sub(old_at) as usize;
        let (head, rest) = out.split_at_mut(1);
        self.copy(old_at + 1, rest, at + 1);
        let right_used = self.copy(node.index, &mut rest[right_at - 1..], at + right_at as u32);
        head[0] = Node {
            index: at + right_at as u32,
            ..node
        };
        right_at + right_used
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3A;

    use super::*;
    use crate::bvh::build::PrimBox;

    /// Seeded boxes: a grid of placements (as the generated scenes are) plus noise.
    fn boxes(n: usize, seed: u64) -> Vec<PrimRef> {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|i| {
                let c = Vec3A::new((i % 1000) as f32, next() * 4.0, (i / 1000) as f32 + next());
                let h = Vec3A::splat(0.2 + next());
                PrimRef::new(
                    PrimBox {
                        min: c - h,
                        max: c + h,
                    },
                    i as u32,
                )
            })
            .collect()
    }

    fn moved(refs: &mut [PrimRef], i: usize, by: Vec3A) {
        let b = refs[i].bounds();
        refs[i] = PrimRef::new(
            PrimBox {
                min: b.min + by,
                max: b.max + by,
            },
            refs[i].id,
        );
    }

    /// `build_like` beside the trace of `before` gives exactly `build(after)`.
    fn assert_same_as_fresh(before: &[PrimRef], after: &[PrimRef]) {
        let trace = Trace::new(before.to_vec(), build(before.to_vec(), 1));
        let fresh = build(after.to_vec(), 1);
        let reused = build_like(after.to_vec(), 1, &trace);
        assert_eq!(reused.nodes, fresh.nodes);
        assert_eq!(reused.order, fresh.order);
    }

    #[test]
    fn a_rebuild_beside_a_trace_is_the_fresh_build_bit_for_bit() {
        // Above PARALLEL_MIN, so the fixed slot ranges of parallel subtrees are copied too.
        let before = boxes(20_000, 7);
        assert_same_as_fresh(&before, &before);
        for (i, by) in [
            (10_000, Vec3A::new(0.25, 0.0, 0.0)),
            (0, Vec3A::new(0.0, 3.0, 0.0)),
            (19_999, Vec3A::new(-500.0, 0.0, 9.0)),
            (4321, Vec3A::new(2000.0, 0.0, 0.0)),
        ] {
            let mut after = before.clone();
            moved(&mut after, i, by);
            assert_same_as_fresh(&before, &after);
        }
        let mut many = before.clone();
        for i in (0..20_000).step_by(997) {
            moved(&mut many, i, Vec3A::new(0.5, 0.1, -0.3));
        }
        assert_same_as_fresh(&before, &many);
        // Other counts: the plain build.
        assert_same_as_fresh(&before, &boxes(19_999, 7));
        assert_same_as_fresh(&boxes(300, 3), &boxes(300, 4));
    }
}
