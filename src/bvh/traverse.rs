//! Stack-based traversal of a flattened BVH, shared by the mesh level and the instance level.
//!
//! At an interior node both children's boxes are tested; the nearer (by entry distance) is
//! visited next and the farther one pushed with its entry distance, so that a closest-hit query
//! skips it on pop once a nearer hit has shrunk `t_max`. The stack is a fixed array sized by the
//! builder's depth bound: no allocation per ray.

use super::node::{Node, RayBox, MAX_DEPTH};

const STACK_SIZE: usize = MAX_DEPTH + 2;

/// Visits the leaves whose boxes the ray enters within `(0, *t_max)`, nearer first.
/// `leaf(first, count, t_max)` tests a leaf's primitives, may shrink `t_max`, and returns `true`
/// to stop the traversal (any-hit queries). Returns whether a leaf stopped it.
#[inline(always)]
pub fn traverse<F>(nodes: &[Node], rb: &RayBox, t_max: &mut f32, mut leaf: F) -> bool
where
    F: FnMut(u32, u32, &mut f32) -> bool,
{
    let Some(root) = nodes.first() else {
        return false;
    };
    if rb.hit(root, *t_max).is_none() {
        return false;
    }
    let mut stack = [(0u32, 0.0f32); STACK_SIZE];
    let mut sp = 0usize;
    let mut idx = 0usize;
    loop {
        let node = &nodes[idx];
        if node.is_leaf() {
            if leaf(node.index, node.count(), t_max) {
                return true;
            }
        } else {
            let (l, r) = (idx + 1, node.index as usize);
            let hit_l = rb.hit(&nodes[l], *t_max);
            let hit_r = rb.hit(&nodes[r], *t_max);
            match (hit_l, hit_r) {
                (Some(tl), Some(tr)) => {
                    let (near, far, t_far) = if tl <= tr { (l, r, tr) } else { (r, l, tl) };
                    // The builder bounds the depth, so the stack cannot overflow.
                    stack[sp] = (far as u32, t_far);
                    sp += 1;
                    idx = near;
                    continue;
                }
                (Some(_), None) => {
                    idx = l;
                    continue;
                }
                (None, Some(_)) => {
                    idx = r;
                    continue;
                }
                (None, None) => {}
            }
        }
        loop {
            if sp == 0 {
                return false;
            }
            sp -= 1;
            let (i, t_entry) = stack[sp];
            if RayBox::still_open(t_entry, *t_max) {
                idx = i as usize;
                break;
            }
        }
    }
}
