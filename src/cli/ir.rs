//! `scnc ir FILE`: compile and print the IR as JSON on stdout; diagnostics go to stderr (also
//! with `--diagnostic-format json`), so stdout is exactly the IR. Exit 1 on errors.

use std::process::ExitCode;

use clap::Args;

use super::report::{compile_and_report, DiagArgs, JsonTo, SceneArg};

#[derive(Debug, Clone, Args)]
pub struct IrArgs {
    #[command(flatten)]
    pub scene: SceneArg,
    #[command(flatten)]
    pub diag: DiagArgs,
}

pub fn run(args: &IrArgs) -> ExitCode {
    let compiled = compile_and_report(&args.scene.file, &args.diag, JsonTo::Stderr);
    match &compiled.scene {
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
