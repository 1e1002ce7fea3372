//! Stage 4: deterministic random numbers. Each value is a pure hash of (seed, pixel, sample
//! index, dimension): never of the thread, the tile order or the time, so renders are
//! bit-identical whatever the thread count (`render { seed 0 }` changes every value).

use glam::Vec2;

/// murmur3's 64-bit finaliser: a bijective avalanche mix.
#[inline]
fn mix64(mut x: u64) -> u64 {
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
    x ^= x >> 33;
    x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    x ^ (x >> 33)
}

/// The random stream of one pixel sample: dimension `d` is `hash(key, d)`.
#[derive(Debug, Clone)]
pub struct Sampler {
    key: u64,
    dim: u64,
}

impl Sampler {
    pub fn new(seed: u64, px: u32, py: u32, sample: u32) -> Sampler {
        let pixel = ((py as u64) << 32) | px as u64;
        let key = mix64(mix64(mix64(seed) ^ pixel) ^ (sample as u64).wrapping_add(0x9e37_79b9));
        Sampler { key, dim: 0 }
    }

    /// A value in [0, 1) (24 random bits, so exactly representable).
    pub fn next_1d(&mut self) -> f32 {
        let h = mix64(self.key ^ self.dim.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        self.dim += 1;
        (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }
}

/// The van der Corput radical inverse in base 2 (second coordinate of Hammersley points).
pub fn radical_inverse_2(i: u32) -> f32 {
    (i.reverse_bits() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_inputs_same_values_and_uniform_mean() {
        let mut a = Sampler::new(7, 3, 4, 5);
        let mut b = Sampler::new(7, 3, 4, 5);
        let xs: Vec<f32> = (0..10_000).map(|_| a.next_1d()).collect();
        assert!(xs
            .iter()
            .all(|&x| x == b.next_1d() && (0.0..1.0).contains(&x)));
        let mean = xs.iter().sum::<f32>() / xs.len() as f32;
        // Standard error of the mean of U(0,1) over 1e4 values is 0.0029.
        assert!((mean - 0.5).abs() < 4.0 * 0.0029, "mean {mean}");
        let mut c = Sampler::new(7, 3, 4, 6);
        assert_ne!(xs[0], c.next_1d());
    }

    #[test]
    fn radical_inverse_is_stratified() {
        assert_eq!(radical_inverse_2(0), 0.0);
        assert_eq!(radical_inverse_2(1), 0.5);
        assert_eq!(radical_inverse_2(2), 0.25);
        assert_eq!(radical_inverse_2(3), 0.75);
    }
}
