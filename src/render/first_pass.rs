//! Stage 4, render: the first batches of an adaptive render, which every pixel takes before
//! any pixel decides, so that each can pool its neighbours' (`render::early_stop`). The render
//! goes band by band (rows of tiles, `render::bands`): a band's [`FirstBatches`] cover its rows
//! and a margin of `early_stop::RADIUS` rows and columns, those above kept from the band
//! before, so about a band's accumulators are held at a time, not the image's.
//!
//! Syntax: none of its own; `render { noise 0.05 }` / `--noise 0.05` renders this way.

use super::early_stop::{self, FirstBatchSpread, FirstBatchSummary, NeighbourPrior};
use super::estimate::Accumulator;
use super::integrator::RayCounts;
use super::tile_rows::{self, TileRows};
use super::{Cancelled, PixelWindow, Tile};

/// Side of the block of pixels a pixel pools ([`early_stop::RADIUS`] each way), and its pixels.
const BLOCK_SIDE: usize = 2 * early_stop::RADIUS as usize + 1;
const BLOCK_PIXELS: usize = BLOCK_SIDE * BLOCK_SIDE;
/// The pixel's own place in its block, row by row.
const CENTRE: usize = BLOCK_PIXELS / 2;

/// The first batches of an adaptive render's pixels in one band of rows and its margin
/// ([`early_stop::RADIUS`]), with the rays taken for the ones new to this band.
pub(super) struct FirstBatches {
    area: PixelWindow,
    /// Row-major over `area`.
    pixels: Vec<Accumulator>,
    /// What each of them tells its neighbours, row-major over `area`.
    summaries: Vec<FirstBatchSummary>,
    pub(super) counts: RayCounts,
}

impl FirstBatches {
    /// The first batches over `area` that `before` holds; the others are for the tiles to
    /// write ([`FirstBatches::fresh`]) before [`FirstBatches::finish`].
    pub(super) fn start(
        area: PixelWindow,
        before: Option<&FirstBatches>,
        spare: Option<FirstBatches>,
    ) -> FirstBatches {
        let width = area.width() as usize;
        // A band's buffers are a few hundred kB: fresh ones each band cost page faults (a
        // few percent of a loose-target render), so the band before last's are reused.
        let (mut pixels, mut summaries) =
            spare.map_or_else(Default::default, |s| (s.pixels, s.summaries));
        pixels.clear();
        pixels.resize(width * area.height() as usize, Accumulator::default());
        summaries.clear();
        let mut out = FirstBatches {
            area,
            pixels,
            summaries,
            counts: RayCounts::default(),
        };
        if let Some(before) = before {
            for y in area.y0..area.y1 {
                for x in area.x0..area.x1 {
                    if let Some(acc) = before.at(x, y) {
                        let i = (y - area.y0) as usize * width + (x - area.x0) as usize;
                        out.pixels[i] = *acc;
                    }
                }
            }
        }
        out
    }

