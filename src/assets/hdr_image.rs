//! Asset decoding: image bytes (read through a `Loader`) → linear float RGB, for environment
//! maps (`light sky = environment { image("sky.hdr") }`).
//!
//! Formats: Radiance `.hdr` and OpenEXR through the `image` crate, PFM by hand (`PF` colour or
//! `Pf` grey; bottom row first; a negative scale means little-endian), and PNG/JPEG decoded as
//! sRGB and linearised. RGBE mantissas are centred as Radiance's own reader does (see
//! [`centre_rgbe_mantissa`]); every other format's samples already stand for the centre of their
//! quantisation step (8/16-bit integers are rounded by their writers, EXR half and float are exact). The format is recognised from the bytes, not the extension. Rows are
//! returned top first. Nothing here panics on bad bytes: every problem is an [`ImageError`].
//! Dimensions are checked against [`MAX_WIDTH`] × [`MAX_HEIGHT`] *before* decoding.

use std::io::Cursor;

use glam::Vec3;
use image::{DynamicImage, ImageFormat, ImageReader};

/// The widest map accepted: 16384 (with [`MAX_HEIGHT`], 1.6 GB of f32 RGB; larger maps are
/// better downsampled, since the renderer looks texels up without filtering).
pub const MAX_WIDTH: u32 = 16384;
/// The tallest map accepted: 8192 (an equirectangular map is twice as wide as it is tall).
pub const MAX_HEIGHT: u32 = 8192;

