//! The binary BVH node the builder emits (32 bytes): depth-first order; an interior node's first
//! child is the next node, its second child is at `index`. A leaf names `count` consecutive
//! primitives starting at `index`. Stage: made by `bvh::build`, collapsed by `bvh::wide`.

use glam::Vec3;

use crate::geom::Aabb;

/// Most primitives in one leaf (the builder never exceeds it).
pub const MAX_LEAF: u32 = 8;
/// Deepest path the builder produces; traversal stacks are sized from it.
pub const MAX_DEPTH: usize = 96;

/// One node of a flattened BVH: bounds, then either the second child (interior) or the first
/// primitive (leaf), and `count << 2 | split axis` (`count == 0` marks an interior node).
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Zeroable, bytemuck::Pod)]
#[repr(C)]
pub struct Node {
    /// Lower corner of the node's box.
    pub min: [f32; 3],
    /// Interior: the second child's node index. Leaf: the first primitive's position in the order.
    pub index: u32,
    /// Upper corner of the node's box.
    pub max: [f32; 3],
    /// `count << 2 | split axis`; `count == 0` marks an interior node.
    pub meta: u32,
}

impl Node {
    /// A leaf of `count` (1 to [`MAX_LEAF`]) primitives starting at `first`.
    pub fn leaf(b: &Aabb, first: u32, count: u32) -> Node {
        debug_assert!(count > 0 && count <= MAX_LEAF);
        Node {
            min: b.min.to_array(),
            index: first,
            max: b.max.to_array(),
            meta: count << 2,
        }
    }

    /// An interior node split on `axis` (0, 1, 2), whose second child is node `right`.
    pub fn interior(b: &Aabb, right: u32, axis: usize) -> Node {
        Node {
            min: b.min.to_array(),
            index: right,
            max: b.max.to_array(),
            meta: axis as u32 & 3,
        }
    }

    /// Primitives in a leaf; 0 for an interior node.
    #[inline]
    pub fn count(&self) -> u32 {
        self.meta >> 2
    }

    /// Whether the node is a leaf (it names at least one primitive).
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count() > 0
    }

    /// The node's box.
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: Vec3::from_array(self.min),
            max: Vec3::from_array(self.max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_32_bytes() {
        assert_eq!(std::mem::size_of::<Node>(), 32);
    }
}
