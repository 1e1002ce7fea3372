//! Shared by every subcommand: the diagnostic options, `--strict`, and reporting what a chain
//! of stages (each returning [`Staged`]) accumulated, once, in the chosen format.
//!
//! Human format: miette's fancy rendering when stderr is a terminal, the plain renderer
//! otherwise (no escape codes in logs). JSON: one document on stdout.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, ValueEnum};

use crate::diag::{render_fancy, render_json, render_plain, summary, Diagnostic, Staged};
use crate::source::SourceMap;

/// `--diagnostic-format`: how errors and warnings are printed.
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
    /// Standard output.
    Stdout,
    /// Standard error.
    Stderr,
}

/// `--strict` at a stage boundary: every warning so far becomes an error, and a stage result
/// with an error has no value (so the chain stops there, as it does on any error).
pub fn strict<T>(mut staged: Staged<T>, diag: &DiagArgs) -> Staged<T> {
    if diag.strict {
        promote_warnings(&mut staged.diagnostics);
        if staged.has_errors() {
            staged.value = None;
        }
    }
    staged
}

/// Reports what a chain of stages accumulated, once, in the format `diag` asks for (human: to
/// stderr; JSON: as `json_to` says). Prints nothing when there is nothing to say.
pub fn report<T>(staged: &Staged<T>, sources: &SourceMap, diag: &DiagArgs, json_to: JsonTo) {
    print_diagnostic_list(
        &staged.diagnostics,
        sources,
        diag.diagnostic_format,
        json_to,
    );
}

/// The exit code of a chain that ended in `staged`: failure when a stage failed or reported an
/// error.
pub fn exit_code<T>(staged: &Staged<T>) -> ExitCode {
    if staged.value.is_none() || staged.has_errors() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
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
                // The fancy rendering carries the `scnc explain` pointer in its help; the plain
                // one (kept byte-stable for snapshots and logs) gets it as a last note here.
                let text = if tty {
                    render_fancy(d, sources, true)
                } else {
                    let plain = render_plain(d, sources, 100);
                    format!(
                        "{}\n   = note: {}\n",
                        plain.trim_end(),
                        d.code.explain_hint()
                    )
                };
                eprintln!("{text}");
            }
            eprintln!("{}", summary(diags));
        }
    }
}
