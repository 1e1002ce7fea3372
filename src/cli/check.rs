//! `scnc check FILE [--compile-only] [--diagnostic-format human|json]`: compile the scene, then
//! build it as `scnc render` would (meshes, environment maps and textures read and validated,
//! lights checked against the geometry; no acceleration structure, no pixels), and print every
//! diagnostic of both stages in one list. Exit 1 on errors (warnings alone exit 0).
//! `--compile-only` stops after the compile: no file but the scene and its includes is read.
//! `--strict` makes every warning an error.

use std::process::ExitCode;

use clap::Args;

use super::report::{print_diagnostic_list, DiagArgs, DiagnosticFormat, JsonTo, SceneArg};
use crate::assets::FsLoader;
use crate::bvh::AccelKind;
use crate::compile::compile_file;
use crate::diag::render_json;
use crate::scene::{self, BuildOptions};

#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    #[command(flatten)]
    pub scene: SceneArg,
    /// Compile only: skip reading and validating meshes, maps and textures.
    #[arg(long)]
    pub compile_only: bool,
    #[command(flatten)]
    pub diag: DiagArgs,
}

pub fn run(args: &CheckArgs) -> ExitCode {
    let loader = FsLoader::new();
    let compiled = compile_file(&args.scene.file, &loader);
    let mut diagnostics = compiled.diagnostics.clone();
    if let (Some(desc), false) = (&compiled.scene, args.compile_only) {
        let options = BuildOptions {
            accel: AccelKind::None,
            camera: None,
        };
        match scene::build(desc, &compiled.sources, &loader, &options) {
            Ok(scene) => diagnostics.extend(scene.warnings),
            Err(problems) => diagnostics.extend(problems),
        }
    }
    if args.diag.strict {
        super::report::promote_warnings(&mut diagnostics);
    }
    match args.diag.diagnostic_format {
        // The JSON document is the command's output: printed even when it lists nothing.
        DiagnosticFormat::Json => println!("{}", render_json(&diagnostics, &compiled.sources)),
        DiagnosticFormat::Human => print_diagnostic_list(
            &diagnostics,
            &compiled.sources,
            DiagnosticFormat::Human,
            JsonTo::Stdout,
        ),
    }
    if diagnostics.iter().any(|d| d.is_error()) {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
