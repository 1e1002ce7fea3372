//! `scnc fmt [FILES…] [--check]`: format `.scn` files in place (atomically), or with `--check`
//! print a unified diff of what would change and exit 1. With no files, formats standard input
//! to standard output. A file with syntax errors is left untouched and its diagnostics printed
//! (exit 1). The formatting itself is [`crate::fmt`].

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::Args;
use similar::TextDiff;

use super::report::{print_diagnostic_list, DiagnosticFormat, JsonTo};
use crate::diag::{Code, Diagnostic};
use crate::film::{write_atomic_with, Durability};
use crate::source::SourceMap;

/// `scnc fmt`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct FmtArgs {
    /// The .scn files to format; none: standard input to standard output.
    #[arg(value_name = "FILES")]
    pub files: Vec<PathBuf>,
    /// Change nothing: print a diff for each file that is not formatted and exit 1.
    #[arg(long)]
    pub check: bool,
}

/// What became of one file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    /// Already formatted.
    Unchanged,
    /// Rewritten, or (with `--check`) would be.
    Changed,
    /// Unreadable, not text, syntax errors or unwritable: left as it was.
    Failed,
}

/// `scnc fmt`: format every file, report, exit 1 if any failed or (`--check`) would change.
pub fn run(args: &FmtArgs) -> ExitCode {
    if args.files.is_empty() {
        return format_stdin(args.check);
    }
    let mut worst = Outcome::Unchanged;
    for path in &args.files {
        match format_path(path, args.check) {
            Outcome::Failed => worst = Outcome::Failed,
            Outcome::Changed if worst == Outcome::Unchanged => worst = Outcome::Changed,
            _ => {}
        }
    }
    match worst {
        Outcome::Changed if args.check => ExitCode::FAILURE,
        Outcome::Failed => ExitCode::FAILURE,
        _ => ExitCode::SUCCESS,
    }
}

fn format_stdin(check: bool) -> ExitCode {
    let mut text = String::new();
    if let Err(e) = std::io::stdin().read_to_string(&mut text) {
        eprintln!("error: cannot read standard input: {e}");
        return ExitCode::FAILURE;
    }
    match format_text(Path::new("<stdin>"), text) {
        Some((old, new)) if check => {
            if old == new {
                ExitCode::SUCCESS
            } else {
                print!("{}", unified_diff(Path::new("<stdin>"), &old, &new));
                ExitCode::FAILURE
            }
        }
        Some((_, new)) => {
            let mut out = std::io::stdout().lock();
            match out.write_all(new.as_bytes()).and_then(|()| out.flush()) {
                Ok(()) => ExitCode::SUCCESS,
                Err(_) => ExitCode::FAILURE,
            }
        }
        None => ExitCode::FAILURE,
    }
}

/// Formats one file in place (or diffs it, with `check`).
fn format_path(path: &Path, check: bool) -> Outcome {
    let text = match std::fs::read(path) {
        Ok(bytes) => match String::from_utf8(bytes) {
            Ok(text) => text,
            Err(e) => {
                let d = Diagnostic::error(
                    Code::SourceNotText,
                    format!("{} is not a text file: {e}", path.display()),
                )
                .help("scene files are UTF-8 text; check that you named the .scn file");
                return unreadable(d);
            }
        },
        Err(e) => {
            let d = Diagnostic::error(Code::IoRead, format!("cannot read {}: {e}", path.display()))
                .help("check the path");
            return unreadable(d);
        }
    };
    let Some((old, new)) = format_text(path, text) else {
        return Outcome::Failed;
    };
    if old == new {
        return Outcome::Unchanged;
    }
    if check {
        print!("{}", unified_diff(path, &old, &new));
        return Outcome::Changed;
    }
    match write_atomic_with(path, Durability::Synced, |f| f.write_all(new.as_bytes())) {
        Ok(()) => Outcome::Changed,
        Err(e) => {
            eprintln!("error: cannot write {}: {e}", path.display());
            Outcome::Failed
        }
    }
}

/// The text before and after formatting, or `None` (diagnostics printed) when it does not parse.
fn format_text(path: &Path, text: String) -> Option<(String, String)> {
    let mut sources = SourceMap::new();
    let file = sources.add(path, path.display().to_string(), text.as_str());
    let formatted = crate::fmt::format(file, &text);
    match formatted.value {
        Some(new) => Some((text, new)),
        None => {
            print_diagnostic_list(
                &formatted.diagnostics,
                &sources,
                DiagnosticFormat::Human,
                JsonTo::Stderr,
            );
            None
        }
    }
}

/// A unified diff from `old` to `new`, headed with the file's name.
fn unified_diff(path: &Path, old: &str, new: &str) -> String {
    let name = path.display().to_string();
    TextDiff::from_lines(old, new)
        .unified_diff()
        .context_radius(3)
        .header(&name, &format!("{name} (formatted)"))
        .to_string()
}

/// Reports why a file could not be read (no source to point into) and fails it.
fn unreadable(d: Diagnostic) -> Outcome {
    print_diagnostic_list(
        &[d],
        &SourceMap::new(),
        DiagnosticFormat::Human,
        JsonTo::Stderr,
    );
    Outcome::Failed
}
