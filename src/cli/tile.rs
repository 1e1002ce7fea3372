//! `scnc render … --tile K/N -o part.exr`: the command line's side of rendering one tile of
//! the image (see `render::window` for the split, `film::tile` for the file, docs/cluster.md).
//!
//! Before anything is built, [`plan`] checks that every output is an `.exr` file and that
//! the image has a row for each tile, and stamps the tile's header with the scene identity
//! (`ir::identity`) of the resolved settings. Once the scene is built, [`TilePlan::balanced`]
//! moves the band to where the rows' costs (`render::balance`) split evenly; after the
//! render, the window is written with `film::tile::write_tile`, atomically.

use std::path::PathBuf;

use crate::diag::{Code, Diagnostic};
use crate::film::tile::TileHeader;
use crate::film::{self, WriteSettings};
use crate::ir::{identity::identity, OutputFormat, SceneDesc};
use crate::render::balance::row_costs;
use crate::render::window::{split, split_by_cost, PixelWindow};
use crate::scene::Scene;
use crate::source::Span;

/// What one tile render needs beyond the scene: its window and its file header.
#[derive(Debug, Clone, Copy)]
pub struct TilePlan {
    /// The pixels to render.
    pub window: PixelWindow,
    /// What the file will say about itself.
    pub header: TileHeader,
}

impl TilePlan {
    /// The plan with its window cut at equal cumulative cost of the built scene's rows
    /// instead of equal height (the same on every machine: the costs are counted work).
    pub fn balanced(self, scene: &Scene) -> TilePlan {
        let (k, n) = (self.header.index, self.header.count);
        let costs = row_costs(scene);
        match split_by_cost(k, n, self.header.width, &costs) {
            Some(window) => TilePlan { window, ..self },
            // Only when the built image's size differs from the plan's, which it cannot.
            None => self,
        }
    }
}

/// `--tile K/N`: `K` in `0..N`, `N` at least 1.
pub fn parse_tile(s: &str) -> Result<(u32, u32), String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("expected K/N such as 0/4 (tile K of N, from 0), got `{s}`"))?;
    let number = |v: &str| -> Result<u32, String> {
        v.trim()
            .parse()
            .map_err(|_| format!("`{v}` is not a whole number"))
    };
    let (k, n) = (number(k)?, number(n)?);
    if n == 0 || k >= n {
        return Err(format!(
            "tile {k} of {n} does not exist: tiles count from 0, so K is 0..={}",
            n.saturating_sub(1)
        ));
    }
    Ok((k, n))
}

/// The plan of tile `k` of `n` of `desc` (render settings resolved) from camera `camera`,
/// or a diagnostic for each output that is not EXR and for a tile with no rows.
pub fn plan(
    (k, n): (u32, u32),
    desc: &SceneDesc,
    camera: usize,
    accel: &str,
    targets: &[(PathBuf, Option<Span>)],
) -> Result<TilePlan, Vec<Diagnostic>> {
    let mut problems: Vec<Diagnostic> = targets
        .iter()
        .filter(|(path, _)| film::format_for_path(path) != Some(OutputFormat::Exr))
        .map(|(path, span)| {
            let d = Diagnostic::error(
                Code::CliTileNotExr,
                format!(
                    "`--tile` writes an OpenEXR tile, but the output `{}` is not `.exr`",
                    path.display()
                ),
            )
            .help("give `-o part_K.exr`, then `scnc merge part_*.exr -o final.png`");
            match span {
                Some(span) => d.at(*span, "this output is used, as no `-o` was given"),
                None => d,
            }
        })
        .collect();
    let (width, height) = (desc.render.width, desc.render.height);
    let window = split(k, n, width, height);
    if window.is_none() {
        problems.push(
            Diagnostic::error(
                Code::CliTooManyTiles,
                format!(
                    "the image has {height} rows: it cannot be cut into {n} tiles of whole rows"
                ),
            )
            .help(format!("use at most {height} tiles")),
        );
    }
    match window {
        Some(window) if problems.is_empty() => Ok(TilePlan {
            window,
            header: TileHeader {
                identity: identity(desc, camera, accel),
                index: k,
                count: n,
                width,
                height,
                output: WriteSettings::from_render(&desc.render),
            },
        }),
        _ => Err(problems),
    }
}
