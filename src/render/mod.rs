//! Stage 4, render: `Scene` → `Film` (linear RGB radiance per pixel). Deterministic, cancellable.
