//! Shading layer: the environment map's texel radiances (`light sky = environment {
//! image("sky.hdr") }`), held in 4 bytes each when that is exact.
//!
//! A sampled sky direction and an escaping BRDF ray each read one texel at a random place of
//! the map: a cache miss in a 6 MiB array for a 1024 × 512 map of three f32s (docs/speed.md).
//! A Radiance `.hdr` file stores every texel as three 8-bit mantissas and one shared exponent,
//! and its decoded f32s are exactly `(m + ½) · 2^k` (the `image` crate decodes to the middle of
//! the step); such a map fits the same record again, a third of the size, and decodes to the
//! same bits (env-bench's sky: 6 MiB → 2 MiB). [`Texels::new`] packs a map only if every texel
//! round-trips bit for bit, and otherwise keeps the f32s: the radiance the render reads is the
//! same either way.

use glam::Vec3;

/// The mantissas' offset: the `image` crate decodes a Radiance texel as `(m + ½) · 2^k`
/// (the middle of the 8-bit step), other sources may give `m · 2^k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Offset {
    /// `m · 2^k`.
    Zero,
    /// `(m + ½) · 2^k`.
    Half,
}

impl Offset {
    fn value(self) -> f32 {
        match self {
            Offset::Zero => 0.0,
            Offset::Half => 0.5,
        }
    }
}

/// The texels of a map, row-major.
#[derive(Debug, Clone)]
pub enum Texels {
    /// Per texel `[m_r, m_g, m_b, k + 127]`: radiance `(m + offset) · 2^k` (all zero: black).
    Packed {
        /// The records.
        records: Vec<[u8; 4]>,
        /// What each mantissa stands for beyond its integer.
        offset: Offset,
    },
    /// Per texel its f32 radiance.
    Float(Vec<Vec3>),
}

impl Texels {
    /// The packed form if every texel round-trips exactly, else `texels` as they are.
    pub fn new(texels: Vec<Vec3>) -> Texels {
        for offset in [Offset::Half, Offset::Zero] {
            let packed: Option<Vec<[u8; 4]>> = texels.iter().map(|&t| pack(t, offset)).collect();
            if let Some(records) = packed {
                return Texels::Packed { records, offset };
            }
        }
        Texels::Float(texels)
    }

    /// The radiance of texel `i` (row-major); `i` must be below [`Texels::len`].
    #[inline]
    pub fn get(&self, i: usize) -> Vec3 {
        match self {
            Texels::Packed { records, offset } => unpack(records[i], *offset),
            Texels::Float(f) => f[i],
        }
    }

    /// The number of texels.
    pub fn len(&self) -> usize {
        match self {
            Texels::Packed { records, .. } => records.len(),
            Texels::Float(f) => f.len(),
        }
    }

    /// Whether there is no texel.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Heap memory.
    pub fn bytes(&self) -> usize {
        match self {
            Texels::Packed { records, .. } => records.len() * 4,
            Texels::Float(f) => f.len() * std::mem::size_of::<Vec3>(),
        }
    }

    /// Whether the texels are held packed.
    pub fn is_packed(&self) -> bool {
        matches!(self, Texels::Packed { .. })
    }
}

/// `t` as 8-bit mantissas (plus `offset`) over the shared exponent of its largest channel, if
/// that decodes to exactly `t`'s bits.
fn pack(t: Vec3, offset: Offset) -> Option<[u8; 4]> {
    let bits = t.to_array().map(f32::to_bits);
    if bits == [0; 3] {
        return Some([0; 4]);
    }
    let largest = t.max_element();
    if !largest.is_finite() || largest <= 0.0 {
        return None;
    }
    // largest = f · 2^e with f in [1, 2); over 2^(e − 7) it lies in [128, 256).
    let e = ((largest.to_bits() >> 23) & 0xff) as i32 - 127;
    let biased = e - 7 + 127;
    if !(1..=254).contains(&biased) {
        return None;
    }
    // 2^(127 − biased): a power of two (subnormal at worst), so `c · inv_scale` is `c / scale`
    // without a division; the round trip below checks the record either way.
    let inv_scale = match 254 - biased {
        0 => f32::from_bits(1 << 22),
        field => f32::from_bits((field as u32) << 23),
    };
    let mut record = [0u8; 4];
    for (m, c) in record.iter_mut().zip(t.to_array()) {
        let q = c * inv_scale - offset.value();
        // In range, `q as u8` truncates exactly (no libm `truncf` call on baseline x86-64).
        if !(0.0..=255.0).contains(&q) || f32::from(q as u8) != q {
            return None;
        }
        *m = q as u8;
    }
    record[3] = biased as u8;
    (unpack(record, offset).to_array().map(f32::to_bits) == bits).then_some(record)
}

#[inline]
fn unpack(record: [u8; 4], offset: Offset) -> Vec3 {
    if record[3] == 0 {
        return Vec3::ZERO;
    }
    let scale = f32::from_bits(u32::from(record[3]) << 23);
    let o = offset.value();
    Vec3::new(
        (f32::from(record[0]) + o) * scale,
        (f32::from(record[1]) + o) * scale,
        (f32::from(record[2]) + o) * scale,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radiance_hdr_values_pack_and_read_back_the_same_bits() {
        // What an RGBE file decodes to: 8-bit mantissas times 2^(e − 136).
        let texels: Vec<Vec3> = (0..600u32)
            .map(|i| {
                let e = 100 + (i % 60) as i32;
                let scale = 2f32.powi(e - 136);
                let m = |k: u32| ((i * k + 7) % 256) as f32;
                if i % 97 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new(255.0, m(31), m(57)) * scale
                }
            })
            .collect();
        let packed = Texels::new(texels.clone());
        assert!(packed.is_packed());
        assert_eq!(packed.bytes(), 600 * 4);
        for (i, t) in texels.iter().enumerate() {
            assert_eq!(
                packed.get(i).to_array().map(f32::to_bits),
                t.to_array().map(f32::to_bits)
            );
        }
    }

    #[test]
    fn half_step_mantissas_pack_too() {
        // The `image` crate's Radiance decoding: (m + ½) · 2^(e − 136).
        let texels: Vec<Vec3> = (0..300u32)
            .map(|i| {
                let scale = 2f32.powi(120 + (i % 20) as i32 - 136);
                let m = |k: u32| ((i * k + 3) % 256) as f32 + 0.5;
                Vec3::new(m(1), 200.5, m(13)) * scale
            })
            .collect();
        let packed = Texels::new(texels.clone());
        assert!(packed.is_packed());
        for (i, t) in texels.iter().enumerate() {
            assert_eq!(
                packed.get(i).to_array().map(f32::to_bits),
                t.to_array().map(f32::to_bits)
            );
        }
    }

    #[test]
    fn a_map_with_one_inexact_texel_keeps_its_floats() {
        let mut texels = vec![Vec3::new(0.5, 0.25, 1.0); 10];
        texels[3] = Vec3::new(0.1, 0.2, 0.3);
        let kept = Texels::new(texels.clone());
        assert!(!kept.is_packed());
        assert!((0..10).all(|i| kept.get(i) == texels[i]));
        // A channel far below the largest (under its 8-bit step) is inexact too.
        assert!(!Texels::new(vec![Vec3::new(1.0, 1e-3, 0.0)]).is_packed());
        assert!(!Texels::new(vec![Vec3::new(-0.0, 0.0, 0.0)]).is_packed());
    }
}
