//! Stage 3 assets: every image format decodes to the value its writer meant, with no
//! half-step offset (issue 19). A float original is quantised the way each format's writers
//! do it (RGBE truncates, 8- and 16-bit integers round, EXR half rounds), decoded through
//! `scnc::assets`, and the mean signed error per channel is compared with the quantisation step.

use std::io::Cursor;

use glam::Vec3;
use image::{DynamicImage, ImageFormat};
use scnc::assets::hdr_image::{centre_rgbe_mantissa, decode_float_image};
use scnc::assets::texture_image::{decode_texture, srgb_to_linear};

/// A benchmark-like sky: a smooth blue gradient over 3 decades, values not on any grid.
fn sky(w: u32, h: u32) -> Vec<Vec3> {
    let mut out = Vec::new();
    for j in 0..h {
        for i in 0..w {
            let (u, v) = ((i as f32 + 0.37) / w as f32, (j as f32 + 0.61) / h as f32);
            let up = 1.0 - v;
            let base = Vec3::new(0.25 + 0.35 * up, 0.35 + 0.45 * up, 0.55 + 0.75 * up);
            out.push(base * (1.0 + 40.0 * u * u) * (0.1 + 0.013 * (i * 7 % 11) as f32));
        }
    }
    out
}

/// RGBE as Radiance's `setcolr` and the benchmark's `gen.py` write it: truncated mantissas.
fn rgbe_file(w: u32, h: u32, px: &[Vec3]) -> Vec<u8> {
    let mut b = format!("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n").into_bytes();
    for c in px {
        let m = c.max_element();
        if m < 1e-32 {
            b.extend([0; 4]);
            continue;
        }
        let e = m.log2().floor() as i32 + 1; // m = mant · 2^e, mant in [0.5, 1)
        let s = 256.0 / 2f64.powi(e);
        let q = |x: f32| (x as f64 * s) as u8;
        b.extend([q(c.x), q(c.y), q(c.z), (e + 128) as u8]);
    }
    b
}

/// Mean signed relative error per channel of `decoded` against `original`.
fn mean_relative_error(decoded: &[Vec3], original: &[Vec3]) -> Vec3 {
    let sum: glam::DVec3 = decoded
        .iter()
        .zip(original)
        .map(|(d, o)| ((*d - *o) / *o).as_dvec3())
        .sum();
    (sum / original.len() as f64).as_vec3()
}

#[test]
fn rgbe_reads_radiance_centred_mantissa_exactly() {
    // (128, 64, 32) · 2^(129−136) and black: Radiance reads (m + ½) · 2^(e−136).
    let mut b = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".to_vec();
    b.extend_from_slice(&[128, 64, 32, 129, 0, 0, 0, 0]);
    let img = decode_float_image(&b).expect("valid HDR");
    assert_eq!(img.pixels[0], Vec3::new(128.5, 64.5, 32.5) / 128.0);
    assert_eq!(img.pixels[1], Vec3::ZERO);
    // The same through the texture decoder (RGBE textures are read the same way).
    let t = decode_texture(&b, true).expect("valid HDR");
    assert_eq!(t.texels[0].truncate(), Vec3::new(128.5, 64.5, 32.5) / 128.0);
    assert_eq!(centre_rgbe_mantissa(Vec3::ZERO), Vec3::ZERO);
}

#[test]
fn rgbe_has_no_bias_against_the_float_original() {
    let (w, h) = (64, 32);
    let original = sky(w, h);
    let img = decode_float_image(&rgbe_file(w, h, &original)).expect("valid HDR");
    let centred = mean_relative_error(&img.pixels, &original);
    // The crate's plain reading m · 2^(e−136), undone: half a step darker everywhere.
    let step_down: Vec<Vec3> = img
        .pixels
        .iter()
        .map(|c| *c - (centre_rgbe_mantissa(*c) - *c))
        .collect();
    let plain = mean_relative_error(&step_down, &original);
    println!("RGBE mean relative error: centred {centred:?}, plain m·2^(e−136) {plain:?}");
    // One step is 1/128 … 1/256 of the largest channel: the plain reading is 0.2–0.8% dark.
    assert!(plain.max_element() < -0.002, "{plain}");
    assert!(centred.abs().max_element() < 0.0005, "{centred}");
    // Also what the `image` crate's own RGBE writer (truncating) produces.
    let buffer =
        image::Rgb32FImage::from_raw(w, h, original.iter().flat_map(|c| c.to_array()).collect())
            .expect("w × h");
    let mut bytes = Cursor::new(Vec::new());
    DynamicImage::ImageRgb32F(buffer)
        .write_to(&mut bytes, ImageFormat::Hdr)
        .expect("encodes");
    let img = decode_float_image(bytes.get_ref()).expect("valid HDR");
    let centred = mean_relative_error(&img.pixels, &original);
    assert!(centred.abs().max_element() < 0.0005, "{centred}");
}

fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Values spread over [0.02, 1], so that an sRGB offset or a wrong curve shows.
fn ramp(n: u32) -> Vec<f32> {
    (0..n)
        .map(|i| 0.02 + 0.98 * (i as f32 + 0.5) / n as f32)
        .collect()
}

#[test]
fn eight_bit_srgb_decodes_through_the_srgb_curve_without_offset() {
    let values = ramp(4096);
    let bytes: Vec<u8> = values
        .iter()
        .map(|&v| (linear_to_srgb(v) * 255.0).round() as u8)
        .collect();
    let grey = image::GrayImage::from_raw(values.len() as u32, 1, bytes).expect("n × 1");
    let mut png = Cursor::new(Vec::new());
    DynamicImage::ImageLuma8(grey)
        .write_to(&mut png, ImageFormat::Png)
        .expect("encodes");
    let as_env = decode_float_image(png.get_ref()).expect("valid PNG");
    let as_tex = decode_texture(png.get_ref(), true).expect("valid PNG");
    let (mut sum, mut worst) = (0.0f64, 0.0f32);
    for (i, &v) in values.iter().enumerate() {
        let (env, tex) = (as_env.pixels[i].x, as_tex.texels[i].x);
        assert!((env - tex).abs() < 1e-6, "the two decoders agree");
        // In the sRGB domain the error is within half a step of 1/255.
        let err = linear_to_srgb(env) - linear_to_srgb(v);
        worst = worst.max(err.abs());
        sum += err as f64;
    }
    let mean = sum / values.len() as f64;
    println!("8-bit sRGB: mean error {mean:.2e}, worst {worst:.2e} (half a step is 1.96e-3)");
    assert!(worst <= 0.5 / 255.0 + 1e-5 && mean.abs() < 0.05 / 255.0);
    assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
}

#[test]
fn sixteen_bit_png_decodes_without_offset() {
    let values = ramp(4096);
    let samples: Vec<u16> = values
        .iter()
        .map(|&v| (v * 65535.0).round() as u16)
        .collect();
    let grey = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(values.len() as u32, 1, samples)
        .expect("n × 1");
    let mut png = Cursor::new(Vec::new());
    DynamicImage::ImageLuma16(grey)
        .write_to(&mut png, ImageFormat::Png)
        .expect("encodes");
    let tex = decode_texture(png.get_ref(), false).expect("valid PNG");
    let (mut sum, mut worst) = (0.0f64, 0.0f32);
    for (i, &v) in values.iter().enumerate() {
        let err = tex.texels[i].x - v;
        worst = worst.max(err.abs());
        sum += err as f64;
    }
    let mean = sum / values.len() as f64;
    println!("16-bit PNG: mean error {mean:.2e}, worst {worst:.2e} (half a step is 7.6e-6)");
    assert!(worst <= 0.5 / 65535.0 + 1e-7 && mean.abs() < 0.05 / 65535.0);
}

#[test]
fn exr_half_decodes_to_the_nearest_half_without_offset() {
    use exr::prelude::{f16, Image, SpecificChannels, WritableImage};
    let (w, h) = (64usize, 32usize);
    let original = sky(w as u32, h as u32);
    let half = |x: f32| f16::from_f32(x);
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let c = original[p.y() * w + p.x()];
        (half(c.x), half(c.y), half(c.z))
    });
    let mut bytes = Cursor::new(Vec::new());
    Image::from_channels((w, h), channels)
        .write()
        .to_buffered(&mut bytes)
        .expect("encodes");
    let img = decode_float_image(bytes.get_ref()).expect("valid EXR");
    for (d, o) in img.pixels.iter().zip(&original) {
        let nearest = Vec3::new(half(o.x).to_f32(), half(o.y).to_f32(), half(o.z).to_f32());
        assert_eq!(*d, nearest, "EXR half samples are exact");
    }
    let mean = mean_relative_error(&img.pixels, &original);
    println!("EXR half: mean relative error {mean:?}");
    assert!(mean.abs().max_element() < 1e-4, "{mean}");
}
