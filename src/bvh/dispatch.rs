//! What a query does before and after its kernel: the finiteness test of the ray, the kernel
//! path (instruction set × triangle test) chosen once when the structure is built, and the
//! caller-owned traversal stacks ([`Scratch`]). Per primary ray this overhead was as many
//! instructions as the kernel's node tests (`docs/bvh.md`, 2026-11-26, seventh session), so
//! each piece is kept to a few instructions: one `match` on one byte, scalar loads of the ray
//! (never a wide load over the narrow stores of a ray the caller has just built), and no
//! thread-local lookup when the caller holds a [`Scratch`].
//!
//! Stage: queries, for `two_level.rs`.

use super::isa::{Isa, Portable, Simd};
use super::mesh_bvh::{MollerTrumbore, Watertight};
use super::query::{AnyOn, ClosestOn, ClosestOneOn};
use super::slot_hit::PackedSlotHit;
use super::traverse::{with_stacks, Entry, SCRATCH};
use super::two_level::{Placed, TwoLevel};
use super::{Hit, TriangleTest};
use crate::geom::avx2::{Avx2, Avx512, Kernel};
use crate::geom::Ray;

/// The kernels a query runs on, with the token that proves the CPU has them, and the
/// triangle test: one flat enum, so a query dispatches with one `match` (it was two, on the
/// test and then on the instruction set).
#[derive(Debug, Clone, Copy)]
pub(super) enum Path {
    PortableMoller,
    PortableWatertight,
    Avx2Moller(Avx2),
    Avx2Watertight(Avx2),
    Avx512Moller(Avx512),
    Avx512Watertight(Avx512),
}

impl Path {
    /// The widest instruction set this CPU has (and `SCNC_SIMD` allows), running `test`.
    pub(super) fn detect(test: TriangleTest) -> Path {
        if let Some(avx) = Avx512::detect() {
            Path::avx512(avx, test)
        } else if let Some(avx) = Avx2::detect() {
            Path::avx2(avx, test)
        } else {
            Path::portable(test)
        }
    }

    fn portable(test: TriangleTest) -> Path {
        match test {
            TriangleTest::MollerTrumbore => Path::PortableMoller,
            TriangleTest::Watertight => Path::PortableWatertight,
        }
    }

    fn avx2(avx: Avx2, test: TriangleTest) -> Path {
        match test {
            TriangleTest::MollerTrumbore => Path::Avx2Moller(avx),
            TriangleTest::Watertight => Path::Avx2Watertight(avx),
        }
    }

    fn avx512(avx: Avx512, test: TriangleTest) -> Path {
        match test {
            TriangleTest::MollerTrumbore => Path::Avx512Moller(avx),
            TriangleTest::Watertight => Path::Avx512Watertight(avx),
        }
    }

    /// The triangle test it runs.
    pub(super) fn test(self) -> TriangleTest {
        match self {
            Path::PortableMoller | Path::Avx2Moller(_) | Path::Avx512Moller(_) => {
                TriangleTest::MollerTrumbore
            }
            Path::PortableWatertight | Path::Avx2Watertight(_) | Path::Avx512Watertight(_) => {
                TriangleTest::Watertight
            }
        }
    }

    /// The instruction set it runs on.
    pub(super) fn simd(self) -> Simd {
        match self {
            Path::PortableMoller | Path::PortableWatertight => Simd::Portable,
            Path::Avx2Moller(_) | Path::Avx2Watertight(_) => Simd::Avx2,
            Path::Avx512Moller(_) | Path::Avx512Watertight(_) => Simd::Avx512,
        }
    }

    /// The same test on `simd`; `None` if this CPU cannot run it.
    pub(super) fn with_simd(self, simd: Simd) -> Option<Path> {
        let test = self.test();
        match simd {
            Simd::Portable => Some(Path::portable(test)),
            Simd::Avx2 => Avx2::detect_cpu().map(|avx| Path::avx2(avx, test)),
            Simd::Avx512 => Avx512::detect_cpu().map(|avx| Path::avx512(avx, test)),
        }
    }
}

