//! Diagnostics: errors and warnings as data, carried with spans from every stage.
//!
//! Each stage has its own error type; all of them convert into [`Diagnostic`], the one shape the
//! CLI prints (fancy on a terminal, plain in tests, JSON for editors). A compile collects many
//! diagnostics in one run; warnings never stop it.

mod diagnostic;

pub use diagnostic::{Diagnostic, Label, Severity};
