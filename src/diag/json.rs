//! JSON rendering of diagnostics for editors and the preview (`--diagnostic-format json`).
//!
//! One object `{"diagnostics": [...], "errors": N, "warnings": M}`; each diagnostic has
//! `severity`, `code`, `message`, `help`, `explain` (the command that explains the code), and `labels` (primary first) with `file` (display
//! name), `path`, byte `start`/`end`, 1-based `line`/`column` and `message`.

use serde::Serialize;

use super::{Diagnostic, Label};
use crate::source::SourceMap;

#[derive(Serialize)]
struct JsonLabel<'a> {
    primary: bool,
    file: &'a str,
    path: String,
    start: u32,
    end: u32,
    line: usize,
    column: usize,
    message: &'a str,
}

#[derive(Serialize)]
struct JsonDiagnostic<'a> {
    severity: super::Severity,
    code: super::Code,
    message: &'a str,
    help: Option<&'a str>,
    /// `scnc explain CODE`: where to read what the code means.
    explain: String,
    labels: Vec<JsonLabel<'a>>,
    /// Lines of OBJ/MTL files (absent when there are none).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    files: &'a [super::ExternalLabel],
}

#[derive(Serialize)]
struct JsonReport<'a> {
    diagnostics: Vec<JsonDiagnostic<'a>>,
    errors: usize,
    warnings: usize,
}

fn label<'a>(l: &'a Label, primary: bool, sources: &'a SourceMap) -> JsonLabel<'a> {
    let f = sources.get(l.span.file);
    let (line, column) = sources.line_col(l.span.file, l.span.start as usize);
    JsonLabel {
        primary,
        file: &f.name,
        path: f.path.display().to_string(),
        start: l.span.start,
        end: l.span.end,
        line,
        column,
        message: &l.message,
    }
}

fn report<'a>(diags: &'a [Diagnostic], sources: &'a SourceMap) -> JsonReport<'a> {
    JsonReport {
        diagnostics: diags
            .iter()
            .map(|d| JsonDiagnostic {
                severity: d.severity,
                code: d.code,
                message: &d.message,
                help: d.help.as_deref(),
                explain: format!("scnc explain {}", d.code),
                labels: d
                    .primary
                    .iter()
                    .map(|l| label(l, true, sources))
                    .chain(d.secondary.iter().map(|l| label(l, false, sources)))
                    .collect(),
                files: &d.external,
            })
            .collect(),
        errors: diags.iter().filter(|d| d.is_error()).count(),
        warnings: diags.iter().filter(|d| !d.is_error()).count(),
    }
}

/// All diagnostics as one pretty-printed JSON document.
#[allow(
    clippy::expect_used,
    reason = "the report is plain strings and numbers, which always serialise"
)]
pub fn render_json(diags: &[Diagnostic], sources: &SourceMap) -> String {
    // ok: the report is plain strings and numbers, which always serialise.
    serde_json::to_string_pretty(&report(diags, sources)).expect("plain data serialises")
}

/// The `diagnostics` array of [`render_json`]'s document, as a JSON value (for an event that
/// carries it: `scnc watch`'s, the preview's), made without printing and parsing the document.
pub fn json_diagnostics(diags: &[Diagnostic], sources: &SourceMap) -> serde_json::Value {
    // Plain strings and numbers always convert; an empty array would be the fallback.
    serde_json::to_value(report(diags, sources).diagnostics)
        .unwrap_or_else(|_| serde_json::Value::Array(Vec::new()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Code;

    #[test]
    fn the_diagnostics_value_is_the_documents_array() {
        let mut sources = SourceMap::new();
        let text = "scnc 1\nobject ball { material rd }\n";
        let file = sources.add("a.scn", "a.scn", std::sync::Arc::<str>::from(text));
        let d = Diagnostic::warning(Code::CheckUnused, "material `red` is never used");
        let e = Diagnostic::error(Code::CheckUnknownMaterial, "unknown material `rd`")
            .at(crate::source::Span::new(file, 30, 32), "not declared")
            .help("did you mean `red`?");
        let diags = [d, e];
        let json: serde_json::Value = serde_json::from_str(&render_json(&diags, &sources)).unwrap();
        let value = json_diagnostics(&diags, &sources);
        assert_eq!(value, json["diagnostics"]);
        assert_eq!(value[1]["labels"][0]["line"], 2);
    }

    #[test]
    fn codes_are_their_strings_and_say_how_to_explain_them() {
        let d = Diagnostic::warning(Code::CheckUnused, "material `red` is never used");
        let json: serde_json::Value =
            serde_json::from_str(&render_json(&[d], &SourceMap::new())).unwrap();
        let d = &json["diagnostics"][0];
        assert_eq!(d["code"], "scnc::check::unused");
        assert_eq!(d["explain"], "scnc explain scnc::check::unused");
        assert_eq!(json["warnings"], 1);
    }
}
