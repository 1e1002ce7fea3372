//! Asset decoding for material textures: image bytes (read through a `Loader`) → linear RGBA
//! texels, for `texture wood = image("wood.png") { encoding srgb | data }`.
//!
//! Formats: PNG, JPEG, Radiance `.hdr` and OpenEXR through the `image` crate, recognised from
//! the bytes (not the extension); 8- and 16-bit integer and 32-bit float samples; grey,
//! grey+alpha, RGB and RGBA (grey is copied to R, G and B; a missing alpha is 1).
//! Colour textures (`encoding srgb`, the default) have integer samples sRGB-decoded to linear;
//! float images are already linear. Data textures (`encoding data`: normal maps, masks) are
//! read raw (integers scaled to [0, 1]). Alpha is never sRGB-decoded. Non-finite float samples
//! become 0.
//!
//! Dimensions are checked *before* decoding against [`MAX_TEXTURE_SIDE`]: a texture larger than
//! 8192 × 8192 texels (1 GiB as f32 RGBA, plus a third for its mip pyramid) is rejected.
//! Nothing here panics on bad bytes: every problem is an [`ImageError`].

use glam::Vec4;
use image::DynamicImage;

use super::hdr_image::decode_checked;
pub use super::hdr_image::ImageError;

/// The largest accepted width and height of a texture.
pub const MAX_TEXTURE_SIDE: u32 = 8192;

/// A decoded texture: `width × height` RGBA texels, row 0 at the top of the image.
#[derive(Debug, Clone)]
pub struct TexelImage {
    /// Width in texels (1..=[`MAX_TEXTURE_SIDE`]).
    pub width: u32,
    /// Height in texels (1..=[`MAX_TEXTURE_SIDE`]).
    pub height: u32,
    /// `width · height` texels, row-major from the top row; RGB linear when decoded with
    /// `srgb`, raw otherwise; alpha always raw.
    pub texels: Vec<Vec4>,
}

/// Decodes `bytes` (PNG, JPEG, HDR, EXR); `srgb` decodes integer colour samples to linear.
pub fn decode_texture(bytes: &[u8], srgb: bool) -> Result<TexelImage, ImageError> {
    let image = decode_checked(
        bytes,
        "not a PNG, JPEG, Radiance .hdr or OpenEXR image",
        (MAX_TEXTURE_SIDE, MAX_TEXTURE_SIDE),
    )?;
    let (width, height) = (image.width(), image.height());
    let texels = match image {
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_) => image
            .into_rgba32f()
            .pixels()
            .map(|p| Vec4::from_array(p.0.map(|c| if c.is_finite() { c } else { 0.0 })))
            .collect(),
        DynamicImage::ImageLuma8(_)
        | DynamicImage::ImageLumaA8(_)
        | DynamicImage::ImageRgb8(_)
        | DynamicImage::ImageRgba8(_) => {
            let lut: [f32; 256] = std::array::from_fn(|i| {
                let c = i as f32 / 255.0;
                if srgb {
                    srgb_to_linear(c)
                } else {
                    c
                }
            });
            image
                .into_rgba8()
                .pixels()
                .map(|p| {
                    let [r, g, b, a] = p.0;
                    Vec4::new(
                        lut[r as usize],
                        lut[g as usize],
                        lut[b as usize],
                        a as f32 / 255.0,
                    )
                })
                .collect()
        }
        _ => image
            .into_rgba32f()
            .pixels()
            .map(|p| {
                let [r, g, b, a] = p.0;
                let d = |c: f32| if srgb { srgb_to_linear(c) } else { c };
                Vec4::new(d(r), d(g), d(b), a)
            })
            .collect(),
    };
    Ok(TexelImage {
        width,
        height,
        texels,
    })
}

