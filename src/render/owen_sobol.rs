//! Stage 4: the points of adaptive renders' sample sequences (`rng::Sampler::point_2d`,
//! `rng::PixelSequences`): Owen-scrambled Sobol' (0,2)-sequences, one per pixel, replicate and
//! stream (pbrt-v4's padded Owen-scrambled Sobol', with the hash-based nested uniform scramble
//! of Laine–Karras / Burley 2020, as its `FastOwenScrambler`). Point `j` of a sequence: its index
//! shuffled by a nested uniform scramble (so the streams of one sample are not paired by their
//! common index), then Sobol' dimensions 0 and 1 of the shuffled index, each scrambled on its
//! own. Every power-of-two prefix and every aligned power-of-two block is a (0,m,2)-net; each
//! point is uniform on [0, 1)².
//!
//! Syntax: none of its own; `render { noise 0.05 }` / `--noise 0.05` samples with it.
//!
//! The Laine–Karras hash works on bit-reversed values (its carries run from the low bits up, so
//! reversed, each digit depends only on the digits above it). Written as scramble = reverse, hash,
//! reverse, the point takes seven 32-bit reversals, which x86 has no instruction for (a byte
//! swap and three mask-and-shift steps each). [`OwenSobol::point`] keeps the values in the
//! reversed domain between the steps instead: three reversals, the same bits as the plain
//! composition ([`OwenSobol::point_by_definition`], tested).

use glam::Vec2;

use super::rng::mix64;

/// The scramble of one stream of one sequence: the two hashes of the sequence's key and the
/// stream that every point of it shares, derived once where a loop takes several points of the
/// same sequence (`rng::PixelSequences::points_2d`).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct OwenSobol {
    bits: u64,
    seeds: u64,
}

