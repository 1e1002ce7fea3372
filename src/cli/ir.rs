//! `scnc ir FILE`: compile and print the IR as JSON on stdout; diagnostics go to stderr (also
//! with `--diagnostic-format json`), so stdout is exactly the IR. Exit 1 on errors.

use std::process::ExitCode;

use clap::Args;

use super::overrides::OverrideArgs;
use super::report::{report, strict, DiagArgs, JsonTo, SceneArg};
use crate::assets::FsLoader;
use crate::compile::compile_with;
use crate::source::SourceMap;

/// `scnc ir`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct IrArgs {
    /// The scene file.
    #[command(flatten)]
    pub scene: SceneArg,
    /// `--frame F`, `--define NAME=VALUE`.
    #[command(flatten)]
    pub overrides: OverrideArgs,
    /// Diagnostic format and `--strict`.
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// `scnc ir`: compile, report, print the IR.
pub fn run(args: &IrArgs) -> ExitCode {
    let mut sources = SourceMap::new();
    let compiled = strict(
        compile_with(
            &args.scene.file,
            &FsLoader::new(),
            &mut sources,
            &args.overrides.overrides(),
        ),
        &args.diag,
    );
    report(&compiled, &sources, &args.diag, JsonTo::Stderr);
    match &compiled.value {
        Some(scene) => match serde_json::to_string_pretty(scene) {
            Ok(json) => {
                println!("{json}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: cannot serialise the IR: {e}");
                ExitCode::FAILURE
            }
        },
        None => ExitCode::FAILURE,
    }
}
