//! Wavefront OBJ and MTL decoding (stage 3, assets): bytes → [`ObjModel`] (triangles, normals,
//! UVs, which material each run of triangles uses) and [`MtlLibrary`]s. The `.scn` syntax that
//! leads here is `mesh m = obj("meshes/m.obj") { … }` (see `check/mesh.rs`); reading the files
//! goes through the [`Loader`](super::Loader) in [`load`].
//!
//! scnc's own parser, written to read what modelling tools actually write (tobj, the previous
//! parser, rejected a file for one Latin-1 byte, rendered `l` polylines as faces and fanned
//! concave polygons). One concept per file:
//! - [`encoding`]: UTF-16 transcoding, Latin-1 fallback for names;
//! - [`lexer`], [`number`]: lines, comments, tokens, floats and indices;
//! - [`polygon`]: triangulation (shorter-diagonal quads, ear clipping, degenerates dropped);
//! - [`polygon_check`]: faces that repeat their corners, triangles that miss the Newell area;
//! - [`model`]: OBJ statements, single indexing of `v/vt/vn` corners;
//! - `model_notes`: the once-per-file warnings a parse leaves for the end;
//! - `normals`: normals for the vertices a file with `vn`s left without one;
//! - [`mtl`]: MTL statements;
//! - [`load`]: the OBJ and its `mtllib`s through the `Loader`, with every warning placed.
//!
//! Problems are [`Note`]s (warnings: the file still loads) or one [`ObjError`] (it cannot), each
//! at a [`Place`] in the file's text, so the caller can show the line with a snippet.

pub mod encoding;
pub mod lexer;
pub mod load;
pub mod model;
mod model_notes;
pub mod mtl;
mod normals;
pub mod number;
pub mod phong;
pub mod polygon;
pub mod polygon_check;
pub mod report;

use crate::diag::Code;
pub use load::{load_obj, LoadedObj, MtlSource};
pub use model::{parse_obj, MaterialRun, ObjModel, ObjStats};
pub use mtl::{parse_mtl, BumpKind, MtlLibrary, MtlMaterial, TexRef};

/// A line of an OBJ or MTL file: its 1-based number and the byte range of its statement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Place {
    /// 1-based line number (of the first physical line, for a `\`-continued statement).
    pub line: u32,
    /// Byte offset of the statement's start in the file's UTF-8 text.
    pub start: usize,
    /// Byte offset one past the statement's end.
    pub end: usize,
}

impl Place {
    /// The place of `part`, a sub-slice of `line.text`.
    pub fn of_line(line: &lexer::Line<'_>, part: &[u8]) -> Place {
        let skip = (part.as_ptr() as usize).saturating_sub(line.text.as_ptr() as usize);
        let start = line.offset + skip.min(line.text.len());
        Place {
            line: line.number,
            start,
            end: start + part.len(),
        }
    }
}

/// A warning about a file that still loads.
#[derive(Debug, Clone, PartialEq)]
pub struct Note {
    /// Stable code, e.g. `scnc::obj::lines_skipped`.
    pub code: Code,
    /// What is wrong, as one sentence.
    pub message: String,
    /// The line (and byte range) it is about.
    pub at: Place,
    /// How to fix or silence it, when known.
    pub help: Option<String>,
}

impl Note {
    /// A warning with no help yet.
    pub fn warning(code: Code, message: impl Into<String>, at: Place) -> Note {
        Note {
            code,
            message: message.into(),
            at,
            help: None,
        }
    }

    /// Adds how to fix it.
    pub fn help(mut self, help: impl Into<String>) -> Note {
        self.help = Some(help.into());
        self
    }
}

/// Why a file cannot be loaded, at the line where that became clear.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjError {
    /// Stable code, e.g. `scnc::obj::missing_number`.
    pub code: Code,
    /// What is wrong, as one sentence.
    pub message: String,
    /// The line (and byte range) where loading stopped.
    pub at: Place,
    /// How to fix it, when known.
    pub help: Option<String>,
}

impl ObjError {
    /// An error with no help yet.
    pub fn new(code: Code, message: impl Into<String>, at: Place) -> ObjError {
        ObjError {
            code,
            message: message.into(),
            at,
            help: None,
        }
    }

    /// Adds how to fix it.
    pub fn help(mut self, help: impl Into<String>) -> ObjError {
        self.help = Some(help.into());
        self
    }
}
