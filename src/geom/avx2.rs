//! AVX2 on eight `f32` lanes, behind a token that only run-time detection can make: the one
//! module of the crate allowed `unsafe` code (see `docs/bvh.md`, "Instruction set").
//!
//! Stage: geometry support, below the BVH. The slab test of `bvh::isa` and the eight-triangle
//! test of [`super::triangle8`] are written, in safe code, against the methods here; each
//! method is one `core::arch` intrinsic. Holding an [`Avx2`] proves the CPU has AVX2 and FMA
//! (the only constructor is [`Avx2::detect`]), which is what makes every call below sound.
//! [`Avx2::prefetch`] is the one method of several instructions: a `prefetcht0` per cache line
//! of a value (a hint that can neither fault nor change a value).
//! [`Avx2::run`] enters a function compiled for AVX2, into which the query's traversal and leaf
//! tests are inlined, so the intrinsics become single instructions.
//!
//! Every operation is the IEEE one that the SSE path (glam's `Vec4`) performs, with the same
//! operand order for `min`/`max` (NaN handling) and the same comparison predicates, and no
//! fused multiply-add is ever formed: the AVX2 path computes the same bits as the portable one,
//! lane for lane (tests compare them).
//!
//! [`Avx512`] is the same token on a CPU that also has AVX-512 (F, VL, BW, DQ): its
//! [`Avx512::run`] compiles the same kernels for AVX-512, which gives the compiler 32 vector
//! registers instead of 16 (the traversal's ray constants stay in registers instead of being
//! spilled) and compares straight into mask registers; [`Avx512::le_mask`] is the one explicit
//! AVX-512 operation. The registers stay 256 bits wide (AVX-512VL), so the CPU keeps its AVX2
//! clock. Same IEEE operations, same bits.
//!
//! `SCNC_SIMD=portable`, `avx2` or `avx512` caps the path a process uses (read once).
//!
//! On other architectures [`Avx2`] and [`Avx512`] are uninhabited: `detect` returns `None` and
//! the methods are never reached.
#![allow(unsafe_code)]

#[cfg(target_arch = "x86_64")]
use core::arch::x86_64::*;

/// Proof that the CPU runs AVX2 and FMA instructions; made only by [`Avx2::detect`].
#[derive(Debug, Clone, Copy)]
pub struct Avx2 {
    _proof: Proof,
}

#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
struct Proof;

#[cfg(not(target_arch = "x86_64"))]
#[derive(Debug, Clone, Copy)]
enum Proof {}

/// Eight `f32` lanes (a comparison result holds all-ones or all-zeros lanes).
#[derive(Debug, Clone, Copy)]
pub struct F8(
    #[cfg(target_arch = "x86_64")] __m256,
    #[cfg(not(target_arch = "x86_64"))] Proof,
);

/// Proof that the CPU runs AVX2, FMA and AVX-512 F, VL, BW and DQ; made only by
/// [`Avx512::detect`]. Every [`Avx2`] operation is available through [`Avx512::avx2`].
#[derive(Debug, Clone, Copy)]
pub struct Avx512 {
    avx2: Avx2,
}

/// A computation to run inside [`Avx2::run`] or [`Avx512::run`] with the token `T` (a trait
/// rather than a closure so that its body is `#[inline(always)]` and so compiled for the
/// instruction set with everything it inlines).
pub trait Kernel<T> {
    /// What it returns.
    type Output;
    /// Runs it; the implementation should be `#[inline(always)]`.
    fn call(self, token: T) -> Self::Output;
}

/// Bytes in a cache line on every x86-64 CPU (the unit [`Avx2::prefetch`] asks for).
#[cfg(target_arch = "x86_64")]
const CACHE_LINE: usize = 64;

/// Cache lines touched by `len` bytes that start `skew` bytes into a line.
#[cfg(target_arch = "x86_64")]
fn lines_spanned(skew: usize, len: usize) -> usize {
    (skew + len).div_ceil(CACHE_LINE)
}

