//! The [`Diagnostic`] record: severity, stable code, message, labelled spans and help.

use serde::Serialize;

use super::Code;
use crate::source::Span;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
/// How bad a diagnostic is.
pub enum Severity {
    /// Reported; never stops the pipeline.
    Warning,
    /// Stops the pipeline after the stage that found it.
    Error,
}

/// A span with a short text shown under it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Label {
    /// Where.
    pub span: Span,
    /// The text shown under it.
    pub message: String,
}

/// A line of a file outside the [`SourceMap`](crate::source::SourceMap) (an OBJ or MTL file
/// read as an asset): only the line is kept, so a diagnostic about a 100 MB mesh stays small.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExternalLabel {
    /// The file's name as shown (the path as written).
    pub file: String,
    /// 1-based line number.
    pub line: u32,
    /// The line's text (lossily decoded, without its line end).
    pub text: String,
    /// Byte range within `text` to underline.
    pub start: u32,
    /// End of that range (exclusive).
    pub end: u32,
    /// The text shown under it.
    pub message: String,
}

/// One problem found in the user's input.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// Stable code, e.g. `scnc::check::unknown_material` (serialised as that string); editors
    /// and tests key on it, and `scnc explain` explains it.
    pub code: Code,
    /// One sentence saying what is wrong.
    pub message: String,
    /// Where it is wrong. `None` only for problems with no source location (e.g. the root
    /// file itself cannot be read).
    pub primary: Option<Label>,
    /// Other places that explain the problem (the first declaration of a duplicate, the
    /// include chain of a cycle, ...).
    pub secondary: Vec<Label>,
    /// How to fix it, when known.
    pub help: Option<String>,
    /// Where in an asset file (OBJ/MTL) it is wrong; shown before the `.scn` labels, which then
    /// say where the scene referenced the file.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub external: Vec<ExternalLabel>,
}

impl Diagnostic {
    /// An error: it stops the pipeline after the stage that found it.
    pub fn error(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            code,
            message: message.into(),
            primary: None,
            secondary: Vec::new(),
            help: None,
            external: Vec::new(),
        }
    }

    /// A warning: reported, never stops anything.
    pub fn warning(code: Code, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            ..Diagnostic::error(code, message)
        }
    }

    /// Sets the primary label.
    pub fn at(mut self, span: Span, label: impl Into<String>) -> Diagnostic {
        self.primary = Some(Label {
            span,
            message: label.into(),
        });
        self
    }

    /// Adds a secondary label.
    pub fn also(mut self, span: Span, label: impl Into<String>) -> Diagnostic {
        self.secondary.push(Label {
            span,
            message: label.into(),
        });
        self
    }

    /// Adds a label in an asset file's line.
    pub fn in_file(mut self, label: ExternalLabel) -> Diagnostic {
        self.external.push(label);
        self
    }

    /// Sets how to fix it.
    pub fn help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// Whether it is an error (not a warning).
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }

    /// Moves every label by an edit's [`crate::source::Shift`] (or renumbered file ids); `false`
    /// when a label reaches into the edited bytes (the incremental compile then compiles in full).
    pub fn shift_spans(&mut self, shift: &impl crate::source::MoveSpans) -> bool {
        let mut ok = true;
        for label in self.primary.iter_mut().chain(&mut self.secondary) {
            ok &= shift.apply(&mut label.span);
        }
        ok
    }
}
