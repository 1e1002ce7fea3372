//! Diagnostics: errors and warnings as data, carried with spans from every stage.
//!
//! Each stage reports [`Diagnostic`] records, the one shape the CLI prints: [`render_fancy`] on
//! a terminal (miette), [`render_plain`] in tests and logs (fixed width, no colour), and
//! [`render_json`] for editors. A compile collects many diagnostics in one run; warnings never
//! stop it. Every diagnostic's [`Code`] comes from one registry (`codes.rs`), which also holds
//! each code's summary and explanation for `scnc explain`.

mod code;
mod codes;
mod diagnostic;
mod fancy;
mod json;
mod plain;
mod staged;
pub mod suggest;

pub use code::Code;
pub use diagnostic::{Diagnostic, ExternalLabel, Label, Severity};
pub use fancy::render_fancy;
pub use json::{json_diagnostics, maps_sort_keys, render_json, write_json_diagnostics};
pub use plain::{render_plain, render_plain_all, summary};
pub use staged::Staged;