/// `$body` with `$test` naming the path's triangle test (a type) and `$isa` bound to its
/// instruction set's token: one `match` on the one-byte [`Path`].
macro_rules! on_path {
    ($path:expr, |$test:ident, $isa:ident| $body:expr) => {
        match $path {
            Path::PortableMoller => {
                type $test = MollerTrumbore;
                let $isa = Portable;
                $body
            }
            Path::PortableWatertight => {
                type $test = Watertight;
                let $isa = Portable;
                $body
            }
            Path::Avx2Moller($isa) => {
                type $test = MollerTrumbore;
                $body
            }
            Path::Avx2Watertight($isa) => {
                type $test = Watertight;
                $body
            }
            Path::Avx512Moller($isa) => {
                type $test = MollerTrumbore;
                $body
            }
            Path::Avx512Watertight($isa) => {
                type $test = Watertight;
                $body
            }
        }
    };
}

impl TwoLevel {
    /// The nearest hit along `ray` before its `t_max` (none for a non-finite ray), with this
    /// thread's stacks.
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        if !traceable(ray) {
            return None;
        }
        // One placement (the common case: every mesh placed once, unmoved): the thread-local
        // borrow returns the kernel's packed hit in registers, resolved out here.
        if let [p] = self.placed.as_slice() {
            let h = with_stacks(|s| self.closest_one(p, ray, s));
            return self.resolve(p, h);
        }
        with_stacks(|s| self.closest_top(ray, s))
    }

    /// [`Self::closest_hit`] with the caller's stacks.
    pub fn closest_hit_with(&self, ray: &Ray, scratch: &mut Scratch) -> Option<Hit> {
        if !traceable(ray) {
            return None;
        }
        if let [p] = self.placed.as_slice() {
            let h = self.closest_one(p, ray, scratch.entries());
            return self.resolve(p, h);
        }
        self.closest_top(ray, scratch.entries())
    }

    /// The closest hit of the one placement `p`, in its kernel.
    #[inline(always)]
    fn closest_one(&self, p: &Placed, ray: &Ray, stacks: &mut [Entry]) -> PackedSlotHit {
        on_path!(self.path, |T, isa| isa
            .enter(ClosestOneOn::<T>::new(self, p, ray, stacks)))
    }

    /// The closest hit through the top level, in the kernel.
    #[inline(always)]
    fn closest_top(&self, ray: &Ray, stacks: &mut [Entry]) -> Option<Hit> {
        on_path!(self.path, |T, isa| isa
            .enter(ClosestOn::<T>::new(self, ray, stacks)))
    }

    /// The hit of the one placement `p` from its kernel's packed hit.
    #[inline(always)]
    fn resolve(&self, p: &Placed, packed: PackedSlotHit) -> Option<Hit> {
        let h = packed.unpack();
        let m = self.meshes[p.group as usize].mesh_hit(h)?;
        let instance = if p.merged {
            self.merged_instances[m.part as usize]
        } else {
            p.index
        };
        Some(Hit {
            t: h.t,
            u: m.u,
            v: m.v,
            instance,
            prim: m.prim,
        })
    }

    /// Whether anything blocks `ray` before its `t_max` (shadow rays), with this thread's
    /// stacks.
    pub fn any_hit(&self, ray: &Ray) -> bool {
        if !traceable(ray) {
            return false;
        }
        with_stacks(|s| self.any_on_path(ray, s))
    }

    /// [`Self::any_hit`] with the caller's stacks.
    pub fn any_hit_with(&self, ray: &Ray, scratch: &mut Scratch) -> bool {
        if !traceable(ray) {
            return false;
        }
        self.any_on_path(ray, scratch.entries())
    }

    /// The any-hit query on this structure's path.
    #[inline(always)]
    fn any_on_path(&self, ray: &Ray, stacks: &mut [Entry]) -> bool {
        on_path!(self.path, |T, isa| isa
            .enter(AnyOn::<T>::new(self, ray, stacks)))
    }

    /// The instruction set queries run on.
    pub fn simd(&self) -> Simd {
        self.path.simd()
    }

    /// Makes queries run on `simd`; `false` (and no change) if this CPU cannot run it.
    pub fn force_simd(&mut self, simd: Simd) -> bool {
        self.path
            .with_simd(simd)
            .map(|path| self.path = path)
            .is_some()
    }
}

