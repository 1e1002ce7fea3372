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

/// [`json_diagnostics`]'s array printed (the same bytes as the value's `to_string`, tested),
/// written to `out` straight from the diagnostics: no value of ten small strings per diagnostic
/// is made and printed again (`scnc watch`'s `error` event of 1,002 diagnostics: 13.7 ms for
/// the value and its printing at load 9, docs/watch.md).
///
/// A value's objects print their keys sorted (serde_json's map, without its `preserve_order`
/// feature): [`SortedDiagnostic`] and [`SortedLabel`] declare their fields in that order. A
/// diagnostic with lines of OBJ/MTL files (whose fields are not) goes through a value, and so
/// does everything when the map keeps insertion order instead (another crate in the build may
/// turn that feature on; [`maps_sort_keys`]).
pub fn write_json_diagnostics(out: &mut Vec<u8>, diags: &[Diagnostic], sources: &SourceMap) {
    let report = report(diags, sources);
    // Plain strings and numbers always serialise into memory; `null` would be the fallback.
    let write = |out: &mut Vec<u8>, d: &JsonDiagnostic| {
        let written = if d.files.is_empty() && maps_sort_keys() {
            serde_json::to_writer(&mut *out, &SortedDiagnostic::of(d))
        } else {
            serde_json::to_value(d).and_then(|v| serde_json::to_writer(&mut *out, &v))
        };
        if written.is_err() {
            out.extend_from_slice(b"null");
        }
    };
    out.push(b'[');
    for (i, d) in report.diagnostics.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        write(out, d);
    }
    out.push(b']');
}

/// Whether a JSON value prints its objects' keys sorted (serde_json's default map), or in the
/// order they were put in.
pub fn maps_sort_keys() -> bool {
    static SORTED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *SORTED.get_or_init(|| {
        let printed = serde_json::json!({"b": 0, "a": 0}).to_string();
        printed.starts_with(r#"{"a""#)
    })
}

/// A [`JsonDiagnostic`] without `files`, its fields in sorted order.
#[derive(Serialize)]
struct SortedDiagnostic<'a> {
    code: super::Code,
    explain: &'a str,
    help: Option<&'a str>,
    labels: Vec<SortedLabel<'a>>,
    message: &'a str,
    severity: super::Severity,
}

/// A [`JsonLabel`], its fields in sorted order.
#[derive(Serialize)]
struct SortedLabel<'a> {
    column: usize,
    end: u32,
    file: &'a str,
    line: usize,
    message: &'a str,
    path: &'a str,
    primary: bool,
    start: u32,
}

impl<'a> SortedDiagnostic<'a> {
    fn of(d: &'a JsonDiagnostic<'a>) -> SortedDiagnostic<'a> {
        let label = |l: &'a JsonLabel<'a>| SortedLabel {
            column: l.column,
            end: l.end,
            file: l.file,
            line: l.line,
            message: l.message,
            path: &l.path,
            primary: l.primary,
            start: l.start,
        };
        SortedDiagnostic {
            code: d.code,
            explain: &d.explain,
            help: d.help,
            labels: d.labels.iter().map(label).collect(),
            message: d.message,
            severity: d.severity,
        }
    }
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
        let mut written = Vec::new();
        write_json_diagnostics(&mut written, &diags, &sources);
        assert_eq!(String::from_utf8(written).unwrap(), value.to_string());
        // A line of an OBJ file, and no diagnostic at all.
        let mut obj = Diagnostic::error(Code::CheckUnknownMaterial, "a face's index is 0");
        obj.external.push(crate::diag::ExternalLabel {
            file: "crate.obj".into(),
            line: 3,
            text: "f 0 1 2".into(),
            start: 2,
            end: 3,
            message: "indices start at 1".into(),
        });
        let diags = [obj, diags[1].clone()];
        let mut written = Vec::new();
        write_json_diagnostics(&mut written, &diags, &sources);
        let value = json_diagnostics(&diags, &sources);
        assert_eq!(String::from_utf8(written).unwrap(), value.to_string());
        let mut written = Vec::new();
        write_json_diagnostics(&mut written, &[], &sources);
        assert_eq!(written, b"[]");
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
