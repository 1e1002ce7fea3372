//! Stage 2, check: AST → `ir::SceneDesc` (names resolved, expressions folded, units normalised,
//! values validated). Reports every error and warning found.