/// The widest path `SCNC_SIMD` allows (read once per process): 0 portable, 1 AVX2, 2 AVX-512
/// (unset or any other value: no cap).
fn allowed_level() -> u8 {
    use std::sync::OnceLock;
    static LEVEL: OnceLock<u8> = OnceLock::new();
    *LEVEL.get_or_init(|| match std::env::var("SCNC_SIMD").as_deref() {
        Ok("portable") => 0,
        Ok("avx2") => 1,
        _ => 2,
    })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_avx2<K: Kernel<Avx2>>(avx: Avx2, kernel: K) -> K::Output {
    kernel.call(avx)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512bw,avx512dq")]
unsafe fn run_avx512<K: Kernel<Avx512>>(avx: Avx512, kernel: K) -> K::Output {
    kernel.call(avx)
}

#[cfg(target_arch = "x86_64")]
#[allow(
    clippy::inline_always,
    reason = "each method is one instruction in the kernels"
)]
impl Avx512 {
    /// The token if this CPU has AVX2, FMA and AVX-512 F/VL/BW/DQ and `SCNC_SIMD` does not ask
    /// for a narrower path.
    pub fn detect() -> Option<Avx512> {
        Avx512::detect_cpu().filter(|_| allowed_level() >= 2)
    }

    /// The token if this CPU has the features, whatever the environment says (for tests).
    pub fn detect_cpu() -> Option<Avx512> {
        let avx2 = Avx2::detect_cpu()?;
        (is_x86_feature_detected!("avx512f")
            && is_x86_feature_detected!("avx512vl")
            && is_x86_feature_detected!("avx512bw")
            && is_x86_feature_detected!("avx512dq"))
        .then_some(Avx512 { avx2 })
    }

    /// The AVX2 operations (all of them run here, compiled with AVX-512's registers).
    #[inline(always)]
    pub fn avx2(self) -> Avx2 {
        self.avx2
    }

    /// Runs `kernel` inside a function compiled for AVX2, FMA and AVX-512 F/VL/BW/DQ.
    #[inline(always)]
    pub fn run<K: Kernel<Avx512>>(self, kernel: K) -> K::Output {
        // SAFETY: the token exists, so the CPU has the features `run_avx512` is compiled for.
        unsafe { run_avx512(self, kernel) }
    }

    /// Bit `k` set where `a ≤ b` in lane `k` (ordered: false for NaN), compared straight into
    /// a mask register: `bitmask(le(a, b))` in one instruction.
    #[inline(always)]
    pub fn le_mask(self, a: F8, b: F8) -> u32 {
        // SAFETY: the token proves AVX-512 F and VL.
        u32::from(unsafe { _mm256_cmp_ps_mask::<_CMP_LE_OQ>(a.0, b.0) })
    }
}

#[cfg(not(target_arch = "x86_64"))]
#[allow(
    missing_docs,
    clippy::inline_always,
    reason = "never reached: no token exists"
)]
impl Avx512 {
    pub fn detect() -> Option<Avx512> {
        None
    }
    pub fn detect_cpu() -> Option<Avx512> {
        None
    }
    pub fn avx2(self) -> Avx2 {
        self.avx2
    }
    pub fn run<K: Kernel<Avx512>>(self, _: K) -> K::Output {
        match self.avx2._proof {}
    }
    pub fn le_mask(self, _: F8, _: F8) -> u32 {
        match self.avx2._proof {}
    }
}

#[cfg(target_arch = "x86_64")]
#[allow(
    clippy::inline_always,
    reason = "each method is one instruction in the kernels"
)]
impl Avx2 {
    /// The token if this CPU has AVX2 and FMA and `SCNC_SIMD=portable` is not set.
    pub fn detect() -> Option<Avx2> {
        Avx2::detect_cpu().filter(|_| allowed_level() >= 1)
    }

