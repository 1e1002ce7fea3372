//! Stage 5, film: linear radiance → tone-mapped sRGB PNG, or linear EXR/HDR/PFM; atomic writes.
