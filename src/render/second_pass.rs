//! Stage 4, render: each adaptive pixel's first whole batch (20 samples), which every pixel of
//! a band and a one-pixel margin takes (unless it stopped early, `render::early_stop`) before
//! any pixel decides on it, so that each can pool its neighbours' replicate spreads
//! (`render::pooled_stop`). Kept like `render::first_pass`'s first batches: a band's
//! [`SecondPass`] covers its rows and a margin of `early_stop::RADIUS` rows and columns, the
//! rows above kept from the band before.
//!
//! Syntax: none of its own; `render { noise 0.05 }` / `--noise 0.05` renders this way.

use super::early_stop;
use super::estimate::{Accumulator, PixelEstimate};
use super::integrator::RayCounts;
use super::pooled_stop::ReplicatePool;
use super::tile_rows::{self, TileRows};
use super::{Cancelled, PixelWindow, Tile};

/// Where an adaptive pixel is after its first whole batch.
#[derive(Debug, Clone, Copy)]
pub(super) enum PixelState {
    /// It stopped before (early, or at its cap).
    Done(PixelEstimate),
    /// It took its first whole batch, `taken` samples in all, and waits for the pooled stop.
    Pooling { acc: Accumulator, taken: u32 },
}

/// The states after the first whole batch over one band of rows and its margin.
pub(super) struct SecondPass {
    area: PixelWindow,
    /// Row-major over `area`; `None` only before the tiles fill it.
    pixels: Vec<Option<PixelState>>,
    /// What each pixel's replicates say ([`Accumulator::relative_replicate_variance`]),
    /// row-major over `area`.
    spreads: Vec<Option<(f64, f64)>>,
    pub(super) counts: RayCounts,
}

impl SecondPass {
    /// The states over `area` that `before` holds; the others are for the tiles to write
    /// ([`SecondPass::fresh`]) before [`SecondPass::finish`].
    pub(super) fn start(
        area: PixelWindow,
        before: Option<&SecondPass>,
        spare: Option<SecondPass>,
    ) -> SecondPass {
        let width = area.width() as usize;
        // The band before last's buffers, reused (as `FirstBatches::start`'s).
        let (mut pixels, mut spreads) =
            spare.map_or_else(Default::default, |s| (s.pixels, s.spreads));
        pixels.clear();
        pixels.resize(width * area.height() as usize, None);
        spreads.clear();
        let mut out = SecondPass {
            area,
            pixels,
            spreads,
            counts: RayCounts::default(),
        };
        if let Some(before) = before {
            for y in area.y0..area.y1 {
                for x in area.x0..area.x1 {
                    if let Some(state) = before.at(x, y) {
                        let i = (y - area.y0) as usize * width + (x - area.x0) as usize;
                        out.pixels[i] = Some(*state);
                    }
                }
            }
        }
        out
    }

    /// Each of `tiles`' pixels, for its tile to write its state into (`tile_rows`).
    pub(super) fn fresh(&mut self, tiles: &[Tile]) -> Vec<TileRows<'_, Option<PixelState>>> {
        tile_rows::split(&mut self.pixels, self.area, tiles)
    }

    /// The band's states once the tiles have written theirs, with their ray counts
    /// (`results`); `Cancelled` if a tile is missing.
    pub(super) fn finish(self, results: Vec<Option<RayCounts>>) -> Result<SecondPass, Cancelled> {
        let mut out = self;
        for counts in results {
            out.counts.add(&counts.ok_or(Cancelled)?);
        }
        let spreads = out.pixels.iter().map(|state| match state {
            Some(PixelState::Pooling { acc, .. }) => acc.relative_replicate_variance(),
            _ => None,
        });
        out.spreads.extend(spreads);
        Ok(out)
    }

    pub(super) fn at(&self, x: u32, y: u32) -> Option<&PixelState> {
        self.index(x, y)
            .and_then(|i| self.pixels.get(i))
            .and_then(Option::as_ref)
    }

    /// Where (`x`, `y`) is in `pixels` and `spreads`; `None` outside `area`.
    fn index(&self, x: u32, y: u32) -> Option<usize> {
        let a = &self.area;
        if x < a.x0 || x >= a.x1 || y < a.y0 || y >= a.y1 {
            return None;
        }
        Some((y - a.y0) as usize * a.width() as usize + (x - a.x0) as usize)
    }

    /// The replicate spreads of the block within [`early_stop::RADIUS`] of (`x`, `y`), its
    /// own included, pooled in a fixed order.
    pub(super) fn pool(&self, x: u32, y: u32) -> ReplicatePool {
        let r = early_stop::RADIUS as i64;
        let (x, y) = (i64::from(x), i64::from(y));
        let block = (-r..=r)
            .flat_map(move |dy| (-r..=r).map(move |dx| (dx, dy)))
            .filter_map(|(dx, dy)| {
                let (nx, ny) = (u32::try_from(x + dx).ok()?, u32::try_from(y + dy).ok()?);
                *self.spreads.get(self.index(nx, ny)?)?
            });
        ReplicatePool::pool(block)
    }
}
