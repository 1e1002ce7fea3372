//! Stage 4 support, acceleration: a per-thread count of the BVH work queries do — wide
//! nodes tested plus primitives handed to leaf tests — read by `render::balance` to cost rows
//! for `--tile K/N` (a measure of work that is the same on every machine, unlike time).
//!
//! Each traversal counts in a local register and adds its total once, when it ends, so the
//! render's hot loop pays one thread-local add per traversal and nothing per node.

use std::cell::Cell;

thread_local! {
    static VISITS: Cell<u64> = const { Cell::new(0) };
}

/// The BVH work done on this thread so far (wrapping; read it before and after a query and
/// subtract with `wrapping_sub`).
pub fn visits() -> u64 {
    VISITS.with(Cell::get)
}

/// Adds one traversal's count to this thread's total.
#[inline(always)]
pub(super) fn add(n: u32) {
    VISITS.with(|v| v.set(v.get().wrapping_add(u64::from(n))));
}

/// Finer counts for studying traversal (the `bvh-counters` feature; compiled out otherwise):
/// wide nodes tested, leaves entered and packets of four triangles tested, per thread.
#[cfg(feature = "bvh-counters")]
pub mod counters {
    use std::cell::Cell;

    thread_local! {
        static COUNTS: Cell<[u64; 3]> = const { Cell::new([0; 3]) };
    }

    /// (wide nodes tested, leaves entered, packets tested) on this thread so far.
    pub fn read() -> [u64; 3] {
        COUNTS.with(Cell::get)
    }

    /// Adds to counter `k` (0 nodes, 1 leaves, 2 packets).
    #[inline(always)]
    pub(crate) fn add(k: usize, n: u64) {
        COUNTS.with(|c| {
            let mut v = c.get();
            v[k] += n;
            c.set(v);
        });
    }
}