/// A decoded image: `width × height` linear RGB values, row 0 at the top.
#[derive(Debug, Clone)]
pub struct FloatImage {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` linear RGB values, row by row from the top.
    pub pixels: Vec<Vec3>,
}

/// Why image bytes could not be decoded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImageError {
    /// Not an image of a known format, truncated, or inconsistent.
    #[error("{0}")]
    Corrupt(String),
    /// The header announces more pixels than the limit allows (nothing was allocated).
    #[error("{width} × {height} is larger than the {MAX_WIDTH} × {MAX_HEIGHT} limit")]
    TooLarge {
        /// The width the header announces.
        width: u32,
        /// The height the header announces.
        height: u32,
    },
}

/// Decodes `bytes` as PFM, Radiance HDR, OpenEXR, PNG or JPEG.
pub fn decode_float_image(bytes: &[u8]) -> Result<FloatImage, ImageError> {
    if bytes.starts_with(b"PF") || bytes.starts_with(b"Pf") {
        return decode_pfm(bytes);
    }
    let image = decode_checked(
        bytes,
        "not a Radiance .hdr, OpenEXR, PFM, PNG or JPEG image",
        (MAX_WIDTH, MAX_HEIGHT),
    )?;
    let (width, height) = (image.width(), image.height());
    let linear = matches!(
        image,
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_)
    );
    let rgb = image.into_rgb32f();
    let pixels = rgb
        .pixels()
        .map(|p| {
            let c = Vec3::from_array(p.0);
            if linear {
                c
            } else {
                Vec3::new(
                    srgb_to_linear(c.x),
                    srgb_to_linear(c.y),
                    srgb_to_linear(c.z),
                )
            }
        })
        .collect();
    Ok(FloatImage {
        width,
        height,
        pixels,
    })
}

/// Decodes `bytes` with the `image` crate (format recognised from the bytes), after reading only
/// the header to reject an unknown format (`not_an_image`), an empty image or one larger than
/// `max` (width, height): an absurd header never allocates its pixels.
pub(crate) fn decode_checked(
    bytes: &[u8],
    not_an_image: &str,
    max: (u32, u32),
) -> Result<DynamicImage, ImageError> {
    let reader = || {
        ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| ImageError::Corrupt(e.to_string()))
    };
    let probe = reader()?;
    if probe.format().is_none() {
        return Err(ImageError::Corrupt(not_an_image.into()));
    }
    let (width, height) = probe
        .into_dimensions()
        .map_err(|e| ImageError::Corrupt(e.to_string()))?;
    check_size(width, height, max)?;
    let mut full = reader()?;
    let rgbe = full.format() == Some(ImageFormat::Hdr);
    full.no_limits();
    let mut image = full
        .decode()
        .map_err(|e| ImageError::Corrupt(e.to_string()))?;
    if rgbe {
        if let DynamicImage::ImageRgb32F(rgb) = &mut image {
            for p in rgb.pixels_mut() {
                p.0 = centre_rgbe_mantissa(Vec3::from_array(p.0)).to_array();
            }
        }
    }
    Ok(image)
}

/// Moves an RGBE pixel decoded as `m · 2^(e−136)` (the `image` crate's reading) to the centre of
/// its quantisation step, `(m + ½) · 2^(e−136)`, as Radiance's `colr_color` reads it: writers
/// (Radiance's `setcolr`, the `image` crate, the benchmark's `gen.py`) truncate, so the plain
/// reading is biased dark by half a step, 0.2–0.4% on a typical sky.
///
/// The crate's floats are exact, and writers normalise (the largest mantissa is in 128..=255),
/// so the step `2^(e−136)` is the largest channel's power of two divided by 128. A black pixel
/// (`e = 0`) stays black; so do subnormal results (`e` ≤ 9, below 1e-38), where the step cannot
/// be read back from the float.
pub fn centre_rgbe_mantissa(rgb: Vec3) -> Vec3 {
    let max = rgb.max_element();
    if !max.is_normal() || max < 0.0 {
        return rgb;
    }
    // 2^⌊log2 max⌋: the float with max's exponent bits and a zero mantissa.
    let power = f32::from_bits(max.to_bits() & 0x7f80_0000);
    rgb + Vec3::splat(power / 256.0)
}

fn check_size(
    width: u32,
    height: u32,
    (max_width, max_height): (u32, u32),
) -> Result<(), ImageError> {
    if width > max_width || height > max_height {
        return Err(ImageError::TooLarge { width, height });
    }
    if width == 0 || height == 0 {
        return Err(ImageError::Corrupt(format!(
            "the image is empty ({width} × {height})"
        )));
    }
    Ok(())
}

fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// PFM: `PF\n<w> <h>\n<scale>\n` then `h` rows of `w` pixels (3 or 1 f32 each), bottom row first.
fn decode_pfm(bytes: &[u8]) -> Result<FloatImage, ImageError> {
    let bad = |what: &str| ImageError::Corrupt(format!("PFM: {what}"));
    let channels = if bytes.starts_with(b"PF") { 3 } else { 1 };
    // Three whitespace-separated header tokens after the magic, then one whitespace byte.
    let mut pos = 2;
    let mut tokens = Vec::with_capacity(3);
    for _ in 0..3 {
        while bytes.get(pos).is_some_and(u8::is_ascii_whitespace) {
            pos += 1;
        }
        let start = pos;
        while bytes.get(pos).is_some_and(|b| !b.is_ascii_whitespace()) {
            pos += 1;
        }
        let token = std::str::from_utf8(&bytes[start..pos]).map_err(|_| bad("bad header"))?;
        tokens.push(token);
    }
    pos += 1; // the single whitespace byte before the data
    let parse_dim = |t: &str| t.parse::<u32>().map_err(|_| bad("bad width or height"));
    let (width, height) = (parse_dim(tokens[0])?, parse_dim(tokens[1])?);
    let scale: f32 = tokens[2].parse().map_err(|_| bad("bad scale"))?;
    if scale == 0.0 || !scale.is_finite() {
        return Err(bad("the scale must be a non-zero number"));
    }
    check_size(width, height, (MAX_WIDTH, MAX_HEIGHT))?;
    let (w, h) = (width as usize, height as usize);
    let data = bytes.get(pos..).ok_or_else(|| bad("truncated"))?;
    let needed = w * h * channels * 4;
    if data.len() < needed {
        return Err(bad(&format!(
            "truncated: {} bytes of pixel data, {needed} expected",
            data.len()
        )));
    }
    let little = scale < 0.0;
    let value = |i: usize| {
        let b = [
            data[4 * i],
            data[4 * i + 1],
            data[4 * i + 2],
            data[4 * i + 3],
        ];
        if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut pixels = Vec::with_capacity(w * h);
    for row in 0..h {
        let file_row = h - 1 - row;
        for col in 0..w {
            let i = (file_row * w + col) * channels;
            pixels.push(if channels == 3 {
                Vec3::new(value(i), value(i + 1), value(i + 2))
            } else {
                Vec3::splat(value(i))
            });
        }
    }
    Ok(FloatImage {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm(w: u32, h: u32, rows_bottom_first: &[f32]) -> Vec<u8> {
        let mut b = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
        for v in rows_bottom_first {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b
    }

    #[test]
    fn pfm_rows_are_flipped_to_top_first() {
        // 1 × 2: bottom pixel red, top pixel green.
        let bytes = pfm(1, 2, &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let img = decode_float_image(&bytes).expect("valid PFM");
        assert_eq!((img.width, img.height), (1, 2));
        assert_eq!(img.pixels, vec![Vec3::Y, Vec3::X]);
    }

    #[test]
    fn bad_bytes_are_errors_not_panics() {
        for bytes in [
            &b""[..],
            b"PF\n",
            b"PF\n2 2\n-1\n\x00\x00",
            b"PF\nx y\n-1\n",
            b"PF\n1 1\n0\n\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00",
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n\x01",
            b"not an image at all",
        ] {
            assert!(decode_float_image(bytes).is_err(), "{bytes:?}");
        }
        let huge = pfm(MAX_WIDTH + 1, 1, &[]);
        assert_eq!(
            decode_float_image(&huge).err(),
            Some(ImageError::TooLarge {
                width: MAX_WIDTH + 1,
                height: 1
            })
        );
    }

    #[test]
    fn radiance_hdr_decodes_linear() {
        // 2 × 1 flat RGBE: (1, 0.5, 0.25) and (0, 0, 0).
        let mut b = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".to_vec();
        b.extend_from_slice(&[128, 64, 32, 129, 0, 0, 0, 0]);
        let img = decode_float_image(&b).expect("valid HDR");
        assert_eq!((img.width, img.height), (2, 1));
        assert!(
            (img.pixels[0] - Vec3::new(1.0, 0.5, 0.25))
                .abs()
                .max_element()
                < 1e-2
        );
        assert_eq!(img.pixels[1], Vec3::ZERO);
    }

    #[test]
    fn openexr_decodes_linear_and_top_first() {
        let top_first = [1.5f32, 0.25, 0.0, 0.0, 0.0, 7.0];
        let buffer = image::Rgb32FImage::from_raw(1, 2, top_first.to_vec()).expect("1 × 2");
        let mut bytes = Cursor::new(Vec::new());
        DynamicImage::ImageRgb32F(buffer)
            .write_to(&mut bytes, image::ImageFormat::OpenExr)
            .expect("encodes");
        let img = decode_float_image(bytes.get_ref()).expect("valid EXR");
        assert_eq!(
            img.pixels,
            vec![Vec3::new(1.5, 0.25, 0.0), Vec3::new(0.0, 0.0, 7.0)]
        );
    }
}
