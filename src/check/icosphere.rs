//! Stage 2, check: `mesh NAME = icosphere { subdivisions N  radius R }` → `ir::BuiltinShape`.
//!
//! Syntax: `mesh ball = icosphere { subdivisions 5  radius 0.6 }`. `subdivisions` is a whole
//! number 0..=8 (default 3; 8 is 1.3 million triangles), `radius` a number > 0 (default 1). The
//! shape is built by `scene::shapes`, vertex for vertex as the benchmark's `icosphere(N)`.

use super::Checker;
use crate::ir::BuiltinShape;
use crate::syntax::Block;

/// The most subdivisions accepted: 20 · 4⁸ = 1,310,720 triangles (the benchmark's dense-L8).
pub const MAX_SUBDIVISIONS: u64 = 8;

impl Checker<'_> {
    /// The keys of an `icosphere { ... }` block, each checked and defaulted.
    pub(super) fn icosphere(&mut self, body: &Block) -> Option<BuiltinShape> {
        let keys = super::vocabulary::ICOSPHERE_KEYS;
        let props = self.split(body, "an icosphere", keys, &[], &[]);
        let subdivisions = match props.get("subdivisions") {
            None => Some(3),
            Some(p) => self
                .one(p, "subdivisions 5")
                .and_then(|e| self.int_in(e, 0, MAX_SUBDIVISIONS, "subdivisions")),
        };
        let radius = match props.get("radius") {
            None => Some(1.0),
            Some(p) => self
                .one(p, "radius 1")
                .and_then(|e| self.positive(e, "radius")),
        };
        Some(BuiltinShape::Icosphere {
            radius: radius? as f32,
            subdivisions: u32::try_from(subdivisions?).ok()?,
        })
    }
}
