//! Plain-text rendering of diagnostics: fixed width, no colour, deterministic (tests, logs,
//! non-terminal output). Shape, one block per diagnostic:
//!
//! ```text
//! error[scnc::check::unknown_material]: unknown material `shinny`
//!   --> scene.scn:3:24
//!    |
//!  3 | object tall { material shinny }
//!    |                        ^^^^^^ no material of this name
//!    |
//!   ::: scene.scn:2:10 first declared here            (one per secondary label)
//!    = help: did you mean `shiny`?
//! ```

use std::fmt::Write;

use super::{Diagnostic, ExternalLabel, Label, Severity};
use crate::source::SourceMap;

/// Renders one diagnostic; source lines are cut to `width` columns.
pub fn render_plain(d: &Diagnostic, sources: &SourceMap, width: usize) -> String {
    let mut out = String::new();
    let sev = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let _ = writeln!(out, "{sev}[{}]: {}", d.code, d.message);
    for ext in &d.external {
        external_snippet(&mut out, ext, width);
    }
    if let Some(primary) = &d.primary {
        snippet(&mut out, primary, sources, width, "-->");
    }
    for label in &d.secondary {
        snippet(&mut out, label, sources, width, ":::");
    }
    if let Some(help) = &d.help {
        let _ = writeln!(out, "   = help: {help}");
    }
    out
}

/// Renders every diagnostic, separated by blank lines, with a summary line at the end.
pub fn render_plain_all(diags: &[Diagnostic], sources: &SourceMap, width: usize) -> String {
    let mut out = String::new();
    for d in diags {
        out.push_str(&render_plain(d, sources, width));
        out.push('\n');
    }
    out.push_str(&summary(diags));
    out.push('\n');
    out
}

/// "2 errors, 1 warning".
pub fn summary(diags: &[Diagnostic]) -> String {
    let errors = diags.iter().filter(|d| d.is_error()).count();
    let warnings = diags.len() - errors;
    let plural = |n: usize, w: &str| format!("{n} {w}{}", if n == 1 { "" } else { "s" });
    format!(
        "{}, {}",
        plural(errors, "error"),
        plural(warnings, "warning")
    )
}

fn snippet(out: &mut String, label: &Label, sources: &SourceMap, width: usize, arrow: &str) {
    let file = sources.get(label.span.file);
    let text: &str = &file.text;
    let start = (label.span.start as usize).min(text.len());
    let (line, col) = sources.line_col(label.span.file, start);
    let _ = writeln!(out, "  {arrow} {}:{line}:{col}", file.name);
    let line_start = text[..floor(text, start)].rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[line_start..]
        .find('\n')
        .map_or(text.len(), |i| line_start + i);
    let src_line: String = text[line_start..line_end]
        .chars()
        .map(|c| if c == '\t' { ' ' } else { c })
        .collect();
    let gutter = line.to_string();
    let pad = " ".repeat(gutter.len());
    let shown: String = src_line.chars().take(width).collect();
    let _ = writeln!(out, " {pad} |");
    let _ = writeln!(out, " {gutter} | {}", shown.trim_end());
    // Caret run: from the label's column to its end (clipped to this line and the width).
    let col0 = text[line_start..floor(text, start)].chars().count();
    let end = (label.span.end as usize).clamp(start, line_end);
    let len = text[floor(text, start)..floor(text, end)]
        .chars()
        .count()
        .max(1);
    let col0 = col0.min(width);
    let len = len.min(width.saturating_sub(col0).max(1));
    let _ = writeln!(
        out,
        " {pad} | {}{} {}",
        " ".repeat(col0),
        "^".repeat(len),
        label.message
    );
}

/// A line of an OBJ/MTL file: same shape as [`snippet`].
fn external_snippet(out: &mut String, ext: &ExternalLabel, width: usize) {
    let text = &ext.text;
    let start = floor(text, ext.start as usize);
    let end = floor(text, (ext.end as usize).max(start));
    let col0 = text[..start].chars().count();
    let _ = writeln!(out, "  --> {}:{}:{}", ext.file, ext.line, col0 + 1);
    let gutter = ext.line.to_string();
    let pad = " ".repeat(gutter.len());
    let shown: String = text
        .chars()
        .map(|c| if c == '\t' { ' ' } else { c })
        .take(width)
        .collect();
    let _ = writeln!(out, " {pad} |");
    let _ = writeln!(out, " {gutter} | {}", shown.trim_end());
    let len = text[start..end].chars().count().max(1);
    let col0 = col0.min(width);
    let len = len.min(width.saturating_sub(col0).max(1));
    let _ = writeln!(
        out,
        " {pad} | {}{} {}",
        " ".repeat(col0),
        "^".repeat(len),
        ext.message
    );
}

fn floor(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while i > 0 && !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}
