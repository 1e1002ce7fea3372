//! Node loops specialised per direction octant: the slab test reads, per axis, the bounds row
//! of the near plane (`min` for a positive direction, `max` for a negative one) and of the far
//! plane. Chosen per ray, those six rows are six offsets the loop reloads from the stack at
//! every node (the general registers are taken); as a compile-time constant of an
//! [`Octant`] they are fixed displacements of the node's loads. A query is dispatched once,
//! on the ray's three sign bits, into one of eight copies of its loop.
//!
//! Stage: queries. `mesh_bvh.rs` hands its bottom-level traversals to [`Isa::per_octant`]; the
//! AVX2 and AVX-512 paths run them through [`dispatch`], the portable path as it is. Same
//! operations on the same rows, so the same bits.

use super::isa::Isa;
use super::wide::{octant_rows, Rows, WideNode, WideRay, WIDTH};
use crate::geom::triangle::{TriangleHit, WatertightRay};
use crate::geom::triangle4::Tri4;

/// A traversal to run on an instruction set that may be specialised per octant (a trait, not a
/// closure, so that its body is generic over the [`Isa`] and inlined into the kernel).
pub trait OctantQuery {
    /// What it returns.
    type Output;
    /// Runs it on `isa`; the implementation should be `#[inline(always)]`.
    fn run<I: Isa>(self, isa: I) -> Self::Output;
}

/// Instruction set `I` for rays whose direction lies in octant `O` (bit `axis` set for a
/// negative coordinate): its slab test reads that octant's rows, whatever the ray says.
#[derive(Debug, Clone, Copy)]
pub struct Octant<I, const O: usize>(pub I);

impl<I: Isa, const O: usize> Octant<I, O> {
    /// The near and far rows of octant `O`.
    const ROWS: Rows = octant_rows(O);
}

/// Runs `query` on `isa` specialised for `octant` (0–7; only its low three bits are read).
#[inline(always)]
pub fn dispatch<I: Isa, Q: OctantQuery>(isa: I, octant: usize, query: Q) -> Q::Output {
    match octant & 0b111 {
        0 => query.run(Octant::<I, 0>(isa)),
        1 => query.run(Octant::<I, 1>(isa)),
        2 => query.run(Octant::<I, 2>(isa)),
        3 => query.run(Octant::<I, 3>(isa)),
        4 => query.run(Octant::<I, 4>(isa)),
        5 => query.run(Octant::<I, 5>(isa)),
        6 => query.run(Octant::<I, 6>(isa)),
        _ => query.run(Octant::<I, 7>(isa)),
    }
}

impl<I: Isa, const O: usize> Isa for Octant<I, O> {
    /// `I`'s slab test on octant `O`'s rows. The ray must lie in that octant (`dispatch`
    /// sees to it): debug builds check.
    #[inline(always)]
    fn slab(self, ray: &WideRay, n: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        debug_assert_eq!(ray.octant(), O, "a ray run in another octant's loop");
        self.0.slab_rows(ray, n, t_max, Self::ROWS)
    }
    #[inline(always)]
    fn slab_rows(self, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32) {
        self.0.slab_rows(ray, n, t_max, rows)
    }
    /// Already specialised: as it is.
    #[inline(always)]
    fn per_octant<Q: OctantQuery>(self, _: usize, query: Q) -> Q::Output {
        query.run(self)
    }
    #[inline(always)]
    fn closest_tris(
        self,
        r: &WatertightRay,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)> {
        self.0.closest_tris(r, t_max, tris)
    }
    #[inline(always)]
    fn any_tris(self, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
        self.0.any_tris(r, t_max, tris)
    }
    #[inline(always)]
    fn prefetch<T: ?Sized>(self, at: &T) {
        self.0.prefetch(at);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::isa::Portable;
    use crate::geom::avx2::{Avx2, Avx512};
    use crate::geom::Ray;
    use glam::Vec3;

    /// The slab test of one ray against one node.
    struct Slab<'a>(&'a WideRay, &'a WideNode, f32);
    impl OctantQuery for Slab<'_> {
        type Output = ([u32; WIDTH], u32);
        #[inline(always)]
        fn run<I: Isa>(self, isa: I) -> Self::Output {
            let (t, mask) = isa.slab(self.0, self.1, self.2);
            (t.map(f32::to_bits), mask)
        }
    }

    #[test]
    fn octant_rows_are_the_rays_own() {
        for octant in 0..8 {
            let sign = |axis: usize| if (octant >> axis) & 1 == 1 { -1.0 } else { 1.0 };
            let ray = WideRay::new(&Ray::new(
                Vec3::ZERO,
                Vec3::new(sign(0) * 0.5, sign(1) * 2.0, sign(2)),
            ));
            assert_eq!(ray.octant(), octant);
            assert_eq!(octant_rows(octant), ray.rows(), "octant {octant}");
        }
        // −0 counts as negative, as the sign bit does.
        let ray = WideRay::new(&Ray::new(Vec3::ZERO, Vec3::new(-0.0, 0.0, 1.0)));
        assert_eq!(ray.octant(), 1);
    }

    /// Rays in every octant (signed zeros among their coordinates) through a node of boxes
    /// around the origin: each path's dispatched slab test gives the bits of the portable
    /// test on the ray's own rows. A wrong octant swaps near and far planes on some axis,
    /// which changes the entry distances of every box the ray enters.
    #[test]
    fn dispatched_slab_tests_give_the_rays_own_bits() {
        let mut n = WideNode {
            bounds: [[0.0; WIDTH]; 6],
            child: [0; WIDTH],
            count: [1; WIDTH],
        };
        for lane in 0..WIDTH {
            let s = 0.5 + lane as f32 * 0.25;
            for axis in 0..3 {
                n.bounds[axis][lane] = -s - axis as f32 * 0.125;
                n.bounds[axis + 3][lane] = s;
            }
        }
        let mut rng = crate::testing::SplitMix64(8);
        let mut coord = || match rng.next_u64() % 8 {
            0 => 0.0,
            1 => -0.0,
            r => ((rng.next_u64() >> 11) % 2001) as f32 / 500.0 - 2.0 + r as f32 * 1e-3,
        };
        let mut octants = [0u32; 8];
        let mut entered = 0;
        for case in 0..4_000 {
            let o = Vec3::new(coord(), coord(), coord()) * 3.0;
            let d = Vec3::new(coord(), coord(), coord());
            let ray = WideRay::new(&Ray::new(o, d));
            octants[ray.octant()] += 1;
            for t_max in [f32::INFINITY, 2.0] {
                let want = Slab(&ray, &n, t_max).run(Portable);
                entered += want.1.count_ones();
                let got = dispatch(Portable, ray.octant(), Slab(&ray, &n, t_max));
                assert_eq!(got, want, "portable, case {case}: o {o} d {d}");
                if let Some(avx) = Avx2::detect_cpu() {
                    let got = avx.per_octant(ray.octant(), Slab(&ray, &n, t_max));
                    assert_eq!(got, want, "AVX2, case {case}: o {o} d {d}");
                }
                if let Some(avx) = Avx512::detect_cpu() {
                    let got = avx.per_octant(ray.octant(), Slab(&ray, &n, t_max));
                    assert_eq!(got, want, "AVX-512, case {case}: o {o} d {d}");
                }
            }
        }
        assert!(octants.iter().all(|&c| c > 100), "octants {octants:?}");
        assert!(entered > 4_000, "too few boxes entered: {entered}");
    }
}
