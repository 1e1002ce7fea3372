//! Stage 5, film: one tile of `scnc render --tile K/N` as an OpenEXR file, and back.
//!
//! Input: the window's linear radiance ([`Film`] of the window's size) and a [`TileHeader`];
//! output: EXR bytes (and [`decode_tile`] the reverse, for `scnc merge`). The file is a
//! standard scan-line EXR: the display window is the whole image, the data window the tile's
//! pixels, channels R, G, B as 32-bit floats holding the radiance bits exactly as rendered
//! (not clamped, unlike a plain `.exr` output, so that merging loses nothing), ZIP-compressed
//! (lossless). Custom header attributes carry what merging needs:
//!
//! | attribute       | type  | value                                                        |
//! |-----------------|-------|--------------------------------------------------------------|
//! | `scnc:identity` | text  | the scene identity, `scnc-id1-…` (see `ir::identity`)        |
//! | `scnc:tile`     | text  | `K/N`                                                        |
//! | `scnc:exposure` | float | `render { exposure }` (stops), for a PNG made by merging     |
//! | `scnc:tonemap`  | text  | `clamp`, `reinhard` or `filmic`                              |

use std::io::{Cursor, Write};
use std::path::Path;

use exr::meta::attribute::{AttributeValue, IntegerBounds, Text};
use exr::prelude::*;
// The prelude brings its own `Result`; this module returns the standard one.
use glam::Vec3;
use std::result::Result;

use super::{write_atomic_with, Durability, Film, WriteError, WriteSettings};
use crate::ir::identity::Identity;
use crate::ir::ToneMap;
use crate::render::PixelWindow;

/// What a tile file says about itself besides its pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TileHeader {
    /// The scene and settings it was rendered from.
    pub identity: Identity,
    /// Its index `K` of `N`.
    pub index: u32,
    /// `N`.
    pub count: u32,
    /// Full image width (the display window).
    pub width: u32,
    /// Full image height.
    pub height: u32,
    /// Exposure and tone map for 8-bit output.
    pub output: WriteSettings,
}

/// A decoded tile: its header, its window and the window's radiance.
#[derive(Debug, Clone)]
pub struct Tile {
    /// What it says about itself.
    pub header: TileHeader,
    /// Its pixels' place in the image (the data window).
    pub window: PixelWindow,
    /// The window's radiance, `window.width()`×`window.height()`.
    pub film: Film,
}

/// Largest side of an image scnc renders (as `--resolution` and the scene language allow).
const MAX_SIDE: u32 = 16384;

const IDENTITY: &str = "scnc:identity";
const INDEX: &str = "scnc:tile";
const EXPOSURE: &str = "scnc:exposure";
const TONEMAP: &str = "scnc:tonemap";

fn tonemap_name(t: ToneMap) -> &'static str {
    match t {
        ToneMap::Clamp => "clamp",
        ToneMap::Reinhard => "reinhard",
        ToneMap::Filmic => "filmic",
    }
}

fn tonemap_from(name: &str) -> Option<ToneMap> {
    [ToneMap::Clamp, ToneMap::Reinhard, ToneMap::Filmic]
        .into_iter()
        .find(|t| tonemap_name(*t) == name)
}

