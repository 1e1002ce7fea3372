//! `scnc check FILE [--compile-only] [--diagnostic-format human|json]`: compile the scene, then
//! build it as `scnc render` would (meshes, environment maps and textures read and validated,
//! lights checked against the geometry; no acceleration structure, no pixels), and print every
//! diagnostic of both stages in one list. Exit 1 on errors (warnings alone exit 0).
//! `--compile-only` stops after the compile: no file but the scene and its includes is read.
//! `--strict` makes every warning an error.

use std::process::ExitCode;

use clap::Args;

use super::overrides::OverrideArgs;
use super::report::{report, strict, DiagArgs, DiagnosticFormat, JsonTo, SceneArg};
use crate::assets::FsLoader;
use crate::bvh::AccelKind;
use crate::compile::compile_with;
use crate::diag::{render_json, Staged};
use crate::scene::{self, BuildOptions};
use crate::source::SourceMap;

/// `scnc check`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    /// The scene file.
    #[command(flatten)]
    pub scene: SceneArg,
    /// Compile only: skip reading and validating meshes, maps and textures.
    #[arg(long)]
    pub compile_only: bool,
    /// `--frame F`, `--define NAME=VALUE`.
    #[command(flatten)]
    pub overrides: OverrideArgs,
    /// Diagnostic format and `--strict`.
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// `scnc check`: compile, build (unless `--compile-only`), report.
pub fn run(args: &CheckArgs) -> ExitCode {
    let loader = FsLoader::new();
    let mut sources = SourceMap::new();
    let options = BuildOptions {
        accel: AccelKind::None,
        camera: None,
    };
    let overrides = args.overrides.overrides();
    let checked =
        compile_with(&args.scene.file, &loader, &mut sources, &overrides).and_then(|desc| {
            if args.compile_only {
                return Staged::ok(());
            }
            scene::build(&desc, &loader, &options).map(|_| ())
        });
    let checked = strict(checked, &args.diag);
    match args.diag.diagnostic_format {
        // The JSON document is the command's output: printed even when it lists nothing.
        DiagnosticFormat::Json => println!("{}", render_json(&checked.diagnostics, &sources)),
        DiagnosticFormat::Human => report(&checked, &sources, &args.diag, JsonTo::Stdout),
    }
    if checked.has_errors() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
