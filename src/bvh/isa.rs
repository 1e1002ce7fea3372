//! The instruction set a query runs on, chosen at run time: the node slab test and the leaf's
//! watertight triangle test, each in a portable form (SSE: glam's four-lane `Vec4`, NEON
//! elsewhere) and in an AVX2 form (eight lanes in one register: the whole 8-wide node in one
//! test, two packets of four triangles at once), which the AVX-512 path runs compiled for
//! AVX-512 (32 registers, the node's compare straight into a mask register).
//!
//! Stage: queries. `dispatch.rs` enters the path chosen at build ([`Simd`], from CPU
//! detection); `traverse.rs` and `mesh_bvh.rs` are generic over [`Isa`], so each
//! path is one monomorphic loop. Both forms compute the same bits (same operations, same
//! order, no fused multiply-adds), so which path runs never changes a hit or an image.

use super::octant::{self, OctantQuery};
use super::wide::{Rows, WideNode, WideRay, EXIT_SLACK, WIDTH};
use crate::geom::avx2::{Avx2, Avx512, F8};
use crate::geom::triangle::{TriangleHit, WatertightRay};
use crate::geom::triangle4::{any4, closest4, Tri4};
use crate::geom::triangle8::{any8, closest8};

/// Which instruction set the BVH's queries run on (`Accel::simd`, `Accel::force_simd`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Simd {
    /// Four-lane SSE (x86-64's baseline; NEON or scalar elsewhere): runs on every CPU.
    Portable,
    /// Eight-lane AVX2, chosen when the CPU has AVX2 and FMA (and no AVX-512, or
    /// `SCNC_SIMD=avx2`), unless `SCNC_SIMD=portable`.
    Avx2,
    /// The AVX2 kernels compiled for AVX-512 F/VL/BW/DQ (still eight lanes: 32 registers and
    /// mask compares), chosen when the CPU has it, unless `SCNC_SIMD` is `portable` or `avx2`.
    Avx512,
}

/// The kernels of one instruction set.
pub trait Isa: Copy {
    /// Entry distances of the node's children and the mask (bit k) of those entered within
    /// `(0, t_max)`.
    #[inline(always)]
    fn slab(self, ray: &WideRay, n: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        self.slab_rows(ray, n, t_max, ray.rows())
    }
    /// [`Self::slab`] with the near and far bounds rows given (`ray`'s own, or constants).
    fn slab_rows(self, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32);
    /// Runs `query` on this instruction set: on the AVX2 and AVX-512 paths inside a copy
    /// specialised for the direction `octant` (`octant.rs`), elsewhere as it is.
    fn per_octant<Q: OctantQuery>(self, octant: usize, query: Q) -> Q::Output;
    /// The closest watertight hit among the packets `tris`, as `triangle4::closest4`.
    fn closest_tris(
        self,
        r: &WatertightRay,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)>;
    /// Whether any triangle of `tris` is hit, as `triangle4::any4`.
    fn any_tris(self, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool;
    /// Asks for the cache lines of `at` to be loaded ahead of use (a hint; may do nothing).
    fn prefetch<T: ?Sized>(self, at: &T);
}

/// The portable kernels: [`WideRay::hit`] and the four-lane triangle test.
#[derive(Debug, Clone, Copy)]
pub struct Portable;

impl Isa for Portable {
    #[inline(always)]
    fn slab(self, ray: &WideRay, n: &WideNode, t_max: f32) -> ([f32; WIDTH], u32) {
        ray.hit(n, t_max)
    }
    #[inline(always)]
    fn slab_rows(self, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32) {
        ray.hit_rows(n, t_max, rows)
    }
    /// As it is: eight copies of the loop for the path of CPUs without AVX2 are not worth
    /// their size.
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
        closest4(r, t_max, tris)
    }
    #[inline(always)]
    fn any_tris(self, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
        any4(r, t_max, tris)
    }
    /// Nothing: a prefetch instruction needs the `unsafe` token module, and this path is
    /// the one for CPUs without AVX2.
    #[inline(always)]
    fn prefetch<T: ?Sized>(self, _: &T) {}
}