impl OwenSobol {
    /// The scramble of `stream` of the sequence keyed by `sequence_key`.
    #[inline]
    pub(super) fn of(sequence_key: u64, stream: u64) -> OwenSobol {
        let bits = mix64(sequence_key ^ stream.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        OwenSobol {
            bits,
            seeds: mix64(bits ^ 0x2545_f491_4f6c_dd1d),
        }
    }

    /// Point `j` of the sequence: [`OwenSobol::point_by_definition`], bit for bit.
    #[inline]
    pub(super) fn point(self, j: u32) -> Vec2 {
        // The shuffled index `i`, and its reversal `u` (the hash's output before its last
        // reversal): Sobol' dimension 0 of `i` is `u`, which the x scramble reverses back.
        let u = laine_karras(j.reverse_bits(), (self.bits >> 32) as u32);
        let i = u.reverse_bits();
        let x_reversed = laine_karras(i, self.seeds as u32);
        let y_reversed = laine_karras(sobol_dim1_reversed(i), (self.seeds >> 32) as u32);
        // Both final reversals in one 64-bit reversal: x lands in the high half, y in the low.
        let both = ((u64::from(y_reversed) << 32) | u64::from(x_reversed)).reverse_bits();
        Vec2::new(bits_to_unit((both >> 32) as u32), bits_to_unit(both as u32))
    }

    /// Point `j` as the composition of whole scrambles: the index scrambled, then Sobol'
    /// dimension 0 (the bit-reversed index) and dimension 1 of it, each scrambled.
    #[cfg(test)]
    fn point_by_definition(self, j: u32) -> Vec2 {
        let i = owen_scramble(j, (self.bits >> 32) as u32);
        let x = owen_scramble(i.reverse_bits(), self.seeds as u32);
        let y = owen_scramble(sobol_dim1_by_bit(i), (self.seeds >> 32) as u32);
        Vec2::new(bits_to_unit(x), bits_to_unit(y))
    }
}

/// Points side by side: lane `k` is `scrambles[k].point(j[k])`, bit for bit, in loops over
/// fixed-length arrays that the compiler turns into vector instructions where it may (inside
/// `geom::avx2::Avx2::run`, eight lanes a vector: `render::rect_lit`'s runs of samples). One
/// point takes about 160 instructions one at a time, almost all of it in the three hashes and
/// the bit reversals (which x86 does not have: a byte swap and three mask-and-shift steps), so
/// this, not the scrambles' derivation, is what an adaptive sample's sequences cost
/// (docs/quality.md, fourteenth session).
#[inline(always)]
pub(super) fn points_side_by_side<const N: usize>(
    scrambles: &[OwenSobol; N],
    j: &[u32; N],
    out: &mut [Vec2; N],
) {
    let index_seed: [u32; N] = std::array::from_fn(|k| (scrambles[k].bits >> 32) as u32);
    let x_seed: [u32; N] = std::array::from_fn(|k| scrambles[k].seeds as u32);
    let y_seed: [u32; N] = std::array::from_fn(|k| (scrambles[k].seeds >> 32) as u32);
    let mut i = [0u32; N];
    let mut x = [0u32; N];
    for k in 0..N {
        let u = laine_karras(j[k].reverse_bits(), index_seed[k]);
        i[k] = u.reverse_bits();
        x[k] = laine_karras(i[k], x_seed[k]).reverse_bits();
    }
    let mut y = [0u32; N];
    for k in 0..N {
        y[k] = laine_karras(sobol_dim1_reversed(i[k]), y_seed[k]).reverse_bits();
    }
    for k in 0..N {
        out[k] = Vec2::new(bits_to_unit(x[k]), bits_to_unit(y[k]));
    }
}

/// The top 24 bits of a 0.32 fraction as a value in [0, 1).
#[inline]
fn bits_to_unit(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The Laine–Karras hash with Burley 2020's constants (pbrt-v4's `FastOwenScrambler` between its
/// two reversals) of the bit-reversed fraction `v`: each output bit depends on the input bits at
/// and below it only, that is on the digits at and above it of the fraction.
#[inline]
fn laine_karras(mut v: u32, seed: u32) -> u32 {
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v
}

/// A nested uniform (Owen) scramble of the 0.32 fraction `v` keyed by `seed`: each digit is
/// flipped by a hash of the digits above it only, so elementary intervals map onto elementary
/// intervals.
#[cfg(test)]
fn owen_scramble(v: u32, seed: u32) -> u32 {
    laine_karras(v.reverse_bits(), seed).reverse_bits()
}

/// Sobol' dimension 1 of `i` (the upper-triangular Pascal matrix mod 2, as a 0.32 fraction),
/// bit-reversed: the input of its scramble's hash.
///
/// Bit `k` of the reversed product is the XOR of `i`'s bits `j` with `C(j, k)` odd, that is (by
/// Lucas's theorem) of the bits `j` whose position's binary digits include `k`'s: a sum over
/// supersets of the 5-bit position, which five XOR-and-shift steps compute, one per digit of
/// the position (each step adds to every position without that digit the bit at the position
/// with it). Shifts, masks and XORs only, so the eight lanes of
/// [`points_side_by_side`] run as vector instructions, where the table of the bytes' products
/// this replaced took four scalar loads a lane (about 60 instructions a sample of an adaptive
/// render, docs/quality.md, nineteenth session); the same bits (tested against
/// [`sobol_dim1_by_bit`]).
#[inline]
fn sobol_dim1_reversed(mut i: u32) -> u32 {
    i ^= (i >> 1) & 0x5555_5555;
    i ^= (i >> 2) & 0x3333_3333;
    i ^= (i >> 4) & 0x0f0f_0f0f;
    i ^= (i >> 8) & 0x00ff_00ff;
    i ^= (i >> 16) & 0x0000_ffff;
    i
}

/// Sobol' dimension 1 of `i` one bit at a time: the matrix's columns, `1 << 31` and each the
/// one before XOR itself shifted right.
#[cfg(test)]
const fn sobol_dim1_by_bit(mut i: u32) -> u32 {
    let mut out = 0u32;
    let mut column = 1u32 << 31;
    while i != 0 {
        if i & 1 != 0 {
            out ^= column;
        }
        i >>= 1;
        column ^= column >> 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sobol_dim1_by_supersets_is_the_bitwise_product() {
        // The superset steps against the bit loop: every one- and two-bit index, then a spread of
        // hashed ones (the shuffled indices `point` feeds it).
        for a in 0..32 {
            for b in a..32 {
                let i = (1u32 << a) | (1u32 << b);
                let by_bit = sobol_dim1_by_bit(i).reverse_bits();
                assert_eq!(sobol_dim1_reversed(i), by_bit, "index {i:#x}");
            }
        }
        let mut h = 0x1234_5678_9abc_def0u64;
        for _ in 0..100_000 {
            h = mix64(h);
            let i = h as u32;
            let by_bit = sobol_dim1_by_bit(i).reverse_bits();
            assert_eq!(sobol_dim1_reversed(i), by_bit, "index {i:#x}");
        }
        // The first points of the dimension, from its definition.
        let first: Vec<u32> = (0..4).map(|i| sobol_dim1_by_bit(i) >> 30).collect();
        assert_eq!(first, [0, 2, 3, 1]);
    }

    #[test]
    fn points_are_the_composition_of_whole_scrambles() {
        let mut key = 0x0bad_5eed_u64;
        for stream in [0, 1, 3, 7, 1 << 40] {
            for _ in 0..64 {
                key = mix64(key);
                let scramble = OwenSobol::of(key, stream);
                let js = (0..300).chain([1 << 20, u32::MAX - 1, u32::MAX]);
                for j in js {
                    let (fast, plain) = (scramble.point(j), scramble.point_by_definition(j));
                    assert_eq!(fast.x.to_bits(), plain.x.to_bits(), "x of point {j}");
                    assert_eq!(fast.y.to_bits(), plain.y.to_bits(), "y of point {j}");
                }
            }
        }
    }

    #[test]
    fn points_side_by_side_are_the_points_one_at_a_time() {
        let mut key = 0x51de_u64;
        for round in 0..500u32 {
            key = mix64(key);
            let scrambles: [OwenSobol; 8] =
                std::array::from_fn(|k| OwenSobol::of(mix64(key ^ k as u64), k as u64 % 3));
            let j: [u32; 8] = std::array::from_fn(|k| match round % 3 {
                0 => round * 8 + k as u32,
                1 => mix64(key + k as u64) as u32,
                _ => u32::MAX - k as u32,
            });
            let mut out = [Vec2::ZERO; 8];
            points_side_by_side(&scrambles, &j, &mut out);
            for k in 0..8 {
                let one = scrambles[k].point(j[k]);
                assert_eq!(
                    out[k].to_array().map(f32::to_bits),
                    one.to_array().map(f32::to_bits)
                );
            }
        }
    }

    #[test]
    fn the_scramble_is_nested_each_digit_flipped_by_the_digits_above() {
        // Two fractions whose first difference is digit k (from the top) scramble to fractions
        // whose first difference is digit k: elementary intervals onto elementary intervals.
        let mut h = 0x5151_u64;
        for _ in 0..20_000 {
            h = mix64(h);
            let (v, seed, k) = (h as u32, (h >> 32) as u32, (h >> 27) as u32 % 32);
            let w = v ^ (1u32 << (31 - k)); // the first difference at digit k (from the top)
            let (sv, sw) = (owen_scramble(v, seed), owen_scramble(w, seed));
            let high = (!0u64 << (32 - k)) as u32;
            assert_eq!(sv & high, sw & high, "digits above {k}");
            assert_ne!((sv ^ sw) & (1u32 << (31 - k)), 0, "digit {k}");
        }
    }
}
