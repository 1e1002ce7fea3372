//! The stack traversal of a [`Wide`] tree: nearest child first, farther ones pushed with their
//! entry distance and skipped on pop once a nearer hit has shrunk `t_max`; a pushed child's
//! node or leaf is prefetched, so its cache misses overlap the nearer child's visit. Generic
//! over the instruction set ([`Isa`]) and the leaf test ([`LeafVisitor`]), both inlined into
//! the loop.
//!
//! Stage: queries, under `mesh_bvh.rs` (bottom level) and `two_level.rs` (top level).

use std::cell::RefCell;

use super::isa::Isa;
use super::node::MAX_DEPTH;
use super::tally;
use super::wide::{Wide, WideRay, WIDTH};

/// What a traversal does at a leaf: test primitives `first..first + count`, possibly shrink
/// `t_max`, and return `true` to stop. Closures are visitors; the BVH's own leaf tests are
/// types whose `visit` is `#[inline(always)]`, so they are compiled into the traversal loop
/// (a closure's body is left as a call there: measured 6–10% of a trace).
pub trait LeafVisitor {
    /// Visits one leaf.
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool;
    /// Asks for the primitives `first..first + count` to be loaded ahead of their visit (a
    /// hint; by default nothing).
    #[inline(always)]
    fn prefetch(&self, first: u32, count: u32) {
        let _ = (first, count);
    }
}

impl<F: FnMut(u32, u32, &mut f32) -> bool> LeafVisitor for F {
    #[inline(always)]
    fn visit(&mut self, first: u32, count: u32, t_max: &mut f32) -> bool {
        self(first, count, t_max)
    }
}

/// Each wide level may push `WIDTH − 1` entries, and the binary depth bounds the wide depth.
pub const STACK_MAX: usize = (WIDTH - 1) * MAX_DEPTH + 2;

/// A deferred child: its reference (`child`, `count` as in a node) and entry distance.
pub type Entry = (u32, u32, f32);

/// Room for one top-level and one bottom-level traversal.
pub(super) const SCRATCH: usize = 2 * STACK_MAX;

thread_local! {
    /// Each thread's traversal stacks, reused by every query (a fresh array per query has to
    /// be zeroed: measured 4% of a bench run, 25% with the deepest trees).
    static STACKS: RefCell<[Entry; SCRATCH]> = const { RefCell::new([(0, 0, 0.0); SCRATCH]) };
}

/// Runs `query` with stack space for a top-level traversal and the bottom-level ones it
/// nests (`STACK_MAX` entries each): this thread's reused stacks, or (out of line) a fresh
/// array if they are in use (a query run from inside another's leaf test; nothing does that
/// today).
#[inline(always)]
pub fn with_stacks<R>(query: impl FnOnce(&mut [Entry]) -> R) -> R {
    STACKS.with(|cell| match cell.try_borrow_mut() {
        Ok(mut stacks) => query(&mut stacks[..]),
        Err(_) => with_fresh_stacks(query),
    })
}

/// [`with_stacks`]' fallback: a fresh, zeroed array.
#[cold]
#[inline(never)]
fn with_fresh_stacks<R>(query: impl FnOnce(&mut [Entry]) -> R) -> R {
    query(&mut vec![(0, 0, 0.0); SCRATCH])
}

/// Visits the leaves the ray enters within `(0, *t_max)`, nearer first; `leaf(first, count,
/// t_max)` tests a leaf's primitives, may shrink `t_max`, and returns `true` to stop. Returns
/// whether a leaf stopped the traversal. `stack` must hold `w.stack_need` entries (at most
/// [`STACK_MAX`]); what it holds on entry does not matter. The nodes tested and primitives
/// handed to `leaf` are added to `tally` once, at the end.
#[inline(always)]
pub fn traverse<I: Isa, F: LeafVisitor>(
    isa: I,
    w: &Wide,
    ray: &WideRay,
    t_max: &mut f32,
    mut leaf: F,
    stack: &mut [Entry],
) -> bool {
    let mut visits = 0u32;
    let stopped = if w.nodes.is_empty() {
        visits = w.root_count;
        w.root_count > 0 && leaf.visit(w.root_first, w.root_count, t_max)
    } else {
        walk(
            isa,
            w,
            ray,
            t_max,
            leaf,
            &mut stack[..w.stack_need],
            &mut visits,
        )
    };
    tally::add(visits);
    stopped
}

