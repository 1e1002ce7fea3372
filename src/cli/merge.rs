//! `scnc merge part*.exr -o final.png|.exr|.hdr|.pfm`: reads the tiles of
//! `scnc render --tile K/N`, checks they are one image's (see `film::merge`), and writes the
//! image exactly as `scnc render` would have (PNG with the tiles' exposure and tone map),
//! atomically. On any problem nothing is written, so an older output survives.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use super::report::{exit_code, report, DiagArgs, JsonTo};
use crate::diag::{Code, Diagnostic, Staged};
use crate::film::merge::{merge, Part};
use crate::film::tile::{decode_tile, TileError};
use crate::film::{self, Durability};
use crate::source::SourceMap;

/// `scnc merge`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct MergeArgs {
    /// The tile files (`scnc render --tile K/N -o FILE.exr`), in any order.
    #[arg(required = true, value_name = "TILE.exr")]
    pub tiles: Vec<PathBuf>,
    /// The image to write; the format follows the extension (.png, .exr, .hdr, .pfm).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// Diagnostic format and `--strict`.
    #[command(flatten)]
    pub diag: DiagArgs,
}

/// `scnc merge`: read every tile, merge, write; report every problem once.
pub fn run(args: &MergeArgs) -> ExitCode {
    let sources = SourceMap::new();
    let merged = read_parts(&args.tiles).and_then(|parts| merge(&parts));
    let written = merged
        .and_then(|m| film::write(&m.film, &args.output, &m.output, Durability::Synced, None));
    report(&written, &sources, &args.diag, JsonTo::Stdout);
    if written.value.is_some() {
        eprintln!(
            "wrote {} from {} tiles",
            args.output.display(),
            args.tiles.len()
        );
    }
    exit_code(&written)
}

/// Every file decoded, or a diagnostic for each that is not a readable tile.
fn read_parts(paths: &[PathBuf]) -> Staged<Vec<Part>> {
    let mut parts = Vec::with_capacity(paths.len());
    let mut problems = Vec::new();
    for path in paths {
        let name = path.display().to_string();
        let decoded = std::fs::read(path)
            .map_err(|e| TileError::Unreadable(e.to_string()))
            .and_then(|bytes| decode_tile(&bytes));
        match decoded {
            Ok(tile) => parts.push(Part { name, tile }),
            Err(e) => problems.push(diagnostic(&name, &e)),
        }
    }
    if problems.is_empty() {
        Staged::ok(parts)
    } else {
        Staged::failed(problems)
    }
}

fn diagnostic(name: &str, e: &TileError) -> Diagnostic {
    match e {
        TileError::Unreadable(_) => Diagnostic::error(
            Code::MergeUnreadable,
            format!("cannot read the tile `{name}`: {e}"),
        )
        .help("render this tile again: the same command gives the same bits"),
        TileError::NotATile(_) => {
            Diagnostic::error(Code::MergeNotATile, format!("`{name}` is {e}"))
                .help("give only the files `scnc render SCENE --tile K/N -o FILE.exr` wrote")
        }
    }
}