/// [`WideRay::hit`] on all eight lanes at once, the same operations in the same order, up to
/// the final comparison: the entry distances and the slackened exit distances.
#[inline(always)]
fn slab8(avx: Avx2, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> (F8, F8) {
    // No closures here: their bodies might not be inlined into the AVX2 kernel.
    let (near, far) = (&rows.0, &rows.1);
    let (nx, ny, nz) = (
        plane(avx, n, near[0], ray.origin(0), ray.inv_dir(0)),
        plane(avx, n, near[1], ray.origin(1), ray.inv_dir(1)),
        plane(avx, n, near[2], ray.origin(2), ray.inv_dir(2)),
    );
    let (fx, fy, fz) = (
        plane(avx, n, far[0], ray.origin(0), ray.inv_dir_far(0)),
        plane(avx, n, far[1], ray.origin(1), ray.inv_dir_far(1)),
        plane(avx, n, far[2], ray.origin(2), ray.inv_dir_far(2)),
    );
    // The tree grouping of `WideRay::hit`; the slack is in the far reciprocals and here.
    let t_near = avx.max(avx.max(avx.splat(0.0), nx), avx.max(ny, nz));
    let t_exit = avx.min(avx.min(avx.splat(t_max * EXIT_SLACK), fx), avx.min(fy, fz));
    (t_near, t_exit)
}

/// The distances to the planes of bounds row `row` of the eight children, from the origin's
/// coordinate `org` with reciprocal `inv`.
#[inline(always)]
fn plane(avx: Avx2, n: &WideNode, row: usize, org: f32, inv: f32) -> F8 {
    avx.mul(
        avx.sub(avx.load(&n.bounds[row]), avx.splat(org)),
        avx.splat(inv),
    )
}

impl Isa for Avx2 {
    /// [`WideRay::hit`] on all eight lanes at once: the same operations in the same order.
    #[inline(always)]
    fn slab_rows(self, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32) {
        let (t_near, t_exit) = slab8(self, ray, n, t_max, rows);
        (self.store(t_near), self.bitmask(self.le(t_near, t_exit)))
    }
    #[inline(always)]
    fn per_octant<Q: OctantQuery>(self, octant: usize, query: Q) -> Q::Output {
        octant::dispatch(self, octant, query)
    }
    #[inline(always)]
    fn closest_tris(
        self,
        r: &WatertightRay,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)> {
        closest8(self, r, t_max, tris)
    }
    #[inline(always)]
    fn any_tris(self, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
        any8(self, r, t_max, tris)
    }
    #[inline(always)]
    fn prefetch<T: ?Sized>(self, at: &T) {
        Avx2::prefetch(self, at);
    }
}

impl Isa for Avx512 {
    /// The AVX2 slab test, its last comparison made straight into a mask register.
    #[inline(always)]
    fn slab_rows(self, ray: &WideRay, n: &WideNode, t_max: f32, rows: Rows) -> ([f32; WIDTH], u32) {
        let (t_near, t_exit) = slab8(self.avx2(), ray, n, t_max, rows);
        (self.avx2().store(t_near), self.le_mask(t_near, t_exit))
    }
    #[inline(always)]
    fn per_octant<Q: OctantQuery>(self, octant: usize, query: Q) -> Q::Output {
        octant::dispatch(self, octant, query)
    }
    #[inline(always)]
    fn closest_tris(
        self,
        r: &WatertightRay,
        t_max: &mut f32,
        tris: &[Tri4],
    ) -> Option<(usize, TriangleHit)> {
        closest8(self.avx2(), r, t_max, tris)
    }
    #[inline(always)]
    fn any_tris(self, r: &WatertightRay, t_max: f32, tris: &[Tri4]) -> bool {
        any8(self.avx2(), r, t_max, tris)
    }
    #[inline(always)]
    fn prefetch<T: ?Sized>(self, at: &T) {
        self.avx2().prefetch(at);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::avx2::Kernel;
    use crate::geom::Ray;
    use glam::Vec3;

    /// A node of eight random boxes (some flat, some empty lanes).
    fn node(seed: u64) -> WideNode {
        let mut s = seed;
        let mut next = move || {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (s >> 40) as f32 / (1u64 << 24) as f32 * 4.0 - 2.0
        };
        let mut n = WideNode {
            bounds: [[0.0; WIDTH]; 6],
            child: [0; WIDTH],
            count: [1; WIDTH],
        };
        for lane in 0..WIDTH {
            for axis in 0..3 {
                let (a, b) = (next(), next());
                let flat = lane == 3 && axis == 1;
                n.bounds[axis][lane] = a.min(b);
                n.bounds[axis + 3][lane] = if flat { a.min(b) } else { a.max(b) };
            }
            if lane >= 6 {
                for axis in 0..3 {
                    n.bounds[axis][lane] = f32::INFINITY;
                    n.bounds[axis + 3][lane] = f32::NEG_INFINITY;
                }
            }
        }
        n
    }

    /// Every case's slab test on `isa`, inside its kernel function.
    struct AllCases;
    impl<I: Isa> Kernel<I> for AllCases {
        type Output = Vec<([f32; WIDTH], u32)>;
        #[inline(always)]
        fn call(self, isa: I) -> Self::Output {
            cases()
                .iter()
                .map(|(ray, n, t)| isa.slab(ray, n, *t))
                .collect()
        }
    }

    /// 4,000 nodes, each against a ray with axis-parallel and signed-zero direction
    /// components (where the reciprocal is replaced) in turn, to an infinite and a finite
    /// `t_max`.
    fn cases() -> Vec<(WideRay, WideNode, f32)> {
        let mut out = Vec::new();
        for case in 0..4_000u64 {
            let n = node(case);
            let f = |k: u64| ((case * 7 + k) % 13) as f32 / 3.0 - 2.0;
            let mut dir = Vec3::new(f(1), f(2), f(3));
            match case % 4 {
                0 => dir.x = 0.0,
                1 => dir.y = -0.0,
                _ => {}
            }
            let ray = WideRay::new(&Ray::new(Vec3::new(f(4), f(5), f(6)) * 2.0, dir));
            for t_max in [f32::INFINITY, 1.5] {
                out.push((ray, n, t_max));
            }
        }
        out
    }

    #[test]
    fn each_path_slab_test_gives_the_portable_bits_inside_its_kernel() {
        let want = AllCases.call(Portable);
        let bits = |v: &[([f32; WIDTH], u32)]| {
            v.iter()
                .map(|(t, m)| (t.map(f32::to_bits), *m))
                .collect::<Vec<_>>()
        };
        if let Some(avx) = Avx2::detect_cpu() {
            assert_eq!(bits(&avx.run(AllCases)), bits(&want), "AVX2");
        }
        match Avx512::detect_cpu() {
            Some(avx) => assert_eq!(bits(&avx.run(AllCases)), bits(&want), "AVX-512"),
            None => eprintln!("no AVX-512 on this CPU: that path not compared"),
        }
    }

    #[test]
    fn avx2_slab_test_gives_the_portable_bits() {
        let Some(avx) = Avx2::detect_cpu() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let mut entered = 0;
        for (case, (ray, n, t_max)) in cases().iter().enumerate() {
            let (tp, mp) = Portable.slab(ray, n, *t_max);
            let (ta, ma) = avx.slab(ray, n, *t_max);
            assert_eq!(ma, mp, "case {case}");
            assert_eq!(ta.map(f32::to_bits), tp.map(f32::to_bits), "case {case}");
            assert_eq!(ma & 0b1100_0000, 0, "empty lanes are never entered");
            entered += ma.count_ones();
        }
        assert!(
            entered > 1_000,
            "too few boxes entered to test anything: {entered}"
        );
    }
}
