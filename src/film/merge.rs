//! Stage 5, film: `scnc merge` — decoded tiles ([`Tile`]) → the whole image's [`Film`] and
//! the output settings the tiles carry, or a diagnostic for every reason not to merge.
//!
//! Syntax: `scnc merge part*.exr -o final.png`. Refuses tiles of different scenes or settings
//! (their identities or output settings differ), tiles that overlap (naming both files and
//! the rows) and tiles that leave pixels uncovered (naming the rows and, when every tile was
//! cut for the same `N`, the missing `--tile K/N`). Reading the files and writing the result
//! are the CLI's (`cli/merge.rs`); this is the pure part, testable in memory.

use super::tile::Tile;
use super::{Film, WriteSettings};
use crate::diag::{Code, Diagnostic, Staged};
use crate::render::window::split;

/// One decoded tile and the name of its file (for diagnostics).
#[derive(Debug, Clone)]
pub struct Part {
    /// The file it came from, as given on the command line.
    pub name: String,
    /// Its header and pixels.
    pub tile: Tile,
}

/// The assembled image.
#[derive(Debug, Clone)]
pub struct Merged {
    /// The whole image's radiance, bit for bit as one render would have made it.
    pub film: Film,
    /// The exposure and tone map the tiles were rendered with (for 8-bit output).
    pub output: WriteSettings,
}

/// Assembles `parts` (see the module doc); `failed` with every problem found.
pub fn merge(parts: &[Part]) -> Staged<Merged> {
    let Some(first) = parts.first() else {
        return Staged::failed(vec![Diagnostic::error(
            Code::MergeMissing,
            "no tiles to merge",
        )
        .help("give the tile files: scnc merge part*.exr -o final.png")]);
    };
    let mismatched = mismatches(first, parts);
    if !mismatched.is_empty() {
        return Staged::failed(mismatched);
    }
    let mut problems = overlaps(parts);
    problems.extend(missing(parts));
    if !problems.is_empty() {
        return Staged::failed(problems);
    }
    let h = &first.tile.header;
    let mut film = Film::new(h.width, h.height);
    for part in parts {
        let w = part.tile.window;
        for y in 0..w.height() {
            for x in 0..w.width() {
                film.set(w.x0 + x, w.y0 + y, part.tile.film.get(x, y));
            }
        }
    }
    Staged::ok(Merged {
        film,
        output: h.output,
    })
}

/// A diagnostic for each part whose scene, size or output settings differ from `first`'s.
fn mismatches(first: &Part, parts: &[Part]) -> Vec<Diagnostic> {
    let a = &first.tile.header;
    parts
        .iter()
        .filter(|p| {
            let b = &p.tile.header;
            (b.identity, b.width, b.height, b.output) != (a.identity, a.width, a.height, a.output)
        })
        .map(|p| {
            let b = &p.tile.header;
            Diagnostic::error(
                Code::MergeMismatch,
                format!(
                    "`{}` is a tile of another scene or settings than `{}` ({} {}x{} against {} {}x{})",
                    p.name, first.name, b.identity, b.width, b.height, a.identity, a.width, a.height
                ),
            )
            .help(
                "render every tile from the same scene file with the same flags \
                 (--spp, --resolution, --quality, --noise, --camera, --accel, --frame); \
                 re-render the stale tiles",
            )
        })
        .collect()
}

/// A diagnostic for each pair of parts whose windows share pixels.
fn overlaps(parts: &[Part]) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (i, a) in parts.iter().enumerate() {
        for b in &parts[i + 1..] {
            let (wa, wb) = (a.tile.window, b.tile.window);
            let (y0, y1) = (wa.y0.max(wb.y0), wa.y1.min(wb.y1));
            let (x0, x1) = (wa.x0.max(wb.x0), wa.x1.min(wb.x1));
            if y0 < y1 && x0 < x1 {
                out.push(
                    Diagnostic::error(
                        Code::MergeOverlap,
                        format!(
                            "`{}` (tile {}) and `{}` (tile {}) both cover rows {y0}..{y1}, columns {x0}..{x1}",
                            a.name,
                            index(a),
                            b.name,
                            index(b)
                        ),
                    )
                    .help("give each tile once, all cut with the same N (`--tile K/N`)"),
                );
            }
        }
    }
    out
}

fn index(p: &Part) -> String {
    format!("{}/{}", p.tile.header.index, p.tile.header.count)
}

/// A diagnostic if some pixels are covered by no part (called once overlaps are ruled out).
fn missing(parts: &[Part]) -> Option<Diagnostic> {
    let h = &parts.first()?.tile.header;
    let mut uncovered: Vec<(u32, u32)> = Vec::new();
    for y in 0..h.height {
        let covered: u64 = parts
            .iter()
            .map(|p| p.tile.window)
            .filter(|w| (w.y0..w.y1).contains(&y))
            .map(|w| u64::from(w.width()))
            .sum();
        if covered < u64::from(h.width) {
            match uncovered.last_mut() {
                Some(run) if run.1 == y => run.1 = y + 1,
                _ => uncovered.push((y, y + 1)),
            }
        }
    }
    if uncovered.is_empty() {
        return None;
    }
    let rows: Vec<String> = uncovered.iter().map(|(a, b)| format!("{a}..{b}")).collect();
    let mut d = Diagnostic::error(
        Code::MergeMissing,
        format!(
            "the tiles leave pixels of rows {} uncovered",
            rows.join(", ")
        ),
    );
    let n = h.count;
    if parts.iter().all(|p| p.tile.header.count == n) {
        let absent: Vec<String> = (0..n)
            .filter(|k| parts.iter().all(|p| p.tile.header.index != *k))
            .filter(|k| split(*k, n, h.width, h.height).is_some())
            .map(|k| format!("{k}/{n}"))
            .collect();
        d = d.help(format!(
            "missing tiles: {} (render each with `scnc render SCENE --tile K/N -o FILE.exr`)",
            absent.join(", ")
        ));
    }
    Some(d)
}
