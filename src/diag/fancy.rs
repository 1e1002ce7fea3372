//! Fancy terminal rendering of diagnostics through miette (colours, Unicode frames).
//!
//! A [`Diagnostic`] becomes a miette report over the primary label's file; labels in other
//! files (an include chain) become related reports over their own files, so every label is
//! shown in the file it belongs to.

use std::fmt;
use std::sync::Arc;

use miette::{
    GraphicalReportHandler, GraphicalTheme, LabeledSpan, MietteSpanContents, NamedSource,
    SourceSpan, SpanContents,
};

use super::{Code, Diagnostic, Severity};
use crate::source::{FileId, SourceMap};

#[derive(Debug)]
struct Report {
    severity: miette::Severity,
    /// `None` for the context reports attached to a diagnostic (they are not problems).
    code: Option<Code>,
    message: String,
    help: Option<String>,
    source: Option<NamedSource<Arc<str>>>,
    labels: Vec<LabeledSpan>,
    related: Vec<Report>,
    /// Instead of `source`: one line of an asset file.
    line_source: Option<LineSource>,
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Report {}

impl miette::Diagnostic for Report {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.code.map(|c| Box::new(c) as Box<dyn fmt::Display>)
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(self.severity)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn miette::SourceCode> {
        match &self.line_source {
            Some(l) => Some(l as &dyn miette::SourceCode),
            None => self.source.as_ref().map(|s| s as &dyn miette::SourceCode),
        }
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        (!self.labels.is_empty()).then(|| Box::new(self.labels.iter().cloned()) as Box<_>)
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        (!self.related.is_empty())
            .then(|| Box::new(self.related.iter().map(|r| r as &dyn miette::Diagnostic)) as Box<_>)
    }
}

/// One line of an asset file as a miette source, numbered as in the file.
#[derive(Debug)]
struct LineSource {
    name: String,
    text: String,
    line: usize,
}

impl miette::SourceCode for LineSource {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        before: usize,
        after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, miette::MietteError> {
        let inner = self.text.read_span(span, before, after)?;
        Ok(Box::new(MietteSpanContents::new_named(
            self.name.clone(),
            inner.data(),
            *inner.span(),
            inner.line() + self.line.saturating_sub(1),
            inner.column(),
            inner.line_count(),
        )))
    }
}

fn to_report(d: &Diagnostic, sources: &SourceMap) -> Report {
    let mut report = scn_report(d, sources);
    if let Some(ext) = d.external.first() {
        // The asset file's line is the problem; the .scn labels say where it was referenced.
        let fresh = Report {
            severity: report.severity,
            code: report.code,
            message: report.message.clone(),
            help: report.help.clone(),
            source: None,
            labels: Vec::new(),
            related: Vec::new(),
            line_source: None,
        };
        let scn = std::mem::replace(&mut report, fresh);
        let start = (ext.start as usize).min(ext.text.len());
        let len = (ext.end as usize).clamp(start, ext.text.len()) - start;
        report.line_source = Some(LineSource {
            name: ext.file.clone(),
            text: ext.text.clone(),
            line: ext.line as usize,
        });
        report.labels.push(LabeledSpan::new_primary_with_span(
            Some(ext.message.clone()),
            SourceSpan::new(start.into(), len),
        ));
        if scn.source.is_some() {
            report.related.push(Report {
                severity: miette::Severity::Advice,
                code: None,
                message: "referenced here".into(),
                help: None,
                ..scn
            });
        }
    }
    report
}

fn scn_report(d: &Diagnostic, sources: &SourceMap) -> Report {
    let main_file: Option<FileId> = d.primary.as_ref().map(|l| l.span.file);
    let mut labels = Vec::new();
    let mut related = Vec::new();
    if let Some(p) = &d.primary {
        labels.push(LabeledSpan::new_primary_with_span(
            Some(p.message.clone()),
            p.span.source_span(),
        ));
    }
    for l in &d.secondary {
        let span = LabeledSpan::new_with_span(Some(l.message.clone()), l.span.source_span());
        if Some(l.span.file) == main_file {
            labels.push(span);
        } else {
            related.push(Report {
                // Context in another file: shown as advice, not as a second problem.
                severity: miette::Severity::Advice,
                code: None,
                message: l.message.clone(),
                help: None,
                source: Some(sources.named_source(l.span.file)),
                labels: vec![span],
                related: Vec::new(),
                line_source: None,
            });
        }
    }
    Report {
        severity: match d.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        },
        code: Some(d.code),
        message: d.message.clone(),
        help: Some(help_with_explain_hint(d)),
        source: main_file.map(|f| sources.named_source(f)),
        labels,
        related,
        line_source: None,
    }
}

/// The diagnostic's help, then where to read more: the terminal is where a user meets a code
/// for the first time. (Plain output, which tests snapshot, stays without it.)
fn help_with_explain_hint(d: &Diagnostic) -> String {
    match &d.help {
        Some(h) => format!("{h}\n{}", d.code.explain_hint()),
        None => d.code.explain_hint(),
    }
}

/// Renders one diagnostic for a terminal; `color` chooses ANSI colours or plain Unicode.
pub fn render_fancy(d: &Diagnostic, sources: &SourceMap, color: bool) -> String {
    let theme = if color {
        GraphicalTheme::unicode()
    } else {
        GraphicalTheme::unicode_nocolor()
    };
    let handler = GraphicalReportHandler::new_themed(theme);
    let mut out = String::new();
    if handler
        .render_report(&mut out, &to_report(d, sources))
        .is_err()
    {
        out = super::render_plain(d, sources, 100);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Code;

    #[test]
    fn terminal_output_points_at_scnc_explain() {
        let mut sources = SourceMap::new();
        let file = sources.add(
            "scene.scn",
            "scene.scn",
            "object ball { material shinny }\n",
        );
        let d = Diagnostic::error(Code::CheckUnknownMaterial, "unknown material `shinny`")
            .at(
                crate::source::Span::new(file, 23, 29),
                "no material of this name",
            )
            .help("did you mean `shiny`?");
        let out = render_fancy(&d, &sources, false);
        assert!(out.contains("scnc::check::unknown_material"), "{out}");
        assert!(out.contains("did you mean `shiny`?"), "{out}");
        assert!(
            out.contains("run `scnc explain scnc::check::unknown_material` for more"),
            "{out}"
        );
        let plain = super::super::render_plain(&d, &sources, 100);
        assert!(
            !plain.contains("scnc explain"),
            "plain output stays as snapshotted"
        );
    }
}
