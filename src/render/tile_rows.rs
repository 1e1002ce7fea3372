//! Stage 4, render: a band buffer's rows cut into each tile's pieces, so that the tiles of an
//! adaptive render's first two passes (`render::first_pass`, `render::second_pass`) write their
//! pixels straight into the band's buffer, side by side on the worker threads, in safe code
//! (each tile holds its own disjoint `&mut` rows). Before, each tile filled a vector of its
//! own that the band then copied in: an allocation per tile and pass, and the page faults of
//! memory the allocator had given back (about 40% of an adaptive render's faults, against a
//! fixed-count render's 0: docs/quality.md, fourteenth session).
//!
//! Syntax: none of its own; `render { noise 0.05 }` / `--noise 0.05` renders this way.

use super::{PixelWindow, Tile};

/// One tile's rows of a band buffer, top to bottom, each `x1 − x0` long.
pub(super) struct TileRows<'b, T> {
    tile: Tile,
    rows: Vec<&'b mut [T]>,
}

impl<T> TileRows<'_, T> {
    /// The tile's pixel (`x`, `y`), in image coordinates; `None` outside the tile.
    pub(super) fn at(&mut self, x: u32, y: u32) -> Option<&mut T> {
        let t = self.tile;
        if x < t.x0 || y < t.y0 {
            return None;
        }
        let row = self.rows.get_mut((y - t.y0) as usize)?;
        row.get_mut((x - t.x0) as usize)
    }
}

/// `buffer` (row-major over `area`) cut into the pieces of `tiles`: one [`TileRows`] per tile,
/// in their order. The tiles lie inside `area`, do not overlap, and those that share a row
/// come in increasing `x` (as `render::tiles` makes them).
pub(super) fn split<'b, T>(
    buffer: &'b mut [T],
    area: PixelWindow,
    tiles: &[Tile],
) -> Vec<TileRows<'b, T>> {
    let width = area.width() as usize;
    let mut out: Vec<TileRows<'b, T>> = tiles
        .iter()
        .map(|&tile| TileRows {
            tile,
            rows: Vec::with_capacity((tile.y1 - tile.y0) as usize),
        })
        .collect();
    for (y, mut row) in (area.y0..).zip(buffer.chunks_mut(width.max(1))) {
        // The x of `row`'s first element.
        let mut at = area.x0;
        for (k, t) in tiles.iter().enumerate() {
            if y < t.y0 || y >= t.y1 {
                continue;
            }
            debug_assert!(t.x0 >= at && t.x1 >= t.x0, "tiles overlap or go backwards");
            let rest = std::mem::take(&mut row);
            let (_, rest) = rest.split_at_mut((t.x0 - at) as usize);
            let (piece, rest) = rest.split_at_mut((t.x1 - t.x0) as usize);
            if let Some(tile) = out.get_mut(k) {
                tile.rows.push(piece);
            }
            (row, at) = (rest, t.x1);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every tile's pixel written through its rows lands where the row-major index says, and
    /// the pixels outside the tiles (rows kept from the band before) are untouched.
    #[test]
    fn tiles_write_where_the_row_major_index_says() {
        let area = PixelWindow {
            x0: 3,
            y0: 5,
            x1: 40,
            y1: 30,
        };
        let fresh = PixelWindow { y0: 9, ..area };
        let tiles = super::super::tiles(fresh);
        let width = area.width() as usize;
        let mut buffer = vec![(0u32, 0u32); width * area.height() as usize];
        let mut rows = split(&mut buffer, area, &tiles);
        for (rows, tile) in rows.iter_mut().zip(&tiles) {
            for y in tile.y0..tile.y1 {
                for x in tile.x0..tile.x1 {
                    *rows.at(x, y).expect("inside the tile") = (x, y);
                }
            }
            assert!(rows.at(tile.x1, tile.y0).is_none());
            assert!(rows.at(tile.x0, tile.y1).is_none());
        }
        for y in area.y0..area.y1 {
            for x in area.x0..area.x1 {
                let i = (y - area.y0) as usize * width + (x - area.x0) as usize;
                let want = if y >= fresh.y0 { (x, y) } else { (0, 0) };
                assert_eq!(buffer[i], want, "({x}, {y})");
            }
        }
    }
}
