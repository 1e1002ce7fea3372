//! `scnc explain CODE` prints what a diagnostic code means, with an example of the mistake and
//! the fix (as `rustc --explain`); `scnc explain --list` lists every code with its summary.
//!
//! CODE is the full code (`scnc::check::unknown_material`) or a unique tail of it
//! (`check::unknown_material`, `unknown_mesh`). An unknown code exits 1 with the closest codes;
//! a tail several codes share exits 1 listing them.

use std::process::ExitCode;

use clap::Args;

use crate::diag::suggest::did_you_mean;
use crate::diag::Code;

/// Arguments of `scnc explain`.
#[derive(Debug, Clone, Args)]
pub struct ExplainArgs {
    /// The code to explain, e.g. `scnc::check::unknown_material` or `unknown_mesh`.
    #[arg(value_name = "CODE", required_unless_present = "list")]
    pub code: Option<String>,
    /// List every code with its one-line summary.
    #[arg(long, conflicts_with = "code")]
    pub list: bool,
}

/// Runs `scnc explain`.
pub fn run(args: &ExplainArgs) -> ExitCode {
    if args.list {
        print!("{}", list());
        return ExitCode::SUCCESS;
    }
    let query = args.code.as_deref().unwrap_or_default();
    match explain(query) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(message) => {
            eprintln!("{message}");
            ExitCode::FAILURE
        }
    }
}

/// Every code and its summary, one per line, aligned.
pub fn list() -> String {
    let width = Code::ALL
        .iter()
        .map(|c| c.as_str().len())
        .max()
        .unwrap_or(0);
    Code::ALL
        .iter()
        .map(|c| format!("{:width$}  {}\n", c.as_str(), c.summary()))
        .collect()
}

/// The text `scnc explain QUERY` prints, or the error message when QUERY names no single code.
pub fn explain(query: &str) -> Result<String, String> {
    match Code::lookup(query).as_slice() {
        [code] => Ok(format!(
            "{}: {}\n\n{}",
            code.as_str(),
            code.summary(),
            code.explanation()
        )),
        [] => Err(unknown(query)),
        several => Err(format!(
            "`{query}` names several codes; choose one:\n{}",
            several
                .iter()
                .map(|c| format!("  {}  {}\n", c.as_str(), c.summary()))
                .collect::<String>()
        )),
    }
}

/// "no code `x`", with the closest full code or last segment.
fn unknown(query: &str) -> String {
    let names = Code::ALL.iter().map(|c| c.name());
    let full = Code::ALL.iter().map(|c| c.as_str());
    let close = did_you_mean(query, full).or_else(|| did_you_mean(query, names));
    let hint = match close {
        Some(c) => format!("did you mean `{c}`?"),
        None => "run `scnc explain --list` for every code".to_string(),
    };
    format!("error: no diagnostic code `{query}`\n  = help: {hint}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explains_full_codes_and_tails() {
        let full = explain("scnc::check::unknown_material").unwrap();
        assert!(full.starts_with("scnc::check::unknown_material: "));
        assert!(full.contains("Mistake"));
        assert_eq!(explain("check::unknown_material").unwrap(), full);
        assert!(explain("unknown_mesh")
            .unwrap()
            .starts_with("scnc::check::unknown_mesh"));
    }

    #[test]
    fn unknown_and_ambiguous_codes_are_errors_with_help() {
        let e = explain("unknown_materail").unwrap_err();
        assert!(e.contains("did you mean `unknown_material`?"), "{e}");
        let e = explain("scnc::check::unknwn_mesh").unwrap_err();
        assert!(
            e.contains("did you mean `scnc::check::unknown_mesh`?"),
            "{e}"
        );
        let e = explain("unknown_material").unwrap_err();
        assert!(
            e.contains("scnc::check::unknown_material")
                && e.contains("scnc::obj::unknown_material")
        );
        assert!(explain("zzzz").unwrap_err().contains("--list"));
    }

    #[test]
    fn list_has_every_code_once() {
        let l = list();
        assert_eq!(l.lines().count(), Code::ALL.len());
        for c in Code::ALL {
            assert!(l.contains(c.as_str()));
        }
    }
}
