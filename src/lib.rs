//! scnc: a declarative scene-language compiler and direct-lighting ray tracer.
//!
//! ```text
//! scene.scn ─ syntax::parse ─▶ SceneFile (AST, every node spanned)        Staged<SceneFile>
//!           ─ check::check  ─▶ ir::SceneDesc (typed, names resolved,      Staged<SceneDesc>
//!                               units normalised, validated, no I/O)
//!             (compile::compile: parse + includes + check, through the Loader)
//!           ─ scene::build  ─▶ Scene (world triangles + BVH, textures,    Staged<Scene>
//!              (via Loader)     light tables, camera): only what is used
//!           ─ render::render ─▶ Film (linear RGB radiance per pixel)     deterministic, cancellable
//!           ─ film::write    ─▶ PNG (sRGB 8-bit), EXR / HDR / PFM          Staged<()>; atomic
//! ```
//!
//! Every stage returns [`diag::Staged`]: its value (if it could make one) and every
//! [`diag::Diagnostic`] (error or warning, with spans into the `source::SourceMap`) found so
//! far, so `cli` chains the stages with `Staged::and_then` and reports once. Only
//! cancellation ends a render early (`render::Cancelled`); its settings are resolved before it
//! starts (`ir::RenderSettings::resolve`).
//!
//! [`shade`] is the layer between `scene::build` and `render`: what a hit point needs to be
//! shaded (BRDF, lights with `sample` beside `pdf`, textures, the environment map, sampling
//! routines and distributions). The scene stores its types; the integrator calls them.

#![warn(missing_docs)]
// Set here rather than in Cargo.toml's [lints], which would reach tests/ and benches/ too: they
// are crates of their own where an unwrap that fails is a failed test, as are this crate's
// #[cfg(test)] modules (clippy.toml). Each invariant that still expects carries an allow with
// its reason.
#![deny(clippy::unwrap_used, clippy::expect_used)]

// pest_derive without its `std` feature (see Cargo.toml: no native stack probe per rule call)
// names `::alloc::boxed::Box` in the parser it generates.
extern crate alloc;

pub mod assets;
pub mod bvh;
pub mod check;
pub mod cli;
pub mod compile;
pub mod diag;
pub mod film;
pub mod fmt;
pub mod geom;
pub mod ir;
pub mod lsp;
pub mod render;
pub mod scene;
pub mod shade;
pub mod source;
pub mod syntax;
#[doc(hidden)]
pub mod testing;
