//! Seeded randomness for tests and benchmarks: outside the pipeline.
//!
//! The crate's unit tests, its integration tests (`tests/`) and its benchmarks (`benches/`) draw
//! random triangles, rays and edits from one small generator, so a failure reproduces from its
//! seed and no test needs a random-number crate. The renderer's own sample streams live in
//! `render::rng`; nothing in the pipeline uses this module.

use glam::Vec3;

/// SplitMix64 (Steele, Lea and Flood 2014): a 64-bit state advanced by a Weyl sequence and
/// scrambled by a finaliser. `SplitMix64(x).next_u64()` is also a good stateless hash of `x`.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform float in `[0, 1)` from the top 24 bits (every value exactly representable).
    pub fn unit_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// A uniform float in `[lo, hi)`.
    pub fn range_f32(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit_f32()
    }

    /// A point with each coordinate uniform in `[lo, hi)`, drawn x, y, z in that order.
    pub fn vec3(&mut self, lo: f32, hi: f32) -> Vec3 {
        let x = self.range_f32(lo, hi);
        let y = self.range_f32(lo, hi);
        let z = self.range_f32(lo, hi);
        Vec3::new(x, y, z)
    }

    /// A uniform index in `0..n` (0 when `n` is 0); the modulo bias is far below what a test
    /// could notice.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_reference_sequence() {
        // The first outputs for seed 1234567 from the reference implementation (Vigna's
        // splitmix64.c).
        let mut rng = SplitMix64(1_234_567);
        let first: Vec<u64> = (0..3).map(|_| rng.next_u64()).collect();
        assert_eq!(
            first,
            [
                6_457_827_717_110_365_317,
                3_203_168_211_198_807_973,
                9_817_491_932_198_370_423
            ]
        );
    }

    #[test]
    fn unit_floats_stay_in_the_half_open_interval() {
        let mut rng = SplitMix64(0);
        for _ in 0..10_000 {
            let u = rng.unit_f32();
            assert!((0.0..1.0).contains(&u), "{u}");
            assert!(rng.below(7) < 7);
        }
        assert_eq!(SplitMix64(3).below(0), 0);
    }
}
