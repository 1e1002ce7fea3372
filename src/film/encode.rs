//! Stage 5: film → file bytes, one function per format (see the `film` module doc).

use std::io::Cursor;

use image::{ImageEncoder, Rgb};

use super::tonemap::to_srgb8;
use super::write::WriteSettings;
use super::Film;

/// 8-bit sRGB PNG bytes after exposure and tone mapping.
pub fn png(film: &Film, settings: &WriteSettings) -> Result<Vec<u8>, String> {
    let bytes: Vec<u8> = film
        .pixels()
        .iter()
        .flat_map(|&p| to_srgb8(p, settings.exposure, settings.tonemap))
        .collect();
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(
            &bytes,
            film.width(),
            film.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| e.to_string())?;
    Ok(out)
}

fn finite(film: &Film) -> impl Iterator<Item = [f32; 3]> + '_ {
    film.pixels().iter().map(|p| {
        p.to_array()
            .map(|c| if c.is_finite() { c.max(0.0) } else { 0.0 })
    })
}

/// Linear float OpenEXR bytes.
pub fn exr(film: &Film) -> Result<Vec<u8>, String> {
    let floats: Vec<f32> = finite(film).flatten().collect();
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_ne_bytes()).collect();
    let mut out = Cursor::new(Vec::new());
    image::codecs::openexr::OpenExrEncoder::new(&mut out)
        .write_image(
            &bytes,
            film.width(),
            film.height(),
            image::ExtendedColorType::Rgb32F,
        )
        .map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

/// Radiance RGBE (.hdr) bytes.
pub fn hdr(film: &Film) -> Result<Vec<u8>, String> {
    let pixels: Vec<Rgb<f32>> = finite(film).map(Rgb).collect();
    let mut out = Vec::new();
    image::codecs::hdr::HdrEncoder::new(&mut out)
        .encode(&pixels, film.width() as usize, film.height() as usize)
        .map_err(|e| e.to_string())?;
    Ok(out)
}

/// Portable float map: `PF`, size, `-1.0` (negative scale = little-endian), then rows of
/// RGB f32 from the bottom row up.
pub fn pfm(film: &Film) -> Vec<u8> {
    let (w, h) = (film.width(), film.height());
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    out.reserve(w as usize * h as usize * 12);
    for y in (0..h).rev() {
        for x in 0..w {
            for c in film.get(x, y).to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    out
}
