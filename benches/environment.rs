//! Benchmark (a program, not a test): the environment light's importance-sampling costs.
//!
//! - building the sampling table (luminance × sin θ, marginal + conditional CDFs) for a
//!   4096 × 2048 map generated in memory (a sky gradient and a 1.5° sun, like the benchmark's
//!   `sky.hdr`), best and median of several runs;
//! - one environment sample plus one `pdf(direction)` query (what a shading point costs the
//!   light strategy and the MIS weight of a BRDF ray), in ns, over 2²⁰ random inputs.
//!
//! Run: `cargo bench --bench environment`. Figures go in `docs/environment.md`.

use std::f32::consts::PI;
use std::hint::black_box;
use std::time::{Duration, Instant};

use glam::{Vec2, Vec3};
use scnc::render::rng::Sampler;
use scnc::shade::{EnvMap, Environment};

fn sky(width: usize, height: usize) -> Vec<Vec3> {
    let sun = Vec3::new(0.66, 0.5, 0.56).normalize();
    let cos_sun = 1.5f32.to_radians().cos();
    let mut px = Vec::with_capacity(width * height);
    for row in 0..height {
        let theta = PI * (row as f32 + 0.5) / height as f32;
        for col in 0..width {
            let phi = 2.0 * PI * (col as f32 + 0.5) / width as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let up = d.y.max(0.0);
            px.push(if d.dot(sun) > cos_sun {
                Vec3::new(3000.0, 2800.0, 2500.0)
            } else if d.y >= 0.0 {
                Vec3::new(0.25 + 0.35 * up, 0.35 + 0.45 * up, 0.55 + 0.75 * up)
            } else {
                Vec3::new(0.12, 0.1, 0.08)
            });
        }
    }
    px
}

fn main() {
    let (w, h) = (4096, 2048);
    let texels = sky(w, h);
    let runs = 7;
    let mut times: Vec<Duration> = Vec::with_capacity(runs);
    let mut env = None;
    for _ in 0..runs {
        let copy = texels.clone();
        let start = Instant::now();
        let mut map = EnvMap::new(w, h, copy, 0.0).expect("sizes match");
        assert!(map.build_distribution());
        times.push(start.elapsed());
        env = Some(map);
    }
    times.sort();
    println!(
        "build {w}x{h} table (EnvMap::new + build_distribution, {} threads): best {:.1} ms, median {:.1} ms",
        rayon::current_num_threads(),
        times[0].as_secs_f64() * 1e3,
        times[runs / 2].as_secs_f64() * 1e3
    );

    let n = 1 << 20;
    let us: Vec<Vec2> = (0..n).map(|i| Sampler::new(1, 0, 0, i).next_2d()).collect();
    per_sample(env.expect("built"), &us, "4096x2048");
    for (w, h) in [(1024, 512), (256, 128)] {
        let mut map = EnvMap::new(w, h, sky(w, h), 0.0).expect("sizes match");
        assert!(map.build_distribution());
        per_sample(map, &us, &format!("{w}x{h}"));
    }
}

/// ns per `sample` + `pdf`, and per `sample` alone, over the inputs `us` (random, so the table
/// is read all over: the cold-cache case; a pixel's stratified samples are kinder).
fn per_sample(map: EnvMap, us: &[Vec2], name: &str) {
    let mut environment = Environment::new(Vec3::ZERO, Some(map), true);
    assert!(environment.prepare_sampling());
    let n = us.len() as f64;
    let mut both = f64::INFINITY;
    let mut alone = f64::INFINITY;
    for _ in 0..3 {
        let start = Instant::now();
        let mut acc = 0.0f32;
        for &u in us {
            if let Some(s) = environment.sample(black_box(u)) {
                acc += environment.pdf(black_box(s.wi)) + s.radiance.x;
            }
        }
        black_box(acc);
        both = both.min(start.elapsed().as_secs_f64() * 1e9 / n);
        let start = Instant::now();
        let mut acc = 0.0f32;
        for &u in us {
            if let Some(s) = environment.sample(black_box(u)) {
                acc += s.pdf_solid_angle + s.radiance.x;
            }
        }
        black_box(acc);
        alone = alone.min(start.elapsed().as_secs_f64() * 1e9 / n);
    }
    println!("{name}: sample + pdf {both:.0} ns, sample alone {alone:.0} ns (best of 3, {n} random inputs)");
}