/// The sRGB transfer function, inverted (IEC 61966-2-1).
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageFormat, Luma, LumaA, Rgb, Rgba};
    use std::io::Cursor;

    fn encode(img: DynamicImage, format: ImageFormat) -> Vec<u8> {
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, format).expect("encodes");
        out.into_inner()
    }

    #[test]
    fn eight_bit_colour_is_srgb_decoded_and_data_is_raw() {
        let img = DynamicImage::ImageRgb8(image::RgbImage::from_pixel(2, 1, Rgb([128, 0, 255])));
        let png = encode(img, ImageFormat::Png);
        let colour = decode_texture(&png, true).expect("decodes");
        assert!((colour.texels[0].x - 0.2158605).abs() < 1e-5);
        assert_eq!(colour.texels[0].w, 1.0);
        let data = decode_texture(&png, false).expect("decodes");
        assert!((data.texels[0].x - 128.0 / 255.0).abs() < 1e-6);
        assert_eq!(data.texels[1].z, 1.0);
    }

    #[test]
    fn grey_alpha_sixteen_bit_and_float_layouts() {
        let ga =
            DynamicImage::ImageLumaA8(image::GrayAlphaImage::from_pixel(1, 1, LumaA([255, 51])));
        let t = decode_texture(&encode(ga, ImageFormat::Png), true).expect("decodes");
        assert_eq!(t.texels[0], Vec4::new(1.0, 1.0, 1.0, 0.2));
        let g16 = DynamicImage::ImageLuma16(image::ImageBuffer::from_pixel(1, 1, Luma([65535u16])));
        let t = decode_texture(&encode(g16, ImageFormat::Png), false).expect("decodes");
        assert_eq!(t.texels[0], Vec4::ONE);
        let rgba16 = DynamicImage::ImageRgba16(image::ImageBuffer::from_pixel(
            1,
            1,
            Rgba([0u16, 32768, 65535, 65535]),
        ));
        let t = decode_texture(&encode(rgba16, ImageFormat::Png), true).expect("decodes");
        assert!((t.texels[0].y - srgb_to_linear(32768.0 / 65535.0)).abs() < 1e-6);
        let f = DynamicImage::ImageRgb32F(image::ImageBuffer::from_pixel(
            1,
            1,
            Rgb([2.5f32, 0.5, 0.0]),
        ));
        let t = decode_texture(&encode(f, ImageFormat::OpenExr), true).expect("decodes");
        assert_eq!(t.texels[0], Vec4::new(2.5, 0.5, 0.0, 1.0));
    }

    #[test]
    fn jpeg_and_radiance_hdr_decode() {
        let img = DynamicImage::ImageRgb8(image::RgbImage::from_pixel(8, 8, Rgb([200, 100, 50])));
        let t = decode_texture(&encode(img, ImageFormat::Jpeg), false).expect("decodes");
        assert_eq!((t.width, t.height, t.texels.len()), (8, 8, 64));
        assert!(
            (t.texels[0].x - 200.0 / 255.0).abs() < 0.03,
            "{}",
            t.texels[0]
        );
        let hdr = DynamicImage::ImageRgb32F(image::ImageBuffer::from_pixel(
            2,
            2,
            Rgb([4.0f32, 1.0, 0.25]),
        ));
        let t = decode_texture(&encode(hdr, ImageFormat::Hdr), true).expect("decodes");
        assert!(
            (t.texels[3] - Vec4::new(4.0, 1.0, 0.25, 1.0))
                .abs()
                .max_element()
                < 0.05
        );
    }

    #[test]
    fn garbage_truncated_and_oversized_are_errors() {
        assert!(matches!(
            decode_texture(b"hello", true),
            Err(ImageError::Corrupt(_))
        ));
        let img = DynamicImage::ImageRgb8(image::RgbImage::from_pixel(8, 8, Rgb([9, 9, 9])));
        let png = encode(img, ImageFormat::Png);
        let cut = &png[..png.len() / 2];
        assert!(matches!(
            decode_texture(cut, true),
            Err(ImageError::Corrupt(_))
        ));
        assert!(matches!(
            decode_texture(&png_header(9000, 4), true),
            Err(ImageError::TooLarge {
                width: 9000,
                height: 4
            })
        ));
        assert!(matches!(
            decode_texture(&png_header(0, 4), true),
            Err(ImageError::Corrupt(_))
        ));
    }

    /// A PNG signature, an IHDR chunk claiming `w × h` and an empty IDAT (no image data).
    pub(crate) fn png_header(w: u32, h: u32) -> Vec<u8> {
        let mut ihdr = Vec::new();
        ihdr.extend(w.to_be_bytes());
        ihdr.extend(h.to_be_bytes());
        ihdr.extend([8, 2, 0, 0, 0]);
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        chunk(&mut out, b"IHDR", &ihdr);
        chunk(&mut out, b"IDAT", &[]);
        chunk(&mut out, b"IEND", &[]);
        out
    }

    fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
        out.extend((data.len() as u32).to_be_bytes());
        let mut body = kind.to_vec();
        body.extend(data);
        let crc = crc32(&body);
        out.extend(body);
        out.extend(crc.to_be_bytes());
    }

    fn crc32(bytes: &[u8]) -> u32 {
        let mut c = 0xffff_ffffu32;
        for &b in bytes {
            c ^= b as u32;
            for _ in 0..8 {
                c = if c & 1 != 0 {
                    0xedb8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
        }
        !c
    }
}
