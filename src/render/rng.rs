//! Stage 4: deterministic random numbers. Each value is a pure hash of (seed, pixel, sample
//! index, dimension): never of the thread, the tile order or the time, so renders are
//! bit-identical whatever the thread count (`render { seed 0 }` changes every value).
//!
//! This lives in `render/`, not in `shade::sampling`: it is the render loop's sample sequence
//! (which pixel, which sample, which stratum of the pixel's set), while the shading layer only
//! maps the numbers it is handed (`u ∈ [0, 1)²`) to directions and points, whatever produced them.

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

/// The random stream of one pixel sample: dimension `d` is `hash(key, d)`. It also knows the
/// sample's index among the pixel's samples and a per-pixel stream (the same for every sample
/// of the pixel) so that light samples can be stratified across the whole pixel.
#[derive(Debug, Clone)]
pub struct Sampler {
    key: u64,
    dim: u64,
    pixel_key: u64,
    index: u32,
    count: u32,
}

impl Sampler {
    /// A stand-alone stream: sample 0 of 1, so calls with different `sample` are independent.
    pub fn new(seed: u64, px: u32, py: u32, sample: u32) -> Sampler {
        let key = sample_key(seed, px, py, sample);
        Sampler {
            key,
            dim: 0,
            pixel_key: mix64(key ^ 0x5851_f42d_4c95_7f2d),
            index: 0,
            count: 1,
        }
    }

    /// Sample `index` of the `count` samples of pixel (`px`, `py`).
    pub fn for_pixel_sample(seed: u64, px: u32, py: u32, index: u32, count: u32) -> Sampler {
        Sampler::for_batch_sample(seed, px, py, 0, index, count)
    }

    /// Sample `index` of the `count` samples of batch `batch` of pixel (`px`, `py`): each batch
    /// of adaptive sampling is stratified on its own (its own per-pixel stream), and its sample
    /// keys follow the previous batches' (batch 0 is [`Sampler::for_pixel_sample`]).
    pub fn for_batch_sample(
        seed: u64,
        px: u32,
        py: u32,
        batch: u32,
        index: u32,
        count: u32,
    ) -> Sampler {
        let count = count.max(1);
        let global = batch.wrapping_mul(count).wrapping_add(index);
        Sampler {
            key: sample_key(seed, px, py, global),
            dim: 0,
            pixel_key: mix64(sample_key(seed, px, py, u32::MAX - batch) ^ 0x5851_f42d_4c95_7f2d),
            index: index.min(count - 1),
            count,
        }
    }

    /// A value in [0, 1) (24 random bits, so exactly representable).
    pub fn next_1d(&mut self) -> f32 {
        let h = mix64(self.key ^ self.dim.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        self.dim += 1;
        to_unit(h)
    }

    /// The next two dimensions.
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_1d(), self.next_1d())
    }

    /// Random bits shared by every sample of the pixel, for per-pixel scrambling.
    pub fn pixel_bits(&self, dim: u64) -> u64 {
        mix64(self.pixel_key ^ dim.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    }

    /// This sample's index among the pixel's samples, and their count.
    pub fn index(&self) -> (u32, u32) {
        (self.index, self.count)
    }

    /// Point `j` of a 2-D set of `n` points shared by the pixel's samples (Hammersley points
    /// with a per-pixel Cranley–Patterson shift in x and a per-pixel digit scramble in y,
    /// keyed by `stream`): stratified over [0, 1)², and each point uniform on its own.
    pub fn stratified_2d(&self, stream: u64, j: u32, n: u32) -> Vec2 {
        let bits = self.pixel_bits(stream);
        let shift = to_unit(bits);
        let x = ((j as f32 + 0.5) / n as f32 + shift).fract();
        // The shift uses the top 24 bits, the scramble the low 32: independent.
        let y = ((j.reverse_bits() ^ bits as u32) >> 8) as f32 * (1.0 / (1u32 << 24) as f32);
        Vec2::new(x, y)
    }
}

fn sample_key(seed: u64, px: u32, py: u32, sample: u32) -> u64 {
    let pixel = ((py as u64) << 32) | px as u64;
    mix64(mix64(mix64(seed) ^ pixel) ^ (sample as u64).wrapping_add(0x9e37_79b9))
}

/// The per-pixel stream of adaptive batches' sub-pixel shifts (far from the integrator's).
pub const STREAM_SUBPIXEL: u64 = 1 << 40;

/// The top 24 bits of `h` as a value in [0, 1).
pub fn unit(h: u64) -> f32 {
    to_unit(h)
}

fn to_unit(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
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
    fn pixel_stratified_points_cover_every_stratum_once() {
        let count = 16;
        let mut xs = vec![0; count as usize];
        let mut ys = vec![0; count as usize];
        for s in 0..count {
            let sampler = Sampler::for_pixel_sample(3, 10, 20, s, count);
            assert_eq!(sampler.index(), (s, count));
            let p = sampler.stratified_2d(7, s, count);
            assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            xs[(p.x * count as f32) as usize] += 1;
            ys[(p.y * count as f32) as usize] += 1;
        }
        assert!(xs.iter().chain(&ys).all(|&c| c == 1), "{xs:?} {ys:?}");
        // Across independent samplers the two coordinates are uncorrelated: E[xy] = 1/4
        // (standard error of the mean of xy over 1e4 values ≈ 0.0022).
        let n = 10_000;
        let exy: f32 = (0..n)
            .map(|i| {
                let p = Sampler::new(0, 0, 0, i).stratified_2d(5, 0, 1);
                p.x * p.y
            })
            .sum::<f32>()
            / n as f32;
        assert!((exy - 0.25).abs() < 4.0 * 0.0022, "E[xy] = {exy}");
        // Stand-alone samplers do not share their pixel stream.
        let a = Sampler::new(0, 0, 0, 1).stratified_2d(0, 0, 1);
        let b = Sampler::new(0, 0, 0, 2).stratified_2d(0, 0, 1);
        assert_ne!(a, b);
    }
}
