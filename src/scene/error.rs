//! Stage 3 (scene build) errors: problems only visible once files are read or geometry is built.
//!
//! Input: whatever `scene::build` finds wrong while loading assets (`mesh m = obj("m.obj")`,
//! `texture t = image("t.png")`, `light sky = environment { image("sky.hdr") }`) and while
//! preparing triangles. Output: one [`BuildError`] per problem, each converted into a
//! [`Diagnostic`] with a stable code and a label at the path literal (or the declaration) in the
//! `.scn`, so the user sees exactly which file or mesh is at fault.

use std::io;

use thiserror::Error;

use crate::diag::{Code, Diagnostic, Severity};
use crate::source::Span;

/// One problem found while building the scene; [`BuildError::code`] gives its registry code.
#[derive(Debug, Error)]
pub enum BuildError {
    /// The file does not exist.
    #[error("cannot find `{written}`: {source}")]
    Missing {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
    /// The file exists but cannot be read.
    #[error("cannot read `{written}`: {source}")]
    Read {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
    /// A face names a vertex that does not exist.
    #[error("`{written}`: a face refers to a vertex, normal or UV that does not exist ({reason})")]
    IndexOutOfRange {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// What is wrong.
        reason: String,
    },
    /// Every triangle of the mesh is degenerate: nothing to render.
    #[error("every triangle of mesh `{mesh}` is degenerate ({count} triangles of zero area or with a NaN or infinite corner)")]
    AllDegenerate {
        /// The mesh's name.
        mesh: String,
        /// How many.
        count: usize,
        /// Where the scene says it.
        span: Span,
    },
    /// Some triangles were degenerate and were dropped.
    #[error("{count} of {total} triangles of mesh `{mesh}` are degenerate (zero area, repeated vertices, or a NaN or infinite corner) and were dropped")]
    SomeDegenerate {
        /// The mesh's name.
        mesh: String,
        /// How many.
        count: usize,
        /// Out of how many.
        total: usize,
        /// Where the scene says it.
        span: Span,
    },
    /// The mesh has no triangles at all.
    #[error("mesh `{mesh}` has no triangles")]
    EmptyMesh {
        /// The mesh's name.
        mesh: String,
        /// Where the scene says it.
        span: Span,
    },
    /// A transform that flattens the object or is not finite.
    #[error("this transform is singular or not finite, so the object has no area")]
    SingularTransform {
        /// Where the scene says it.
        span: Span,
    },
    /// Something the renderer does not do yet.
    #[error("{what} is not supported yet")]
    Unsupported {
        /// What the scene asked for.
        what: String,
        /// Where the scene says it.
        span: Span,
        /// How to do without it.
        help: String,
    },
    /// An image that cannot be decoded.
    #[error("`{written}` is not a valid image: {reason}")]
    CorruptImage {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// What is wrong.
        reason: String,
    },
    /// An image beyond the size cap (checked before any pixel is allocated).
    #[error("`{written}` is {width} × {height}, larger than the {max_width} × {max_height} limit")]
    ImageTooLarge {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// The image's width.
        width: u32,
        /// The image's height.
        height: u32,
        /// The widest image accepted.
        max_width: u32,
        /// The tallest image accepted.
        max_height: u32,
    },
    /// Environment map pixels that were negative, NaN or infinite (set to black).
    #[error("{count} of {total} pixels of `{written}` are negative, NaN or infinite; they were set to black")]
    InvalidPixels {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
        /// How many.
        count: usize,
        /// Out of how many.
        total: usize,
    },
    /// An environment map that is black everywhere.
    #[error("the environment map `{written}` is black everywhere; it lights nothing")]
    BlackEnvironment {
        /// The path as written in the scene.
        written: String,
        /// Where the scene says it.
        span: Span,
    },
    /// A one-sided area light whose front sees no geometry.
    #[error("area light `{light}` faces away from everything: all the scene's geometry is behind its one-sided front")]
    LightFacesAway {
        /// The light's name.
        light: String,
        /// Where the scene says it.
        span: Span,
    },
    /// A textured material on a mesh without UVs.
    #[error("mesh `{mesh}` has no UV coordinates, but its material `{material}` is textured")]
    NoUvs {
        /// The mesh's name.
        mesh: String,
        /// The textured material's name.
        material: String,
        /// Where the scene says it.
        span: Span,
    },
    /// An object f32 cannot place to a thousandth of its size.
    #[error("the placement of mesh `{mesh}` is resolved only to {step:.1e} in f32, {:.2}% of its size {size:.1e}", 100.0 * step / size)]
    PrecisionLost {
        /// The mesh the object places.
        mesh: String,
        /// The smallest step its world positions can move by.
        step: f64,
        /// Its largest world-space extent.
        size: f64,
        /// The `object` statement.
        span: Span,
    },
    /// A problem inside an OBJ or MTL file, already a diagnostic with both places: the line
    /// of that file and the path literal in the `.scn` (its code is `scnc::obj::…`).
    #[error("{}", .0.message)]
    Obj(Box<Diagnostic>),
    /// The camera to render from does not exist.
    #[error("the scene has no camera {which}")]
    NoCamera {
        /// Which camera: `number N` or `to render from`.
        which: String,
    },
}

impl BuildError {
    /// The stable code editors and tests key on.
    pub fn code(&self) -> Code {
        match self {
            BuildError::Missing { .. } => Code::BuildMissingFile,
            BuildError::Read { .. } => Code::BuildReadFailed,
            BuildError::IndexOutOfRange { .. } => Code::BuildIndexOutOfRange,
            BuildError::AllDegenerate { .. } => Code::BuildDegenerateMesh,
            BuildError::SomeDegenerate { .. } => Code::BuildDegenerateTriangles,
            BuildError::EmptyMesh { .. } => Code::BuildEmptyMesh,
            BuildError::SingularTransform { .. } => Code::BuildSingularTransform,
            BuildError::Unsupported { .. } => Code::BuildUnsupported,
            BuildError::CorruptImage { .. } => Code::BuildCorruptImage,
            BuildError::ImageTooLarge { .. } => Code::BuildImageTooLarge,
            BuildError::InvalidPixels { .. } => Code::BuildInvalidEnvironmentPixels,
            BuildError::BlackEnvironment { .. } => Code::BuildBlackEnvironment,
            BuildError::LightFacesAway { .. } => Code::BuildLightFacesAway,
            BuildError::NoUvs { .. } => Code::BuildNoUvs,
            BuildError::PrecisionLost { .. } => Code::BuildPrecisionLost,
            BuildError::NoCamera { .. } => Code::BuildNoCamera,
            BuildError::Obj(d) => d.code,
        }
    }

    /// Warnings never stop the build; errors do.
    pub fn severity(&self) -> Severity {
        match self {
            BuildError::SomeDegenerate { .. }
            | BuildError::EmptyMesh { .. }
            | BuildError::InvalidPixels { .. }
            | BuildError::BlackEnvironment { .. }
            | BuildError::LightFacesAway { .. }
            | BuildError::PrecisionLost { .. }
            | BuildError::NoUvs { .. } => Severity::Warning,
            BuildError::Obj(d) => d.severity,
            _ => Severity::Error,
        }
    }

    fn span(&self) -> Option<Span> {
        match self {
            BuildError::Missing { span, .. }
            | BuildError::Read { span, .. }
            | BuildError::IndexOutOfRange { span, .. }
            | BuildError::AllDegenerate { span, .. }
            | BuildError::SomeDegenerate { span, .. }
            | BuildError::EmptyMesh { span, .. }
            | BuildError::SingularTransform { span }
            | BuildError::Unsupported { span, .. }
            | BuildError::CorruptImage { span, .. }
            | BuildError::ImageTooLarge { span, .. }
            | BuildError::InvalidPixels { span, .. }
            | BuildError::BlackEnvironment { span, .. }
            | BuildError::LightFacesAway { span, .. }
            | BuildError::PrecisionLost { span, .. }
            | BuildError::NoUvs { span, .. } => Some(*span),
            BuildError::NoCamera { .. } | BuildError::Obj(_) => None,
        }
    }

    fn label(&self) -> &'static str {
        match self {
            BuildError::Missing { .. } | BuildError::Read { .. } => "this file",
            BuildError::IndexOutOfRange { .. } => "this OBJ file",
            BuildError::AllDegenerate { .. } => "no triangle of this mesh has an area",
            BuildError::SomeDegenerate { .. } => "some triangles of this mesh have no area",
            BuildError::EmptyMesh { .. } => "this mesh",
            BuildError::SingularTransform { .. } => "placed here",
            BuildError::Unsupported { .. } => "not supported yet",
            BuildError::CorruptImage { .. } | BuildError::ImageTooLarge { .. } => "this image",
            BuildError::InvalidPixels { .. } => "this image has invalid pixels",
            BuildError::BlackEnvironment { .. } => "this image is black",
            BuildError::LightFacesAway { .. } => "this light shines away from the scene",
            BuildError::NoUvs { .. } => "this object",
            BuildError::PrecisionLost { .. } => "placed here",
            BuildError::NoCamera { .. } | BuildError::Obj(_) => "",
        }
    }

    fn help(&self) -> Option<String> {
        match self {
            BuildError::Missing { .. } => {
                Some("paths are relative to the .scn file that names them".into())
            }
            BuildError::IndexOutOfRange { .. } => Some(
                "OBJ indices are 1-based (negative ones count back from the last vertex)".into(),
            ),
            BuildError::AllDegenerate { .. } => Some(
                "check the mesh's size or scale (all its corners are collinear) and that every coordinate is a finite number".into(),
            ),
            BuildError::Unsupported { help, .. } => Some(help.clone()),
            BuildError::NoCamera { .. } => Some("declare one: `camera main { ... }`".into()),
            BuildError::CorruptImage { .. } => {
                Some("images are PNG, JPEG, Radiance .hdr or OpenEXR files (environment maps may also be PFM)".into())
            }
            BuildError::ImageTooLarge { .. } => {
                Some("downsample the image; a texture that large costs gigabytes of memory".into())
            }
            BuildError::NoUvs { .. } => Some(
                "texture lookups use each triangle's barycentric coordinates instead and a normal map is ignored; give the mesh UVs (`vt` in OBJ files, `uvs [...]` inline) or use a built-in shape".into(),
            ),
            BuildError::BlackEnvironment { .. } => Some(
                "check the file's exposure, or remove the light; a constant colour needs no image"
                    .into(),
            ),
            BuildError::PrecisionLost { .. } => Some(
                "f32 keeps about 7 digits: place small objects near the scene's other objects, and write vertices relative to the mesh's own origin (move the offset into `transform { translate ... }`)".into(),
            ),
            BuildError::LightFacesAway { .. } => Some(
                "a one-sided light emits on the side its corners run counter-clockwise; reverse their order, turn the light around, or set `two_sided true`".into(),
            ),
            _ => None,
        }
    }

    /// As a diagnostic, labelled at its span, with help when the fix is known.
    pub fn to_diagnostic(&self) -> Diagnostic {
        if let BuildError::Obj(d) = self {
            return (**d).clone();
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::FileId;

    #[test]
    fn diagnostics_carry_the_code_and_severity() {
        let span = Span::new(FileId(0), 1, 2);
        let s = || String::from("x");
        let all = [
            BuildError::Missing {
                written: s(),
                span,
                source: io::Error::from(io::ErrorKind::NotFound),
            },
            BuildError::Read {
                written: s(),
                span,
                source: io::Error::from(io::ErrorKind::PermissionDenied),
            },
            BuildError::IndexOutOfRange {
                written: s(),
                span,
                reason: s(),
            },
            BuildError::AllDegenerate {
                mesh: s(),
                count: 1,
                span,
            },
            BuildError::SomeDegenerate {
                mesh: s(),
                count: 1,
                total: 2,
                span,
            },
            BuildError::EmptyMesh { mesh: s(), span },
            BuildError::SingularTransform { span },
            BuildError::Unsupported {
                what: s(),
                span,
                help: s(),
            },
            BuildError::CorruptImage {
                written: s(),
                span,
                reason: s(),
            },
            BuildError::ImageTooLarge {
                written: s(),
                span,
                width: 1,
                height: 1,
                max_width: 1,
                max_height: 1,
            },
            BuildError::InvalidPixels {
                written: s(),
                span,
                count: 1,
                total: 2,
            },
            BuildError::BlackEnvironment { written: s(), span },
            BuildError::LightFacesAway { light: s(), span },
            BuildError::NoUvs {
                mesh: s(),
                material: s(),
                span,
            },
            BuildError::NoCamera { which: s() },
        ];
        for e in &all {
            let d = e.to_diagnostic();
            assert_eq!(d.code, e.code());
            assert_eq!(d.severity, e.severity(), "{}", e.code());
            assert_eq!(
                d.primary.is_some(),
                !matches!(e, BuildError::NoCamera { .. })
            );
        }
    }
}
