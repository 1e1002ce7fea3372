//! Stage 3 (scene build) errors: problems only visible once files are read or geometry is built.
//!
//! Input: whatever `scene::build` finds wrong while loading assets (`mesh m = obj("m.obj")`,
//! `texture t = image("t.png")`, `light sky = environment { image("sky.hdr") }`) and while
//! preparing triangles. Output: one [`BuildError`] per problem, each converted into a
//! [`Diagnostic`] with a stable code and a label at the path literal (or the declaration) in the
//! `.scn`, so the user sees exactly which file or mesh is at fault.

use std::io;

use thiserror::Error;

use crate::diag::{Diagnostic, Severity};
use crate::source::Span;

/// One problem found while building the scene.
#[derive(Debug, Error)]
pub enum BuildError {
    #[error("cannot read `{written}`: {source}")]
    Read {
        written: String,
        span: Span,
        #[source]
        source: io::Error,
    },
    #[error("`{written}` is not a valid OBJ file: {reason}")]
    CorruptObj {
        written: String,
        span: Span,
        reason: String,
    },
    #[error("`{written}`: a face refers to a vertex, normal or UV that does not exist ({reason})")]
    IndexOutOfRange {
        written: String,
        span: Span,
        reason: String,
    },
    #[error("mesh `{mesh}` has a non-finite vertex position (vertex {index}: {value})")]
    NonFiniteVertex {
        mesh: String,
        index: usize,
        value: String,
        span: Span,
    },
    #[error("every triangle of mesh `{mesh}` is degenerate ({count} triangles of zero area)")]
    AllDegenerate {
        mesh: String,
        count: usize,
        span: Span,
    },
    #[error("{count} of {total} triangles of mesh `{mesh}` are degenerate and were dropped")]
    SomeDegenerate {
        mesh: String,
        count: usize,
        total: usize,
        span: Span,
    },
    #[error("mesh `{mesh}` has no triangles")]
    EmptyMesh { mesh: String, span: Span },
    #[error("this transform is singular or not finite, so the object has no area")]
    SingularTransform { span: Span },
    #[error("{what} is not supported yet")]
    Unsupported {
        what: String,
        span: Span,
        help: String,
    },
    #[error("the scene has no camera {which}")]
    NoCamera { which: String },
}

impl BuildError {
    /// The stable code editors and tests key on.
    pub fn code(&self) -> &'static str {
        match self {
            BuildError::Read { source, .. } if source.kind() == io::ErrorKind::NotFound => {
                "scnc::build::missing_file"
            }
            BuildError::Read { .. } => "scnc::build::read_failed",
            BuildError::CorruptObj { .. } => "scnc::build::corrupt_obj",
            BuildError::IndexOutOfRange { .. } => "scnc::build::index_out_of_range",
            BuildError::NonFiniteVertex { .. } => "scnc::build::non_finite_vertex",
            BuildError::AllDegenerate { .. } => "scnc::build::degenerate_mesh",
            BuildError::SomeDegenerate { .. } => "scnc::build::degenerate_triangles",
            BuildError::EmptyMesh { .. } => "scnc::build::empty_mesh",
            BuildError::SingularTransform { .. } => "scnc::build::singular_transform",
            BuildError::Unsupported { .. } => "scnc::build::unsupported",
            BuildError::NoCamera { .. } => "scnc::build::no_camera",
        }
    }

    /// Warnings never stop the build; errors do.
    pub fn severity(&self) -> Severity {
        match self {
            BuildError::SomeDegenerate { .. } | BuildError::EmptyMesh { .. } => Severity::Warning,
            _ => Severity::Error,
        }
    }

    fn span(&self) -> Option<Span> {
        match self {
            BuildError::Read { span, .. }
            | BuildError::CorruptObj { span, .. }
            | BuildError::IndexOutOfRange { span, .. }
            | BuildError::NonFiniteVertex { span, .. }
            | BuildError::AllDegenerate { span, .. }
            | BuildError::SomeDegenerate { span, .. }
            | BuildError::EmptyMesh { span, .. }
            | BuildError::SingularTransform { span }
            | BuildError::Unsupported { span, .. } => Some(*span),
            BuildError::NoCamera { .. } => None,
        }
    }

    fn label(&self) -> &'static str {
        match self {
            BuildError::Read { .. } => "this file",
            BuildError::CorruptObj { .. } | BuildError::IndexOutOfRange { .. } => "this OBJ file",
            BuildError::NonFiniteVertex { .. } => "NaN or infinite coordinate in this mesh",
            BuildError::AllDegenerate { .. } => "no triangle of this mesh has an area",
            BuildError::SomeDegenerate { .. } => "some triangles of this mesh have no area",
            BuildError::EmptyMesh { .. } => "this mesh",
            BuildError::SingularTransform { .. } => "placed here",
            BuildError::Unsupported { .. } => "not supported yet",
            BuildError::NoCamera { .. } => "",
        }
    }

    fn help(&self) -> Option<String> {
        match self {
            BuildError::Read { .. } => {
                Some("paths are relative to the .scn file that names them".into())
            }
            BuildError::IndexOutOfRange { .. } => Some(
                "OBJ indices are 1-based (negative ones count back from the last vertex)".into(),
            ),
            BuildError::NonFiniteVertex { .. } => {
                Some("re-export the mesh; every coordinate must be a finite number".into())
            }
            BuildError::AllDegenerate { .. } => {
                Some("check the mesh's size or scale: all its corners are collinear".into())
            }
            BuildError::Unsupported { help, .. } => Some(help.clone()),
            BuildError::NoCamera { .. } => Some("declare one: `camera main { ... }`".into()),
            _ => None,
        }
    }

    pub fn to_diagnostic(&self) -> Diagnostic {
        let mut d = match self.severity() {
            Severity::Error => Diagnostic::error(self.code(), self.to_string()),
            Severity::Warning => Diagnostic::warning(self.code(), self.to_string()),
        };
        if let Some(span) = self.span() {
            d = d.at(span, self.label());
        }
        if let Some(help) = self.help() {
            d = d.help(help);
        }
        d
    }
}

impl From<BuildError> for Diagnostic {
    fn from(e: BuildError) -> Diagnostic {
        e.to_diagnostic()
    }
}