#[inline(always)]
fn walk<I: Isa, F: LeafVisitor>(
    isa: I,
    w: &Wide,
    ray: &WideRay,
    t_max: &mut f32,
    mut leaf: F,
    stack: &mut [Entry],
    visits: &mut u32,
) -> bool {
    let mut sp = 0usize;
    let (mut child, mut count) = (0u32, 0u32);
    loop {
        if count > 0 {
            *visits = visits.wrapping_add(count);
            #[cfg(feature = "bvh-counters")]
            tally::counters::add(1, 1);
            if leaf.visit(child, count, t_max) {
                return true;
            }
        } else {
            let node = &w.nodes[child as usize];
            *visits = visits.wrapping_add(1);
            #[cfg(feature = "bvh-counters")]
            tally::counters::add(0, 1);
            let (t, mask) = isa.slab(ray, node, *t_max);
            if mask != 0 {
                let first = mask.trailing_zeros() as usize % WIDTH;
                let rest = mask & (mask - 1);
                if rest == 0 {
                    // One child entered (the common case deep in the tree): no ordering.
                    child = node.child[first];
                    count = node.count[first];
                    continue;
                }
                if rest & (rest - 1) == 0 {
                    // Two: the nearer visited next, the other pushed (on a tie the later lane
                    // goes first, as the sort below orders them).
                    let second = rest.trailing_zeros() as usize % WIDTH;
                    let (near, far) = if t[second] <= t[first] {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    stack[sp] = (node.child[far], node.count[far], t[far]);
                    sp += 1;
                    prefetch(isa, w, &leaf, node.child[far], node.count[far]);
                    child = node.child[near];
                    count = node.count[near];
                    continue;
                }
                // More: sorted far to near, the nearest visited next, the others pushed so
                // that they pop in order of distance (on a tie the later lane goes first).
                // (distance, lane) pairs of 8 bytes: the array's initialisation is two
                // vector stores (with a `usize` lane it was fourteen scalar ones).
                let mut hits = [(0.0f32, 0u32); WIDTH];
                hits[0] = (t[first], first as u32);
                let mut n = 1;
                let mut bits = rest;
                while bits != 0 {
                    let k = bits.trailing_zeros() as usize % WIDTH;
                    bits &= bits - 1;
                    let tk = t[k];
                    let mut j = n;
                    while j > 0 && hits[j - 1].0 < tk {
                        hits[j] = hits[j - 1];
                        j -= 1;
                    }
                    hits[j] = (tk, k as u32);
                    n += 1;
                }
                for &(tk, k) in &hits[..n - 1] {
                    let k = k as usize % WIDTH;
                    // `stack` holds `stack_need` entries, the most any path pushes.
                    stack[sp] = (node.child[k], node.count[k], tk);
                    sp += 1;
                    prefetch(isa, w, &leaf, node.child[k], node.count[k]);
                }
                let k = hits[n - 1].1 as usize % WIDTH;
                child = node.child[k];
                count = node.count[k];
                continue;
            }
        }
        loop {
            if sp == 0 {
                return false;
            }
            sp -= 1;
            let (c, n, t_entry) = stack[sp];
            if WideRay::still_open(t_entry, *t_max) {
                child = c;
                count = n;
                break;
            }
        }
    }
}

/// Asks for a deferred child's node or leaf primitives to be loaded while the nearer child is
/// visited (the nearer one is read at once, so prefetching it would gain nothing). On a tree
/// far larger than the L2 cache (dense-L8, 71 MB) this overlaps the misses of the pushed
/// children with the visit of the nearer one: +4–13 % on shadow and +5–14 % on incoherent
/// rays in A/B runs on a loaded machine, 1–3 % slower on a tree that stays in cache
/// (dense-L5); on the idle machine the gain was inside the run-to-run spread (docs/bvh.md,
/// 2026-11-26, fourth session, Zen 5). On a loaded Zen 4 it measured level (fifth session).
#[inline(always)]
fn prefetch<I: Isa, F: LeafVisitor>(isa: I, w: &Wide, leaf: &F, child: u32, count: u32) {
    if count > 0 {
        leaf.prefetch(child, count);
    } else if let Some(node) = w.nodes.get(child as usize) {
        isa.prefetch(node);
    }
}
