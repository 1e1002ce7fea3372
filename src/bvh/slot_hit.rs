//! The closest hit of one bottom-level BVH as its kernel returns it: `t`, the barycentrics and
//! the hit's slot in the leaf order, packed so that the kernel function returns it in two
//! registers; the triangle and instance are resolved after the kernel (`dispatch.rs`).
//!
//! Stage: queries, between `mesh_bvh.rs` (which makes it) and `dispatch.rs` (which resolves it).

/// A closest hit inside one bottom-level BVH as its kernel returns it: the hit's `t`, its
/// barycentrics and its slot in the leaf order. Sixteen bytes, so a kernel function returns
/// it in registers (an `Option<Hit>` of 24 bytes went through memory: six 4-byte stores that
/// the caller read back with one 16-byte load, a failed store forward per query).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlotHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weight of the triangle's second vertex.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex.
    pub v: f32,
    /// Slot in the leaf order (`MeshBvh::ids`); `u32::MAX` for no hit ([`SlotHit::MISS`]),
    /// which is never a slot (`pack_leaves` numbers slots in `u32`, padding included).
    pub slot: u32,
}

/// A [`SlotHit`] as two `u64`s (`t` and `u` bits, `v` bits and the slot): a pair of scalars,
/// which the Rust ABI returns in two registers, where the four-field struct went through
/// memory and the caller read `u` and `v` with one 8-byte load over the kernel's two 4-byte
/// stores (a failed store forward).
#[derive(Debug, Clone, Copy)]
pub struct PackedSlotHit {
    t_u: u64,
    v_slot: u64,
}

impl PackedSlotHit {
    /// The hit's fields, bit for bit.
    #[inline(always)]
    pub fn unpack(self) -> SlotHit {
        SlotHit {
            t: f32::from_bits(self.t_u as u32),
            u: f32::from_bits((self.t_u >> 32) as u32),
            v: f32::from_bits(self.v_slot as u32),
            slot: (self.v_slot >> 32) as u32,
        }
    }
}

impl SlotHit {
    /// The hit as two `u64`s, bit for bit.
    #[inline(always)]
    pub fn pack(self) -> PackedSlotHit {
        PackedSlotHit {
            t_u: u64::from(self.t.to_bits()) | u64::from(self.u.to_bits()) << 32,
            v_slot: u64::from(self.v.to_bits()) | u64::from(self.slot) << 32,
        }
    }

    /// No hit.
    pub const MISS: SlotHit = SlotHit {
        t: f32::INFINITY,
        u: 0.0,
        v: 0.0,
        slot: u32::MAX,
    };
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::SplitMix64;

    #[test]
    fn packing_keeps_every_bit() {
        let mut rng = SplitMix64(7);
        let mut cases = vec![SlotHit::MISS];
        for _ in 0..10_000 {
            let mut word = || (rng.next_u64() >> 32) as u32;
            cases.push(SlotHit {
                t: f32::from_bits(word()),
                u: f32::from_bits(word()),
                v: f32::from_bits(word()),
                slot: word(),
            });
        }
        for h in cases {
            let back = h.pack().unpack();
            assert_eq!(
                [
                    back.t.to_bits(),
                    back.u.to_bits(),
                    back.v.to_bits(),
                    back.slot
                ],
                [h.t.to_bits(), h.u.to_bits(), h.v.to_bits(), h.slot]
            );
        }
    }
}
