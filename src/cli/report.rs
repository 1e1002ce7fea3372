//! Shared by every subcommand: compile a file and print its diagnostics in the chosen format.
//!
//! Human format: miette's fancy rendering when stderr is a terminal, the plain renderer
//! otherwise (no escape codes in logs). JSON: one document on stdout.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::assets::FsLoader;
use crate::compile::{compile_file, Compiled};
use crate::diag::{render_fancy, render_json, render_plain, summary, Diagnostic};
use crate::source::SourceMap;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum DiagnosticFormat {
    /// Readable text (colours on a terminal).
    #[default]
    Human,
    /// One JSON document on stdout, for editors and tools.
    Json,
}

/// Options every compiling subcommand takes.
#[derive(Debug, Clone, Args)]
pub struct DiagArgs {
    /// How to print errors and warnings.
    #[arg(long, value_enum, default_value_t = DiagnosticFormat::Human)]
    pub diagnostic_format: DiagnosticFormat,
    /// Treat every warning as an error (exit 1), e.g. a missing MTL file or texture.
    #[arg(long)]
    pub strict: bool,
}

/// `--strict`: every warning becomes an error, saying why.
pub fn promote_warnings(diags: &mut [Diagnostic]) {
    for d in diags.iter_mut().filter(|d| !d.is_error()) {
        d.severity = crate::diag::Severity::Error;
        d.help = Some(match d.help.take() {
            Some(h) => format!("{h} (an error because of --strict)"),
            None => "an error because of --strict".into(),
        });
    }
}

/// The scene file argument.
#[derive(Debug, Clone, Args)]
pub struct SceneArg {
    /// The .scn file to compile.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
}

/// Where a JSON diagnostics document goes: stdout for `check` (it is the command's output),
/// stderr for commands whose stdout is something else (`ir`, `render`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JsonTo {
    Stdout,
    Stderr,
}

/// Compiles `path` from disk and prints its diagnostics (human format: to stderr).
pub fn compile_and_report(path: &Path, diag: &DiagArgs, json_to: JsonTo) -> Compiled {
    let loader = FsLoader::new();
    let mut compiled = compile_file(path, &loader);
    if diag.strict {
        promote_warnings(&mut compiled.diagnostics);
        if compiled.has_errors() {
            compiled.scene = None;
        }
    }
    print_diagnostics(&compiled, diag.diagnostic_format, json_to);
    compiled
}

/// Prints a compile's diagnostics: human to stderr (fancy on a terminal), JSON as `json_to`
/// says.
pub fn print_diagnostics(compiled: &Compiled, format: DiagnosticFormat, json_to: JsonTo) {
    print_diagnostic_list(&compiled.diagnostics, &compiled.sources, format, json_to);
}

/// Prints diagnostics of any stage whose spans point into `sources` (build and write errors
/// too). Prints nothing for an empty list.
pub fn print_diagnostic_list(
    diags: &[Diagnostic],
    sources: &SourceMap,
    format: DiagnosticFormat,
    json_to: JsonTo,
) {
    if diags.is_empty() {
        return;
    }
    match format {
        DiagnosticFormat::Json => {
            let json = render_json(diags, sources);
            match json_to {
                JsonTo::Stdout => println!("{json}"),
                JsonTo::Stderr => eprintln!("{json}"),
            }
        }
        DiagnosticFormat::Human => {
            let tty = std::io::stderr().is_terminal();
            for d in diags {
                let text = if tty {
                    render_fancy(d, sources, true)
                } else {
                    render_plain(d, sources, 100)
                };
                eprintln!("{text}");
            }
            eprintln!("{}", summary(diags));
        }
    }
}