/// Entering an instruction set's kernel: the portable path calls the query in place, the AVX
/// paths through their token's function compiled for the instruction set.
pub(super) trait Enter: Isa {
    /// Runs `kernel` on this instruction set.
    fn enter<K: Kernel<Self>>(self, kernel: K) -> K::Output;
}

impl Enter for Portable {
    #[inline(always)]
    fn enter<K: Kernel<Portable>>(self, kernel: K) -> K::Output {
        run_portable(self, kernel)
    }
}

/// The portable kernel in a function of its own, as `Avx2::run` and `Avx512::run` enter
/// theirs: inlined into the query's entry, its use of the ray made LLVM load the ray's
/// coordinates in 8-byte pairs for the finiteness test too (and keep a 1.2 KB frame), on
/// every path.
#[inline(never)]
fn run_portable<K: Kernel<Portable>>(isa: Portable, kernel: K) -> K::Output {
    kernel.call(isa)
}

impl Enter for Avx2 {
    #[inline(always)]
    fn enter<K: Kernel<Avx2>>(self, kernel: K) -> K::Output {
        self.run(kernel)
    }
}

impl Enter for Avx512 {
    #[inline(always)]
    fn enter<K: Kernel<Avx512>>(self, kernel: K) -> K::Output {
        self.run(kernel)
    }
}

/// Whether a query can trace `ray`: origin and direction finite, `t_max` not NaN. For a
/// finite `x`, `s + x − x` is `s` exactly when `s` is 0 (and `x − x` is 0); an infinite or
/// NaN `x` makes it NaN, and NaN stays NaN. So the chain below is 0 exactly when all six are
/// finite: 4-byte loads, eleven dependent operations, one compare and one branch (the six
/// `is_finite` tests were six and-compare-branch triples). A chain, not a sum of pairs:
/// LLVM vectorised the pairs with 8-byte loads, which, as the one vector compare's 16-byte
/// loads did, do not forward from the 4-byte stores of a ray built just before the call.
#[inline(always)]
#[allow(
    clippy::eq_op,
    reason = "x − x is the test: 0 for a finite x, NaN otherwise"
)]
pub(super) fn traceable(ray: &Ray) -> bool {
    let (o, d) = (ray.origin, ray.dir);
    let chain = (o.x - o.x) + o.y - o.y + o.z - o.z + d.x - d.x + d.y - d.y + d.z - d.z;
    chain == 0.0 && !ray.t_max.is_nan()
}

/// Traversal stacks a caller keeps and hands to every query it makes
/// ([`crate::bvh::Accel::closest_hit_with`]): one per thread, made once (16 KB, zeroed), as
/// Embree's callers keep an intersect context. Queries without one reach a thread-local copy
/// on every call (an indirect call to the thread-local accessor and a `RefCell` borrow).
#[derive(Debug, Clone)]
pub struct Scratch {
    entries: Box<[Entry]>,
}

impl Scratch {
    /// Stacks for any query on any structure.
    pub fn new() -> Scratch {
        Scratch {
            entries: vec![(0, 0, 0.0); SCRATCH].into_boxed_slice(),
        }
    }

    /// The two `STACK_MAX` halves a query splits it into.
    #[inline(always)]
    pub(super) fn entries(&mut self) -> &mut [Entry] {
        &mut self.entries
    }
}

impl Default for Scratch {
    fn default() -> Scratch {
        Scratch::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn traceable_is_the_six_finiteness_tests_and_t_max_not_nan() {
        let specials = [
            0.0,
            -0.0,
            1.0,
            -3.0e38,
            f32::MAX,
            f32::MIN_POSITIVE * 0.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        for (k, &s) in specials.iter().enumerate() {
            for coord in 0..6 {
                let mut c = [0.25f32, -1.0, 2.0, 0.5, 0.0, -0.75];
                c[coord] = s;
                for t_max in [f32::INFINITY, 1.0, 0.0, f32::NAN] {
                    let ray = Ray {
                        origin: Vec3::new(c[0], c[1], c[2]),
                        dir: Vec3::new(c[3], c[4], c[5]),
                        t_max,
                    };
                    let expected = ray.origin.is_finite() && ray.dir.is_finite() && !t_max.is_nan();
                    assert_eq!(
                        traceable(&ray),
                        expected,
                        "special {k}, coordinate {coord}, {t_max}"
                    );
                }
            }
        }
    }
}