/// The tile's EXR bytes: `film` holds `window`'s pixels.
pub fn encode_tile(
    film: &Film,
    window: PixelWindow,
    header: &TileHeader,
) -> Result<Vec<u8>, String> {
    if (film.width(), film.height()) != (window.width(), window.height()) || film.width() == 0 {
        return Err(format!(
            "a {}x{} film for a {}x{} window",
            film.width(),
            film.height(),
            window.width(),
            window.height()
        ));
    }
    let pixels = |p: Vec2<usize>| {
        let c = film.get(p.x() as u32, p.y() as u32);
        (c.x, c.y, c.z)
    };
    let attributes = LayerAttributes {
        layer_position: Vec2(window.x0 as i32, window.y0 as i32),
        ..LayerAttributes::default()
    };
    let mut layer = Layer::new(
        (window.width() as usize, window.height() as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        SpecificChannels::rgb(pixels),
    );
    let other = &mut layer.attributes.other;
    let text = |s: &str| AttributeValue::Text(Text::from(s));
    other.insert(Text::from(IDENTITY), text(&header.identity.to_string()));
    other.insert(
        Text::from(INDEX),
        text(&format!("{}/{}", header.index, header.count)),
    );
    other.insert(
        Text::from(EXPOSURE),
        AttributeValue::F32(header.output.exposure),
    );
    other.insert(
        Text::from(TONEMAP),
        text(tonemap_name(header.output.tonemap)),
    );
    let mut image = Image::from_layer(layer);
    image.attributes.display_window =
        IntegerBounds::new((0, 0), (header.width as usize, header.height as usize));
    let mut out = Cursor::new(Vec::new());
    image
        .write()
        .non_parallel()
        .to_buffered(&mut out)
        .map_err(|e| e.to_string())?;
    // The crate writes the custom attributes in a hash map's random order: sorted, the same
    // tile is the same bytes on every run.
    let mut bytes = out.into_inner();
    super::exr_header::sort_attributes(&mut bytes).map_err(str::to_string)?;
    Ok(bytes)
}

/// Encodes a tile ([`encode_tile`]) and writes it to `path` atomically, as every output.
pub fn write_tile(
    film: &Film,
    window: PixelWindow,
    header: &TileHeader,
    path: &Path,
) -> Result<(), WriteError> {
    let bytes = encode_tile(film, window, header).map_err(|message| WriteError::Encode {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomic_with(path, Durability::Synced, |f| f.write_all(&bytes)).map_err(|source| {
        WriteError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Why a file is not a tile scnc can merge.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TileError {
    /// Not a readable EXR (truncated, corrupt, or another format).
    #[error("not a readable OpenEXR file ({0})")]
    Unreadable(String),
    /// A readable EXR without scnc's attributes.
    #[error("an OpenEXR file without scnc's tile attributes (`{0}` missing or malformed)")]
    NotATile(&'static str),
}

/// Reads a tile written by [`encode_tile`].
pub fn decode_tile(bytes: &[u8]) -> Result<Tile, TileError> {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| Film::new(size.width() as u32, size.height() as u32),
            |film: &mut Film, p: Vec2<usize>, (r, g, b): (f32, f32, f32)| {
                film.set(p.x() as u32, p.y() as u32, Vec3::new(r, g, b));
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| TileError::Unreadable(e.to_string()))?;
    // A single-part file has one header: exr reads custom attributes into the layer's.
    let other = &image.layer_data.attributes.other;
    let text = |key: &'static str| match other.get(&Text::from(key)) {
        Some(AttributeValue::Text(t)) => Ok(t.to_string()),
        _ => Err(TileError::NotATile(key)),
    };
    let identity = Identity::parse(&text(IDENTITY)?).ok_or(TileError::NotATile(IDENTITY))?;
    let (index, count) = parse_index(&text(INDEX)?).ok_or(TileError::NotATile(INDEX))?;
    let tonemap = tonemap_from(&text(TONEMAP)?).ok_or(TileError::NotATile(TONEMAP))?;
    let exposure = match other.get(&Text::from(EXPOSURE)) {
        Some(AttributeValue::F32(e)) => *e,
        _ => return Err(TileError::NotATile(EXPOSURE)),
    };
    let display = image.attributes.display_window;
    let layer = &image.layer_data;
    let origin = layer.attributes.layer_position;
    let size = layer.size;
    let bad_window = TileError::NotATile("data window");
    if display.position != Vec2(0, 0) || origin.x() < 0 || origin.y() < 0 {
        return Err(bad_window);
    }
    // Sides are bounded as `--resolution` bounds them, so a corrupt header cannot make
    // `scnc merge` allocate an absurd image.
    let side = |v: usize| u32::try_from(v).ok().filter(|v| *v <= MAX_SIDE);
    let (Some(width), Some(height)) = (side(display.size.width()), side(display.size.height()))
    else {
        return Err(bad_window);
    };
    let (x0, y0) = (origin.x() as u32, origin.y() as u32);
    let (Some(x1), Some(y1)) = (
        side(size.width()).and_then(|w| x0.checked_add(w)),
        side(size.height()).and_then(|h| y0.checked_add(h)),
    ) else {
        return Err(bad_window);
    };
    let window = PixelWindow { x0, y0, x1, y1 };
    if window.x1 > width || window.y1 > height {
        return Err(bad_window);
    }
    let header = TileHeader {
        identity,
        index,
        count,
        width,
        height,
        output: WriteSettings { exposure, tonemap },
    };
    Ok(Tile {
        header,
        window,
        film: layer.channel_data.pixels.clone(),
    })
}

fn parse_index(text: &str) -> Option<(u32, u32)> {
    let (k, n) = text.split_once('/')?;
    let (k, n) = (k.parse().ok()?, n.parse().ok()?);
    (k < n).then_some((k, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> TileHeader {
        TileHeader {
            identity: Identity(0x1234),
            index: 1,
            count: 3,
            width: 5,
            height: 9,
            output: WriteSettings {
                exposure: -0.5,
                tonemap: ToneMap::Filmic,
            },
        }
    }

    fn sample_tile() -> (Film, PixelWindow) {
        let window = PixelWindow {
            x0: 0,
            y0: 3,
            x1: 5,
            y1: 6,
        };
        let mut film = Film::new(5, 3);
        for y in 0..3 {
            for x in 0..5 {
                film.set(x, y, Vec3::new(x as f32 * 0.1 + 1e-7, y as f32, -1.0));
            }
        }
        film.set(4, 2, Vec3::new(f32::INFINITY, 3.0e38, f32::MIN_POSITIVE));
        (film, window)
    }

    #[test]
    fn round_trips_every_bit_and_the_header() {
        let (film, window) = sample_tile();
        let bytes = encode_tile(&film, window, &header()).expect("encode");
        let tile = decode_tile(&bytes).expect("decode");
        assert_eq!(tile.header, header());
        assert_eq!(tile.window, window);
        let bits = |f: &Film| -> Vec<[u32; 3]> {
            f.pixels()
                .iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&tile.film), bits(&film));
    }

    #[test]
    fn the_same_tile_is_the_same_bytes() {
        // Each encode builds a fresh attribute map with its own random seed.
        let (film, window) = sample_tile();
        let first = encode_tile(&film, window, &header()).expect("encode");
        for _ in 0..8 {
            assert_eq!(
                encode_tile(&film, window, &header()).expect("encode"),
                first
            );
        }
    }

    #[test]
    fn truncated_and_foreign_files_are_refused() {
        let (film, window) = sample_tile();
        let bytes = encode_tile(&film, window, &header()).expect("encode");
        for cut in [0, 8, bytes.len() / 2, bytes.len() - 1] {
            assert!(
                matches!(decode_tile(&bytes[..cut]), Err(TileError::Unreadable(_))),
                "cut at {cut}"
            );
        }
        let plain = crate::film::encode::exr(&Film::new(1, 1)).expect("plain exr");
        assert_eq!(
            decode_tile(&plain).err(),
            Some(TileError::NotATile(IDENTITY))
        );
    }
}