    /// The token if this CPU has AVX2 and FMA, whatever the environment says (for tests).
    pub fn detect_cpu() -> Option<Avx2> {
        (is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"))
            .then_some(Avx2 { _proof: Proof })
    }

    /// Runs `kernel` inside a function compiled for AVX2 and FMA.
    #[inline(always)]
    pub fn run<K: Kernel<Avx2>>(self, kernel: K) -> K::Output {
        // SAFETY: the token exists, so the CPU has the features `run_avx2` is compiled for.
        unsafe { run_avx2(self, kernel) }
    }

    /// `x` in every lane.
    #[inline(always)]
    pub fn splat(self, x: f32) -> F8 {
        // SAFETY (here and below): the token proves AVX2 and FMA; no pointer is read except
        // through a reference to an array of exactly the size loaded.
        F8(unsafe { _mm256_set1_ps(x) })
    }

    /// The eight values of `a`.
    #[inline(always)]
    pub fn load(self, a: &[f32; 8]) -> F8 {
        F8(unsafe { _mm256_loadu_ps(a.as_ptr()) })
    }

    /// `lo` in lanes 0–3, `hi` in lanes 4–7.
    #[inline(always)]
    pub fn load2(self, lo: &[f32; 4], hi: &[f32; 4]) -> F8 {
        F8(unsafe { _mm256_loadu2_m128(hi.as_ptr(), lo.as_ptr()) })
    }

    /// The eight lanes as an array.
    #[inline(always)]
    pub fn store(self, v: F8) -> [f32; 8] {
        let mut out = [0.0f32; 8];
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v.0) };
        out
    }

    /// `a + b`.
    #[inline(always)]
    pub fn add(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_add_ps(a.0, b.0) })
    }

    /// `a − b`.
    #[inline(always)]
    pub fn sub(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_sub_ps(a.0, b.0) })
    }

    /// `a · b` (rounded; never fused with a neighbouring addition).
    #[inline(always)]
    pub fn mul(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_mul_ps(a.0, b.0) })
    }

    /// `a / b`.
    #[inline(always)]
    pub fn div(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_div_ps(a.0, b.0) })
    }

    /// `minps a, b`: `b` where either is NaN, as glam's `Vec4::min`.
    #[inline(always)]
    pub fn min(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_min_ps(a.0, b.0) })
    }

    /// `maxps a, b`: `b` where either is NaN, as glam's `Vec4::max`.
    #[inline(always)]
    pub fn max(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_max_ps(a.0, b.0) })
    }

    /// `|a|` (the sign bit cleared).
    #[inline(always)]
    pub fn abs(self, a: F8) -> F8 {
        F8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), a.0) })
    }

    /// `a < b` (ordered: false for NaN).
    #[inline(always)]
    pub fn lt(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(a.0, b.0) })
    }

    /// `a ≤ b` (ordered).
    #[inline(always)]
    pub fn le(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(a.0, b.0) })
    }

    /// `a > b` (ordered).
    #[inline(always)]
    pub fn gt(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(a.0, b.0) })
    }

    /// `a = b` (ordered).
    #[inline(always)]
    pub fn eq(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(a.0, b.0) })
    }

    /// `a ≠ b` (unordered: true for NaN, as SSE's `cmpneqps`).
    #[inline(always)]
    pub fn ne(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_cmp_ps::<_CMP_NEQ_UQ>(a.0, b.0) })
    }

    /// Bitwise and of two masks.
    #[inline(always)]
    pub fn and(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_and_ps(a.0, b.0) })
    }

    /// Bitwise or of two masks.
    #[inline(always)]
    pub fn or(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_or_ps(a.0, b.0) })
    }

    /// Bitwise `b & !a` (`andnps a, b`): the lanes of mask `b` that mask `a` leaves clear.
    #[inline(always)]
    pub fn and_not(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_andnot_ps(a.0, b.0) })
    }

    /// Bitwise exclusive or (with a sign-bit mask: an exact negation where the bit is set).
    #[inline(always)]
    pub fn xor(self, a: F8, b: F8) -> F8 {
        F8(unsafe { _mm256_xor_ps(a.0, b.0) })
    }

    /// `if_true` where `mask` is set, else `if_false`.
    #[inline(always)]
    pub fn select(self, mask: F8, if_true: F8, if_false: F8) -> F8 {
        F8(unsafe { _mm256_blendv_ps(if_false.0, if_true.0, mask.0) })
    }

    /// Bit `k` set where lane `k`'s sign bit is (a mask's lanes).
    #[inline(always)]
    pub fn bitmask(self, mask: F8) -> u32 {
        (unsafe { _mm256_movemask_ps(mask.0) }) as u32
    }

    /// Asks for every cache line `at` occupies to be brought into the L1 cache
    /// (`prefetcht0`); a hint, with no effect on any value.
    #[inline(always)]
    pub fn prefetch<T: ?Sized>(self, at: &T) {
        let start = (at as *const T).cast::<i8>();
        let skew = start as usize % CACHE_LINE;
        let line = start.wrapping_sub(skew);
        for k in 0..lines_spanned(skew, std::mem::size_of_val(at)) {
            // SAFETY: a prefetch never faults and changes no value; each address lies on a
            // cache line that `at` occupies.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line.wrapping_add(CACHE_LINE * k)) };
        }
    }
}

