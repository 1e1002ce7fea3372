//! Shared by every subcommand: compile a file and print its diagnostics in the chosen format.
//!
//! Human format: miette's fancy rendering when stderr is a terminal, the plain renderer
//! otherwise (no escape codes in logs). JSON: one document on stdout.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};

use crate::assets::FsLoader;
use crate::compile::{compile_file, Compiled};
use crate::diag::{render_fancy, render_json, render_plain, summary};

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
    let compiled = compile_file(path, &loader);
    print_diagnostics(&compiled, diag.diagnostic_format, json_to);
    compiled
}

/// Prints diagnostics: human to stderr (fancy on a terminal), JSON as `json_to` says.
pub fn print_diagnostics(compiled: &Compiled, format: DiagnosticFormat, json_to: JsonTo) {
    match format {
        DiagnosticFormat::Json => {
            let json = render_json(&compiled.diagnostics, &compiled.sources);
            match json_to {
                JsonTo::Stdout => println!("{json}"),
                JsonTo::Stderr => eprintln!("{json}"),
            }
        }
        DiagnosticFormat::Human => {
            let tty = std::io::stderr().is_terminal();
            for d in &compiled.diagnostics {
                let text = if tty {
                    render_fancy(d, &compiled.sources, true)
                } else {
                    render_plain(d, &compiled.sources, 100)
                };
                eprintln!("{text}");
            }
            if !compiled.diagnostics.is_empty() {
                eprintln!("{}", summary(&compiled.diagnostics));
            }
        }
    }
}
