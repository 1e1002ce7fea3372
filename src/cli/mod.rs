//! The command line: runs the pipeline once (`check`, `ir`, `render`) or in a loop
//! (`watch`). Only this module prints.
//!
//! Each subcommand lives in its own file with its own `Args` struct and `run` function; adding
//! one means a new file, a variant in [`Command`] and an arm in [`run`].

mod bench;
mod check;
mod explain;
mod fmt;
mod frames;
mod inspect;
mod ir;
mod lsp;
mod merge;
pub mod overrides;
mod parse;
mod render;
pub mod report;
mod stats;
mod targets;
mod tile;
mod watch;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use bench::BenchArgs;
pub use check::CheckArgs;
pub use explain::ExplainArgs;
pub use fmt::FmtArgs;
pub use inspect::InspectArgs;
pub use ir::IrArgs;
pub use lsp::LspArgs;
pub use merge::MergeArgs;
pub use render::{AccelArg, RenderArgs};
pub use report::{DiagArgs, DiagnosticFormat, JsonTo, SceneArg};
pub use watch::WatchArgs;

/// scnc: a declarative scene-language compiler and ray tracer.
#[derive(Debug, Parser)]
#[command(
    name = "scnc",
    version,
    about,
    after_help = "Every error and warning has a code, e.g. scnc::check::unknown_material: run \
                  `scnc explain CODE` for what it means and how to fix it, \
                  `scnc explain --list` for every code."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check a scene: report every error and warning (exit 0 clean, 1 on errors).
    ///
    /// Every diagnostic has a code; `scnc explain CODE` says what it means and how to fix it.
    Check(CheckArgs),
    /// Render a scene to an image (PNG, EXR, HDR or PFM by extension).
    ///
    /// Every diagnostic has a code; `scnc explain CODE` says what it means and how to fix it.
    Render(RenderArgs),
    /// Assemble the tiles of `scnc render --tile K/N` into one image, bit for bit as a single
    /// render would have made it (PNG, EXR, HDR or PFM by extension).
    Merge(MergeArgs),
    /// Print a scene's validated intermediate representation as JSON.
    Ir(IrArgs),
    /// Render, then re-render on every change of the scene, its includes and assets, with a
    /// live preview page (Ctrl-C to stop).
    Watch(WatchArgs),
    /// Show what scnc makes of an OBJ file: triangles, area, bounds, materials, warnings.
    Inspect(InspectArgs),
    /// Measure the speed/accuracy curve: `scnc bench quality scene.scn [--out DIR]`.
    Bench(BenchArgs),
    /// Format .scn files in place (`--check`: print a diff and exit 1 if any would change).
    ///
    /// Only whitespace changes and every comment stays; a file with syntax errors is left
    /// untouched and its diagnostics printed. No files: standard input to standard output.
    Fmt(FmtArgs),
    /// The language server, on stdin/stdout: diagnostics as you type and formatting, for
    /// editors (see editors/README.md).
    Lsp(LspArgs),
    /// Explain a diagnostic code with an example of the mistake and the fix.
    ///
    /// `scnc explain scnc::check::unknown_material` (or `unknown_mesh`, a unique last
    /// segment); `scnc explain --list` lists every code with its summary.
    Explain(ExplainArgs),
}

/// Parses the process arguments and runs the chosen command.
pub fn main() -> ExitCode {
    run(Cli::parse())
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> ExitCode {
    match cli.command {
        Command::Check(args) => check::run(&args),
        Command::Ir(args) => ir::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Merge(args) => merge::run(&args),
        Command::Watch(args) => watch::run(&args),
        Command::Inspect(args) => inspect::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Explain(args) => explain::run(&args),
        Command::Fmt(args) => fmt::run(&args),
        Command::Lsp(args) => lsp::run(&args),
    }
}