#[cfg(not(target_arch = "x86_64"))]
#[allow(
    missing_docs,
    clippy::inline_always,
    reason = "never reached: no token exists"
)]
impl Avx2 {
    pub fn detect() -> Option<Avx2> {
        let _ = allowed_level;
        None
    }
    pub fn detect_cpu() -> Option<Avx2> {
        None
    }
    pub fn run<K: Kernel<Avx2>>(self, _: K) -> K::Output {
        match self._proof {}
    }
    pub fn splat(self, _: f32) -> F8 {
        match self._proof {}
    }
    pub fn load(self, _: &[f32; 8]) -> F8 {
        match self._proof {}
    }
    pub fn load2(self, _: &[f32; 4], _: &[f32; 4]) -> F8 {
        match self._proof {}
    }
    pub fn store(self, _: F8) -> [f32; 8] {
        match self._proof {}
    }
    pub fn prefetch<T: ?Sized>(self, _: &T) {
        match self._proof {}
    }
}

#[cfg(not(target_arch = "x86_64"))]
macro_rules! unreachable_ops {
    ($($name:ident($($arg:ident),*)),*) => {
        #[allow(missing_docs, unused_variables, reason = "never reached: no token exists")]
        impl Avx2 {
            $(pub fn $name(self, $($arg: F8),*) -> F8 { match self._proof {} })*
        }
    };
}
#[cfg(not(target_arch = "x86_64"))]
unreachable_ops!(
    add(a, b),
    sub(a, b),
    mul(a, b),
    div(a, b),
    min(a, b),
    max(a, b),
    abs(a),
    lt(a, b),
    le(a, b),
    gt(a, b),
    eq(a, b),
    ne(a, b),
    and(a, b),
    or(a, b),
    and_not(a, b),
    xor(a, b),
    select(m, a, b)
);
#[cfg(not(target_arch = "x86_64"))]
impl Avx2 {
    /// Never reached: no token exists.
    pub fn bitmask(self, _: F8) -> u32 {
        match self._proof {}
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use glam::Vec4;

    /// Values that exercise NaN, ±0, infinities and rounding.
    const A: [f32; 8] = [
        1.5,
        -0.0,
        f32::NAN,
        f32::INFINITY,
        3.0e-39,
        -7.25,
        1.0e30,
        0.1,
    ];
    const B: [f32; 8] = [
        0.3,
        0.0,
        2.0,
        f32::NAN,
        -1.0,
        f32::NEG_INFINITY,
        1.0e-30,
        0.7,
    ];

    fn halves(a: [f32; 8]) -> (Vec4, Vec4) {
        (
            Vec4::new(a[0], a[1], a[2], a[3]),
            Vec4::new(a[4], a[5], a[6], a[7]),
        )
    }

    /// The bits of each lane; every NaN as one value (a NaN's sign and payload are not part
    /// of the contract: no kernel lets a NaN through, and constant folding may change them).
    fn bits(v: [f32; 8]) -> [u32; 8] {
        v.map(|x| if x.is_nan() { u32::MAX } else { x.to_bits() })
    }

    #[test]
    fn every_operation_gives_the_bits_of_the_sse_one() {
        let Some(avx) = Avx2::detect_cpu() else {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        };
        let (a, b) = (avx.load(&A), avx.load(&B));
        let (a0, a1) = halves(std::hint::black_box(A));
        let (b0, b1) = halves(std::hint::black_box(B));
        let sse = |f: &dyn Fn(Vec4, Vec4) -> Vec4| {
            let (lo, hi) = (f(a0, b0), f(a1, b1));
            [lo.x, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w]
        };
        let cases: [(&str, F8, [f32; 8]); 7] = [
            ("add", avx.add(a, b), sse(&|x, y| x + y)),
            ("sub", avx.sub(a, b), sse(&|x, y| x - y)),
            ("mul", avx.mul(a, b), sse(&|x, y| x * y)),
            ("div", avx.div(a, b), sse(&|x, y| x / y)),
            ("min", avx.min(a, b), sse(&|x, y| x.min(y))),
            ("max", avx.max(a, b), sse(&|x, y| x.max(y))),
            ("abs", avx.abs(a), sse(&|x, _| x.abs())),
        ];
        for (name, got, want) in cases {
            assert_eq!(bits(avx.store(got)), bits(want), "{name}");
        }
        let masks: [(&str, F8, u32); 5] = [
            (
                "lt",
                avx.lt(a, b),
                (a0.cmplt(b0).bitmask() | a1.cmplt(b1).bitmask() << 4),
            ),
            (
                "le",
                avx.le(a, b),
                (a0.cmple(b0).bitmask() | a1.cmple(b1).bitmask() << 4),
            ),
            (
                "gt",
                avx.gt(a, b),
                (a0.cmpgt(b0).bitmask() | a1.cmpgt(b1).bitmask() << 4),
            ),
            (
                "eq",
                avx.eq(a, b),
                (a0.cmpeq(b0).bitmask() | a1.cmpeq(b1).bitmask() << 4),
            ),
            (
                "ne",
                avx.ne(a, b),
                (a0.cmpne(b0).bitmask() | a1.cmpne(b1).bitmask() << 4),
            ),
        ];
        for (name, got, want) in masks {
            assert_eq!(avx.bitmask(got), want, "{name}");
        }
        let (lt, ne) = (avx.lt(a, b), avx.ne(a, b));
        let ne_not_lt = avx.bitmask(ne) & !avx.bitmask(lt);
        assert_ne!(ne_not_lt, 0, "some lanes to keep");
        assert_eq!(avx.bitmask(avx.and_not(lt, ne)), ne_not_lt, "and_not");
        let flipped = avx.store(avx.xor(a, avx.splat(-0.0)));
        assert_eq!(
            bits(flipped),
            bits(sse(&|x, _| -x)),
            "xor with the sign bit"
        );
        let picked = avx.store(avx.select(avx.lt(a, b), a, b));
        let want = sse(&|x, y| Vec4::select(x.cmplt(y), x, y));
        assert_eq!(bits(picked), bits(want), "select");
        let two = avx.store(avx.load2(&[1.0, 2.0, 3.0, 4.0], &[5.0, 6.0, 7.0, 8.0]));
        assert_eq!(two, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]);
        assert_eq!(avx.store(avx.splat(2.5)), [2.5; 8]);
    }

