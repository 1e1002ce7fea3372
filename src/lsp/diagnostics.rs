//! Language server: the diagnostics of one open document, exactly those of `scnc check` on its
//! text (compile, then build: a missing OBJ or texture is reported too), as LSP diagnostics with
//! the same codes, UTF-16 ranges, secondary labels as related information and the help text.
//! Each carries a link to its code's explanation ([`explain_url`]). The server keeps one
//! [`Incremental`] front end per open document ([`check_incremental`]), so that as you type in
//! a large scene only the statements you changed are parsed and checked again (the result is
//! the full compile's, `tests/incremental.rs`).

use std::path::Path;

use lsp_types::{
    CodeDescription, DiagnosticRelatedInformation, DiagnosticSeverity, Location, NumberOrString,
    Url,
};

use super::position::LineIndex;
use crate::assets::Loader;
use crate::bvh::AccelKind;
use crate::compile::{Incremental, Overrides};
use crate::diag::{Code, Diagnostic, Severity, Staged};
use crate::scene::{self, BuildOptions};
use crate::source::{SourceMap, Span};

/// Every diagnostic `scnc check PATH` reports, reading files through `loader`, with the sources
/// their spans point into.
pub fn check(path: &Path, loader: &dyn Loader) -> (Vec<Diagnostic>, SourceMap) {
    check_incremental(&mut Incremental::new(Overrides::default()), path, loader)
}

/// [`check`] through `front`, which remembers the document's last compile.
pub fn check_incremental(
    front: &mut Incremental,
    path: &Path,
    loader: &dyn Loader,
) -> (Vec<Diagnostic>, SourceMap) {
    let mut sources = SourceMap::new();
    let options = BuildOptions {
        accel: AccelKind::None,
        camera: None,
    };
    let checked: Staged<()> = front
        .compile(path, loader, &mut sources)
        .and_then(|desc| scene::build(&desc, loader, &options).map(|_| ()));
    (checked.diagnostics, sources)
}

/// The LSP form of the diagnostics that belong in the checked document at `path`: those whose
/// primary label lies in it, and those with no label at all (shown at its start).
pub fn to_lsp(
    path: &Path,
    diagnostics: &[Diagnostic],
    sources: &SourceMap,
) -> Vec<lsp_types::Diagnostic> {
    // The root is file 0; its path in the map is the normalised one.
    let root = sources
        .find(path)
        .or_else(|| sources.files().next().map(|(id, _)| id));
    let Some(file) = root else {
        return diagnostics
            .iter()
            .filter(|d| d.primary.is_none())
            .map(|d| convert(d, lsp_types::Range::default(), sources))
            .collect();
    };
    let text = &sources.get(file).text;
    let index = LineIndex::new(text);
    diagnostics
        .iter()
        .filter_map(|d| match &d.primary {
            Some(label) if label.span.file == file => {
                Some(convert(d, span_range(&index, label.span), sources))
            }
            Some(_) => None,
            None => Some(convert(d, lsp_types::Range::default(), sources)),
        })
        .collect()
}

/// Where the explanations of codes are: `SCNC_EXPLAIN_URL` when set (e.g. the explain folder
/// of a hosted copy of the repository), else the checkout scnc was built from.
pub const EXPLAIN_URL_VAR: &str = "SCNC_EXPLAIN_URL";

/// The link to `code`'s explanation (what `scnc explain CODE` prints): the registry's Markdown
/// file, `BASE/STAGE/NAME.md`, where BASE is [`EXPLAIN_URL_VAR`] or, by default,
/// `file://…/src/diag/explain` in the checkout scnc was built from.
pub fn explain_url(code: Code) -> Option<Url> {
    let base = std::env::var(EXPLAIN_URL_VAR)
        .unwrap_or_else(|_| format!("file://{}/src/diag/explain", env!("CARGO_MANIFEST_DIR")));
    let base = base.trim_end_matches('/');
    Url::parse(&format!("{base}/{}/{}.md", code.stage(), code.name())).ok()
}

fn span_range(index: &LineIndex<'_>, span: Span) -> lsp_types::Range {
    index.range(span.start as usize, span.end as usize)
}

fn convert(d: &Diagnostic, range: lsp_types::Range, sources: &SourceMap) -> lsp_types::Diagnostic {
    let mut message = d.message.clone();
    if let Some(label) = d.primary.as_ref().filter(|l| !l.message.is_empty()) {
        message = format!("{message}: {}", label.message);
    }
    if let Some(help) = &d.help {
        message = format!("{message}\nhelp: {help}");
    }
    let related: Vec<DiagnosticRelatedInformation> = d
        .secondary
        .iter()
        .filter_map(|label| {
            let file = sources.get(label.span.file);
            let uri = Url::from_file_path(&file.path).ok()?;
            let index = LineIndex::new(&file.text);
            Some(DiagnosticRelatedInformation {
                location: Location::new(uri, span_range(&index, label.span)),
                message: label.message.clone(),
            })
        })
        .collect();
    lsp_types::Diagnostic {
        range,
        severity: Some(match d.severity {
            Severity::Error => DiagnosticSeverity::ERROR,
            Severity::Warning => DiagnosticSeverity::WARNING,
        }),
        code: Some(NumberOrString::String(d.code.as_str().to_string())),
        code_description: explain_url(d.code).map(|href| CodeDescription { href }),
        source: Some("scnc".into()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        ..lsp_types::Diagnostic::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assets::MemLoader;
    use crate::compile::Reuse;

    /// As you type in an object, the document's front end re-checks that object alone, and the
    /// diagnostics are those of a check from scratch.
    #[test]
    fn typing_in_an_object_checks_it_alone_with_the_same_diagnostics() {
        let path = Path::new("typing.scn");
        let base = "scnc 1\ncamera c { eye (0, 1, -5)  target (0, 0, 0)  fov 40deg }\n\
                    material m = phong { diffuse #fff }\nmaterial unused = phong { }\n\
                    mesh b = box { size 1 }\n\
                    object b { material m  transform { translate (0, 0, 0) } }\n\
                    object b { material m  transform { translate (1, 0, 0) } }\n";
        let mut front = Incremental::new(Overrides::default());
        let mut loader = MemLoader::new();
        loader.insert(path, base);
        let _ = check_incremental(&mut front, path, &loader);
        for typed in [
            "translate (1, 2, 0)",
            "translate (1, 2, 0deg)",
            "translate (1, 2, 3)",
        ] {
            let text = base.replacen("translate (1, 0, 0)", typed, 1);
            loader.insert(path, text);
            let (got, _) = check_incremental(&mut front, path, &loader);
            assert!(
                matches!(front.reuse, Reuse::Statements { checked: 1, .. }),
                "{typed}: {:?}",
                front.reuse
            );
            let (want, _) = check(path, &loader);
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "{typed}");
            assert!(!got.is_empty(), "the unused material is reported");
        }
    }
}