    /// Each of `tiles`' pixels, for its tile to write its first batch into (`tile_rows`).
    pub(super) fn fresh(&mut self, tiles: &[Tile]) -> Vec<TileRows<'_, Accumulator>> {
        tile_rows::split(&mut self.pixels, self.area, tiles)
    }

    /// The band's first batches once the tiles have written theirs, with their ray counts
    /// (`results`); `Cancelled` if a tile is missing.
    pub(super) fn finish(self, results: Vec<Option<RayCounts>>) -> Result<FirstBatches, Cancelled> {
        let mut out = self;
        for counts in results {
            out.counts.add(&counts.ok_or(Cancelled)?);
        }
        let summaries = out.pixels.iter().map(FirstBatchSummary::of);
        out.summaries.extend(summaries);
        Ok(out)
    }

    pub(super) fn at(&self, x: u32, y: u32) -> Option<&Accumulator> {
        self.index(x, y).and_then(|i| self.pixels.get(i))
    }

    /// Where (`x`, `y`) is in `pixels` and `summaries`; `None` outside `area`.
    fn index(&self, x: u32, y: u32) -> Option<usize> {
        let a = &self.area;
        if x < a.x0 || x >= a.x1 || y < a.y0 || y >= a.y1 {
            return None;
        }
        Some((y - a.y0) as usize * a.width() as usize + (x - a.x0) as usize)
    }

    /// The summaries of the block within [`early_stop::RADIUS`] of (`x`, `y`) that lie in
    /// `area`, row by row, each with its offset from (`x`, `y`). A block inside the area (every
    /// pixel's but at the area's border) is read at fixed offsets from its centre, without a
    /// test per pixel: the same summaries in the same order.
    fn block(&self, x: u32, y: u32) -> impl Iterator<Item = (i64, i64, &FirstBatchSummary)> {
        let r = early_stop::RADIUS;
        let a = &self.area;
        let inside = x >= a.x0 + r && x + r < a.x1 && y >= a.y0 + r && y + r < a.y1;
        let mut block = [None; BLOCK_PIXELS];
        let (width, centre) = (a.width() as i64, self.index(x, y));
        for (k, slot) in block.iter_mut().enumerate() {
            let (dx, dy) = (
                (k % BLOCK_SIDE) as i64 - r as i64,
                (k / BLOCK_SIDE) as i64 - r as i64,
            );
            let index = match (inside, centre) {
                (true, Some(centre)) => usize::try_from(centre as i64 + dy * width + dx).ok(),
                _ => self.neighbour_index(x, y, dx, dy),
            };
            *slot = index
                .and_then(|i| self.summaries.get(i))
                .map(|summary| (dx, dy, summary));
        }
        block.into_iter().flatten()
    }

    /// The block around (`x`, `y`) as [`FirstBatches::block`] gives it, when it lies wholly
    /// inside `area` (every pixel's but at the area's border): the summaries row by row at
    /// their offsets, as an array, without the per-pixel `Option`s and offsets of the general
    /// walk. What a pixel's early stop reads nearly always (`render::Job::decide`): once per
    /// pixel, where the general walk was a tenth of an adaptive 10% render's bookkeeping.
    fn interior_block(&self, x: u32, y: u32) -> Option<[&FirstBatchSummary; BLOCK_PIXELS]> {
        let r = early_stop::RADIUS;
        let a = &self.area;
        if !(x >= a.x0 + r && x + r < a.x1 && y >= a.y0 + r && y + r < a.y1) {
            return None;
        }
        let width = a.width() as usize;
        let corner = (y - r - a.y0) as usize * width + (x - r - a.x0) as usize;
        let row = |k: usize| -> Option<&[FirstBatchSummary; BLOCK_SIDE]> {
            let start = corner + k * width;
            self.summaries
                .get(start..start + BLOCK_SIDE)?
                .try_into()
                .ok()
        };
        let rows: [&[FirstBatchSummary; BLOCK_SIDE]; BLOCK_SIDE] = [row(0)?, row(1)?, row(2)?];
        Some(std::array::from_fn(|k| {
            &rows[k / BLOCK_SIDE][k % BLOCK_SIDE]
        }))
    }

    /// Where the pixel at (`dx`, `dy`) from (`x`, `y`) is in `summaries`; `None` outside `area`.
    fn neighbour_index(&self, x: u32, y: u32, dx: i64, dy: i64) -> Option<usize> {
        let nx = u32::try_from(i64::from(x) + dx).ok()?;
        let ny = u32::try_from(i64::from(y) + dy).ok()?;
        self.index(nx, ny)
    }

    /// What the neighbours of (`x`, `y`) within [`early_stop::RADIUS`] say, in a fixed order.
    pub(super) fn prior(&self, x: u32, y: u32) -> NeighbourPrior {
        if let Some(block) = self.interior_block(x, y) {
            let neighbours = block.iter().enumerate().filter(|&(k, _)| k != CENTRE);
            return NeighbourPrior::pool_summaries(neighbours.map(|(_, &s)| *s));
        }
        let neighbours = self
            .block(x, y)
            .filter(|&(dx, dy, _)| (dx, dy) != (0, 0))
            .map(|(_, _, summary)| *summary);
        NeighbourPrior::pool_summaries(neighbours)
    }

    /// The samples of the first batches of the neighbours of (`x`, `y`) within
    /// [`early_stop::RADIUS`]: [`FirstBatches::prior`]'s count, without its pooling.
    pub(super) fn neighbour_samples(&self, x: u32, y: u32) -> u32 {
        if let Some(block) = self.interior_block(x, y) {
            let neighbours = block.iter().enumerate().filter(|&(k, _)| k != CENTRE);
            return neighbours.map(|(_, s)| s.samples).sum();
        }
        self.block(x, y)
            .filter(|&(dx, dy, _)| (dx, dy) != (0, 0))
            .map(|(_, _, summary)| summary.samples)
            .sum()
    }

    /// The scatter of the first-batch means over the block around (`x`, `y`), its own
    /// included ([`FirstBatchSpread`]).
    pub(super) fn spread(&self, x: u32, y: u32) -> FirstBatchSpread {
        if let Some(block) = self.interior_block(x, y) {
            return FirstBatchSpread::fit_whole_block(block.map(|s| s.mean_luminance));
        }
        let block = self
            .block(x, y)
            .map(|(dx, dy, summary)| (dx as f64, dy as f64, summary.mean_luminance));
        FirstBatchSpread::fit(block)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A 5×4 area at (10, 20), one tile, each pixel's first batch a different pair of values
    /// (one black pixel, which says nothing about relative spread).
    fn batches() -> FirstBatches {
        let area = PixelWindow {
            x0: 10,
            y0: 20,
            x1: 15,
            y1: 24,
        };
        let tile = Tile {
            x0: 10,
            y0: 20,
            x1: 15,
            y1: 24,
        };
        let pixels = (0..20)
            .map(|k| {
                let mut acc = Accumulator::default();
                let v = if k == 7 { 0.0 } else { 0.1 + 0.37 * k as f32 };
                acc.add_replicate(Vec3::splat(v), None);
                acc.add_replicate(Vec3::splat(v * (1.0 + 0.1 * (k % 3) as f32)), None);
                acc
            })
            .collect();
        let pixels: Vec<Accumulator> = pixels;
        let mut first = FirstBatches::start(area, None, None);
        let mut fresh = first.fresh(&[tile]);
        for (k, acc) in pixels.into_iter().enumerate() {
            let (x, y) = (tile.x0 + k as u32 % 5, tile.y0 + k as u32 / 5);
            *fresh[0].at(x, y).expect("in the tile") = acc;
        }
        drop(fresh);
        first
            .finish(vec![Some(RayCounts::default())])
            .expect("every tile is there")
    }

    #[test]
    fn the_summaries_say_what_the_neighbours_accumulators_say() {
        let first = batches();
        // Interior, edge and corner pixels of the area, and one outside it.
        for (x, y) in [(11, 21), (13, 22), (10, 20), (14, 23), (12, 20), (15, 24)] {
            let offsets = (-1i64..=1).flat_map(|dy| (-1i64..=1).map(move |dx| (dx, dy)));
            let at = |dx: i64, dy: i64| first.at((x as i64 + dx) as u32, (y as i64 + dy) as u32);
            let neighbours = offsets
                .clone()
                .filter(|&o| o != (0, 0))
                .filter_map(|(dx, dy)| at(dx, dy));
            assert_eq!(
                first.prior(x, y),
                NeighbourPrior::pool(neighbours),
                "({x}, {y})"
            );
            let block = offsets
                .filter_map(|(dx, dy)| Some((dx as f64, dy as f64, at(dx, dy)?.mean_luminance())));
            assert_eq!(
                first.neighbour_samples(x, y),
                first.prior(x, y).samples(),
                "({x}, {y})"
            );
            assert_eq!(
                first.spread(x, y),
                FirstBatchSpread::fit(block),
                "({x}, {y})"
            );
        }
        // A block with samples in it says something (the test is not vacuous).
        assert_ne!(first.prior(12, 22), NeighbourPrior::default());
        assert_ne!(first.spread(12, 22), FirstBatchSpread::default());
    }
}