    struct Sum([f32; 8]);
    impl Kernel<Avx2> for Sum {
        type Output = f32;
        #[inline(always)]
        fn call(self, avx: Avx2) -> f32 {
            avx.store(avx.add(avx.load(&self.0), avx.splat(1.0)))
                .iter()
                .sum()
        }
    }

    #[test]
    fn kernels_run_inside_the_avx2_function() {
        if let Some(avx) = Avx2::detect_cpu() {
            assert_eq!(avx.run(Sum([1.0; 8])), 16.0);
        }
    }

    /// `le_mask` against `bitmask(le)`, inside the AVX-512 function.
    struct LeMasks;
    impl Kernel<Avx512> for LeMasks {
        type Output = (u32, u32);
        #[inline(always)]
        fn call(self, avx: Avx512) -> (u32, u32) {
            let (a, b) = (avx.avx2().load(&A), avx.avx2().load(&B));
            (avx.le_mask(a, b), avx.avx2().bitmask(avx.avx2().le(a, b)))
        }
    }

    #[test]
    fn the_mask_compare_gives_the_bits_of_the_avx2_one() {
        let Some(avx) = Avx512::detect_cpu() else {
            eprintln!("no AVX-512 on this CPU: nothing to compare");
            return;
        };
        let (mask, want) = avx.run(LeMasks);
        assert_eq!(mask, want);
        assert_ne!(mask, 0, "some lanes compare true");
        assert_ne!(mask, 0xff, "some lanes compare false (NaN among them)");
    }

    #[test]
    fn prefetch_asks_for_exactly_the_lines_a_value_occupies() {
        assert_eq!(lines_spanned(0, 0), 0, "nothing to fetch");
        assert_eq!(lines_spanned(0, 256), 4, "an aligned wide node");
        for skew in [0, 16, 32, 48] {
            assert_eq!(
                lines_spanned(skew, 144),
                3,
                "a 16-byte aligned packet, {skew}"
            );
        }
        assert_eq!(lines_spanned(52, 144), 4, "144 bytes straddling four lines");
        assert_eq!(lines_spanned(63, 2), 2, "two bytes across a line boundary");
        // A hint changes nothing, whatever it is given (an empty slice, an unaligned value).
        if let Some(avx) = Avx2::detect_cpu() {
            let data = [7u8; 300];
            avx.prefetch(&data[..0]);
            avx.prefetch(&data[5..299]);
            assert_eq!(data, [7u8; 300]);
        }
    }
}
