//! Benchmark (a program, not a test): the cost of texture lookups and of building a pyramid.
//!
//! - building the box-filtered mip pyramid of a 1024 × 1024 and a 1000 × 600 image;
//! - ns per lookup (nearest, bilinear, trilinear) over 2²⁰ random UVs and random mip levels
//!   in [0, 6) (random: the cold-cache worst case; a pixel's neighbouring samples are kinder),
//!   and the same for trilinear along a coherent scanline-like walk;
//! - ns per anisotropic lookup, multi-tap and EWA, for footprints of random orientation, a
//!   minor axis at a random level in [0, 5) and an anisotropy of 2, 4, 8 and 16, with the mean
//!   taps (trilinear lookups for multi-tap, texels for EWA);
//! - ns per full shading-point texture evaluation through `Textures::color` (footprint → mip
//!   level → trilinear), which is what a textured sample pays per input.
//!
//! Run: `cargo bench --bench textures`. Figures go in `docs/textures.md`.

use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::{Vec2, Vec4};
use scnc::ir::{ColorInput, Filter, WrapMode};
use scnc::render::rng::Sampler;
use scnc::shade::texture::anisotropic::{ewa, multi_tap};
use scnc::shade::texture::image::ImageData;
use scnc::shade::texture::{FilterStats, Footprint};
use scnc::shade::{Texture, Textures};

fn image(w: u32, h: u32) -> Vec<Vec4> {
    (0..h)
        .flat_map(|y| {
            (0..w).map(move |x| {
                let c = (((x / 8) + (y / 8)) % 2) as f32;
                Vec4::new(c, 0.5 * c + 0.2, (x as f32 / w as f32).sin(), 1.0)
            })
        })
        .collect()
}

fn best_of<F: FnMut() -> f64>(runs: usize, mut f: F) -> f64 {
    (0..runs).map(|_| f()).fold(f64::INFINITY, f64::min)
}

fn main() {
    for (w, h) in [(1024u32, 1024u32), (1000, 600)] {
        let texels = image(w, h);
        let mut times: Vec<Duration> = (0..5)
            .map(|_| {
                let copy = texels.clone();
                let start = Instant::now();
                let data = ImageData::new(w, h, copy, true);
                let t = start.elapsed();
                black_box(data.levels.len());
                t
            })
            .collect();
        times.sort();
        println!(
            "pyramid {w}x{h}: best {:.2} ms, median {:.2} ms",
            times[0].as_secs_f64() * 1e3,
            times[2].as_secs_f64() * 1e3
        );
    }

    let (w, h) = (1024, 1024);
    let data = ImageData::new(w, h, image(w, h), true);
    let n = 1usize << 20;
    let inputs: Vec<(Vec2, f32)> = (0..n)
        .map(|i| {
            let mut s = Sampler::new(7, 0, 0, i as u32);
            let uv = s.next_2d() * 4.0 - Vec2::splat(1.0);
            (uv, s.next_2d().x * 6.0)
        })
        .collect();
    for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
        let ns = best_of(5, || {
            let start = Instant::now();
            let mut acc = Vec4::ZERO;
            for &(uv, lod) in &inputs {
                acc += data.at_lod(black_box(uv), WrapMode::Repeat, filter, black_box(lod));
            }
            black_box(acc);
            start.elapsed().as_secs_f64() * 1e9 / n as f64
        });
        println!("{filter:?} lookup, random UVs ({w}x{h}, repeat): {ns:.1} ns");
    }
    let coherent = best_of(5, || {
        let start = Instant::now();
        let mut acc = Vec4::ZERO;
        for i in 0..n {
            let uv = Vec2::new((i % 2048) as f32 / 2048.0, (i / 2048) as f32 / 512.0);
            acc += data.at_lod(black_box(uv), WrapMode::Repeat, Filter::Trilinear, 0.7);
        }
        black_box(acc);
        start.elapsed().as_secs_f64() * 1e9 / n as f64
    });
    println!("Trilinear lookup, coherent walk at lod 0.7: {coherent:.1} ns");
    anisotropic_methods(&data, &inputs);

    let textures = Textures {
        slots: vec![Some(Texture::Image {
            data: Arc::new(data),
            wrap: WrapMode::Mirror,
            filter: Filter::Trilinear,
        })],
    };
    let mut stats = FilterStats::default();
    let ns = best_of(5, || {
        let start = Instant::now();
        let mut acc = 0.0f32;
        for &(uv, lod) in &inputs {
            let footprint = Footprint::isotropic((lod - 10.0).exp2());
            acc += textures
                .color(
                    ColorInput::Texture(0),
                    black_box(uv),
                    black_box(footprint),
                    &mut stats,
                )
                .x;
        }
        black_box(acc);
        start.elapsed().as_secs_f64() * 1e9 / n as f64
    });
    println!("Textures::color (footprint -> lod -> trilinear), random UVs: {ns:.1} ns");
}

type Method = fn(&ImageData, Vec2, WrapMode, Footprint, &mut FilterStats) -> Vec4;

/// ns per lookup and mean taps of the two anisotropic methods, by anisotropy.
fn anisotropic_methods(data: &ImageData, inputs: &[(Vec2, f32)]) {
    let texel = 1.0 / data.width() as f32;
    for ratio in [2.0f32, 4.0, 8.0, 16.0] {
        let footprints: Vec<(Vec2, Footprint)> = inputs
            .iter()
            .enumerate()
            .map(|(i, &(uv, lod))| {
                let angle = i as f32 * 2.399_963;
                let dir = Vec2::new(angle.cos(), angle.sin());
                let minor = (lod * 5.0 / 6.0).exp2() * texel;
                let fp = Footprint {
                    major: dir * minor * ratio,
                    minor: dir.perp() * minor,
                };
                (uv, fp)
            })
            .collect();
        for (name, method) in [("multi-tap", multi_tap as Method), ("EWA", ewa as Method)] {
            let mut stats = FilterStats::default();
            let ns = best_of(3, || {
                stats = FilterStats::default();
                let start = Instant::now();
                let mut acc = Vec4::ZERO;
                for &(uv, fp) in &footprints {
                    acc += method(data, black_box(uv), WrapMode::Repeat, fp, &mut stats);
                }
                black_box(acc);
                start.elapsed().as_secs_f64() * 1e9 / footprints.len() as f64
            });
            println!(
                "{name} lookup, anisotropy {ratio}: {ns:.1} ns, {:.1} taps",
                stats.mean_taps()
            );
        }
    }
}
