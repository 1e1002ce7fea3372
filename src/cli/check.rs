//! `scnc check FILE [--diagnostic-format human|json]`: compile, print diagnostics, exit 1 on
//! errors (warnings alone exit 0).

use std::process::ExitCode;

use clap::Args;

use super::report::{compile_and_report, DiagArgs, JsonTo, SceneArg};

#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    #[command(flatten)]
    pub scene: SceneArg,
    #[command(flatten)]
    pub diag: DiagArgs,
}

pub fn run(args: &CheckArgs) -> ExitCode {
    let compiled = compile_and_report(&args.scene.file, &args.diag, JsonTo::Stdout);
    if compiled.has_errors() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
