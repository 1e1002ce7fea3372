//! Stage 3–4: the environment map's importance sampling against mathematics, and bad map files.
//!
//! - the sampling density integrates to 1 over the sphere (numerically, rotated map, with and
//!   without a constant part); a sampled direction looks up the texel it was sampled from and
//!   `pdf(direction)` equals the density the sampler reported; a histogram of samples matches the
//!   density (chi-square bound at 4 σ of its distribution);
//! - a diffuse plane under a map renders `ρ/π · ∫ L cos θ dω` (integrated numerically from the
//!   texels) within 4 standard errors for every strategy;
//! - missing, corrupt, oversized, NaN/negative and all-black maps give diagnostics at the path
//!   literal, never a panic.

mod render_common;

use std::f32::consts::PI;

use glam::{Mat4, Vec2, Vec3};
use render_common::*;
use scnc::assets::MemLoader;
use scnc::diag::Severity;
use scnc::geom::Ray;
use scnc::ir::*;
use scnc::render::integrator::{radiance, RayCounts};
use scnc::render::rng::Sampler;
use scnc::scene::DirectStrategy;
use scnc::shade::{EnvMap, Environment};
use scnc::source::{SourceMap, Span};

const W: usize = 64;
const H: usize = 32;

/// A test sky: a gradient above the horizon, black below (zero rows), and a 3° sun 200× the
/// sky, at map azimuth 1 rad and 35° elevation.
fn sky_texels() -> Vec<Vec3> {
    let sun = {
        let (el, az) = (35f32.to_radians(), 1.0f32);
        Vec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin())
    };
    let mut px = Vec::with_capacity(W * H);
    for row in 0..H {
        let theta = PI * (row as f32 + 0.5) / H as f32;
        for col in 0..W {
            let phi = 2.0 * PI * (col as f32 + 0.5) / W as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            px.push(if d.y < 0.0 {
                Vec3::ZERO
            } else if d.dot(sun) > 3f32.to_radians().cos() {
                Vec3::new(200.0, 180.0, 150.0)
            } else {
                Vec3::new(
                    0.2 + 0.3 * d.y,
                    0.3 + 0.4 * d.y,
                    0.6 + 0.3 * phi.cos().abs(),
                )
            });
        }
    }
    px
}

fn map(rotation: f32) -> EnvMap {
    let mut m = EnvMap::new(W, H, sky_texels(), rotation).expect("sizes match");
    assert!(m.build_distribution(), "not black");
    m
}

/// ∫ g over the sphere, on a (θ, φ) grid 16× finer than the map in each direction.
fn sphere_integral(g: impl Fn(Vec3) -> f64) -> f64 {
    let (nt, np) = (H * 16, W * 16);
    let mut sum = 0.0;
    for i in 0..nt {
        let theta = PI * (i as f32 + 0.5) / nt as f32;
        for j in 0..np {
            let phi = 2.0 * PI * (j as f32 + 0.5) / np as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            sum += g(d) * theta.sin() as f64;
        }
    }
    sum * (PI as f64 / nt as f64) * (2.0 * PI as f64 / np as f64)
}

#[test]
fn the_density_integrates_to_one_over_the_sphere() {
    for rotation in [0.0, 0.7, -2.0] {
        let m = map(rotation);
        let total = sphere_integral(|d| m.pdf(d) as f64);
        assert!((total - 1.0).abs() < 2e-3, "rotation {rotation}: {total}");
    }
    let mut env = Environment::new(Vec3::splat(0.3), Some(map(0.4)), true);
    assert!(env.prepare_sampling());
    let total = sphere_integral(|d| env.pdf(d) as f64);
    assert!((total - 1.0).abs() < 2e-3, "mixture: {total}");
}

#[test]
fn samples_round_trip_to_their_texel_and_density() {
    let m = map(0.9);
    let n = 256;
    let mut mismatched = 0;
    for i in 0..n {
        for j in 0..n {
            let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let Some(s) = m.sample(u) else {
                continue;
            };
            assert!((s.wi.length() - 1.0).abs() < 1e-5);
            assert!(
                s.radiance.max_element() > 0.0,
                "black texels are never sampled"
            );
            let pdf = m.pdf(s.wi);
            if m.radiance(s.wi) != s.radiance || (pdf - s.pdf_solid_angle).abs() > 1e-4 * pdf {
                mismatched += 1;
            }
        }
    }
    // Only directions that round onto a texel border may land in the neighbour.
    assert!(
        mismatched <= n * n / 1000,
        "{mismatched} of {} mismatched",
        n * n
    );
}

#[test]
fn a_histogram_of_samples_matches_the_density() {
    let m = map(0.0);
    // Bins of 4 × 4 texels; the probability of a bin is the density integrated over it.
    let (bw, bh) = (W / 4, H / 4);
    let mut p = vec![0.0f64; bw * bh];
    for row in 0..H {
        for col in 0..W {
            let theta = PI * (row as f32 + 0.5) / H as f32;
            let phi = 2.0 * PI * (col as f32 + 0.5) / W as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            // The density over the texel is pdf_uv / (2π² sin θ); its integral over the texel
            // is pdf_uv / (W·H), so recover pdf_uv at the centre.
            let pdf_uv = m.pdf(d) * 2.0 * PI * PI * theta.sin();
            p[(row / 4) * bw + col / 4] += pdf_uv as f64 / (W * H) as f64;
        }
    }
    let n = 200_000u32;
    let mut counts = vec![0u32; bw * bh];
    for i in 0..n {
        let u = Sampler::new(3, 0, 0, i).next_2d();
        if let Some(s) = m.sample(u) {
            let (col, row, _) = m.texel_of(s.wi);
            counts[(row / 4) * bw + col / 4] += 1;
        }
    }
    let total_p: f64 = p.iter().sum();
    assert!((total_p - 1.0).abs() < 1e-4, "{total_p}");
    let mut chi2 = 0.0;
    let mut bins = 0;
    for (k, &c) in counts.iter().enumerate() {
        let expected = p[k] * n as f64;
        if expected == 0.0 {
            assert_eq!(c, 0, "bin {k} has zero probability");
            continue;
        }
        if expected >= 5.0 {
            chi2 += (c as f64 - expected).powi(2) / expected;
            bins += 1;
        }
    }
    let dof = (bins - 1) as f64;
    assert!(bins > 20, "enough populated bins: {bins}");
    assert!(
        chi2 < dof + 4.0 * (2.0 * dof).sqrt(),
        "chi² {chi2:.1} with {dof} degrees of freedom"
    );
}

fn asset(file: scnc::source::FileId, text: &str, literal: &str) -> AssetPath {
    let quoted = format!("\"{literal}\"");
    let start = text.find(&quoted).expect("literal in the fixture");
    AssetPath {
        path: literal.into(),
        written: literal.into(),
        span: Span::new(file, start, start + quoted.len()),
    }
}

/// A diffuse plane under the map (intensity 2), seen from above.
fn plane_under(file: AssetPath, rotation: f32) -> SceneDesc {
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 3.0, -1.0), Vec3::ZERO, Vec3::Y, 40.0),
        settings(8, 8, 1),
    );
    desc.meshes = vec![quad("floor", 4.0, 4.0)];
    desc.materials = vec![phong("grey", Vec3::splat(0.5), 0.0, 1.0)];
    desc.objects = vec![object(0, 0, Mat4::IDENTITY)];
    desc.lights = vec![environment(EnvSource::Image(file), 2.0, rotation, true)];
    desc
}

const SCN: &str = r#"light sky = environment { image("sky.pfm") }"#;

fn fixture() -> (SourceMap, scnc::source::FileId) {
    let mut sources = SourceMap::new();
    let file = sources.add("test.scn", "test.scn", SCN);
    (sources, file)
}

#[test]
fn the_test_sky_s_sun_is_sampled_on_its_own_and_a_plain_gradient_is_not() {
    // The tests of this file then cover the split (`shade::light::env_bright`).
    assert!(map(0.0).has_bright());
    let gradient: Vec<Vec3> = sky_texels()
        .into_iter()
        .map(|t| if t.x > 100.0 { Vec3::splat(0.5) } else { t })
        .collect();
    let mut m = EnvMap::new(W, H, gradient, 0.0).expect("sizes match");
    assert!(m.build_distribution());
    assert!(!m.has_bright());
}

#[test]
fn a_sun_below_a_normal_s_horizon_is_said_so_only_when_none_of_its_samples_is_above() {
    // The render skips the sun's samples at such a normal (`render::mis`): the test sky's
    // 3° sun, rotated, against 2,000 normals and 256 samples of the sun each.
    let m = map(0.7);
    let samples: Vec<Vec3> = (0..256)
        .filter_map(|k| {
            let u = Vec2::new((k as f32 + 0.5) / 256.0, ((k * 97) % 256) as f32 / 256.0);
            m.sample_bright(u).map(|s| s.wi)
        })
        .collect();
    assert_eq!(samples.len(), 256);
    let (mut below, mut near) = (0, 0);
    for i in 0..2000 {
        let z = 1.0 - 2.0 * (i as f32 + 0.5) / 2000.0;
        let t = i as f32 * 2.399_963;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let n = Vec3::new(r * t.cos(), z, r * t.sin());
        let highest = samples.iter().map(|d| n.dot(*d)).fold(f32::MIN, f32::max);
        if m.bright_below_horizon_of(n) {
            below += 1;
            assert!(highest < 0.0, "{n}: a sun sample at cos {highest}");
        } else if highest < -0.6 {
            near += 1;
        }
    }
    // The cone is tight enough: on this coarse map (a texel's diagonal is 8°, its margin twice
    // that) it is about 22° wide, so about 31% of the normals see it wholly below; and every
    // normal whose horizon is far above the sun's samples is recognised.
    assert!(below > 600, "{below} normals");
    assert_eq!(near, 0, "{near} normals far below the sun not recognised");
}

#[test]
fn the_sun_s_density_skipped_outside_its_cone_is_the_texel_s_everywhere() {
    // `EnvMap::bright_density` answers 0 without a texel lookup outside the sun's cone: it must
    // agree with the density read from the direction's texel for every direction, on the
    // sun's texels (near the cone's edge) and all over the sphere.
    let m = map(0.7);
    let near_sun = (0..512).filter_map(|k| {
        let u = Vec2::new((k as f32 + 0.5) / 512.0, ((k * 97) % 512) as f32 / 512.0);
        m.sample_bright(u).map(|s| s.wi)
    });
    let sphere = (0..20_000).map(|i| {
        let z = 1.0 - 2.0 * (i as f32 + 0.5) / 20_000.0;
        let t = i as f32 * 2.399_963;
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * t.cos(), z, r * t.sin())
    });
    let mut lit = 0;
    for d in near_sun.chain(sphere) {
        let (_, _, texel_bright) = m.densities_facing(d, None);
        assert_eq!(m.bright_density(d), texel_bright, "{d}");
        assert_eq!(m.radiance_and_bright_density(d).1, texel_bright, "{d}");
        lit += usize::from(texel_bright > 0.0);
    }
    assert!(lit >= 512, "{lit} directions on the sun");
}

#[test]
fn a_diffuse_plane_under_the_map_renders_its_irradiance_for_every_strategy() {
    plane_irradiance_for_every_strategy(0.0);
}

/// With a constant part as well, the sky strategy's uniform sphere overlaps the sun's texels:
/// three strategies' weights meet there.
#[test]
fn a_diffuse_plane_under_the_map_and_a_constant_renders_its_irradiance() {
    plane_irradiance_for_every_strategy(0.4);
}

fn plane_irradiance_for_every_strategy(constant: f32) {
    let (_sources, file) = fixture();
    let rotation = 0.8;
    let mut loader = MemLoader::new();
    loader.insert("sky.pfm", pfm_bytes(W, H, &sky_texels()));
    let mut desc = plane_under(asset(file, SCN, "sky.pfm"), rotation);
    if constant > 0.0 {
        desc.lights.push(environment(
            EnvSource::Constant(Vec3::splat(constant)),
            1.0,
            0.0,
            true,
        ));
    }
    let (mut scene, _) = build_with(&desc, &loader).expect("builds");
    // E = ∫ L cos θ dω over the upper hemisphere, L looked up exactly as the renderer does.
    let m = map(rotation);
    let irradiance =
        sphere_integral(|d| ((2.0 * m.radiance(d).x + constant) * d.y.max(0.0)) as f64);
    let expected = 0.5 / PI as f64 * irradiance;
    let eye = Vec3::new(0.3, 1.0, -0.2);
    let ray = Ray::new(eye, (Vec3::new(0.1, 0.0, 0.05) - eye).normalize());
    for (strategy, n) in [
        (DirectStrategy::LightOnly, 4000),
        (DirectStrategy::Mis, 4000),
        (DirectStrategy::BrdfOnly, 40000),
    ] {
        scene.strategy = strategy;
        let mut counts = RayCounts::default();
        let values: Vec<f64> = (0..n)
            .map(|i| radiance(&scene, &ray, &mut Sampler::new(5, 0, 0, i), &mut counts).x as f64)
            .collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let se = (var / n as f64).sqrt();
        assert!(se < 0.05 * expected, "{strategy:?}: se {se} vs {expected}");
        assert!(
            (mean - expected).abs() <= 4.0 * se,
            "{strategy:?}: {mean} ± {se} vs {expected}"
        );
    }
}

/// Builds the plane scene with `bytes` as `sky.pfm` (or no file at all).
fn build_sky(bytes: Option<Vec<u8>>) -> (SourceMap, Built) {
    let (sources, file) = fixture();
    let mut loader = MemLoader::new();
    if let Some(b) = bytes {
        loader.insert("sky.pfm", b);
    }
    let desc = plane_under(asset(file, SCN, "sky.pfm"), 0.0);
    let result = build_with(&desc, &loader);
    (sources, result)
}

fn only_error(bytes: Option<Vec<u8>>) -> (String, String) {
    let (sources, result) = build_sky(bytes);
    let diags = result.expect_err("must fail");
    assert_eq!(diags.len(), 1, "{diags:?}");
    let d = &diags[0];
    assert_eq!(d.severity, Severity::Error);
    let at = sources.snippet(d.primary.as_ref().expect("labelled").span);
    assert_eq!(at, "\"sky.pfm\"");
    (d.code.to_string(), d.message.clone())
}

#[test]
fn missing_corrupt_and_oversized_maps_are_errors_at_the_path() {
    assert_eq!(only_error(None).0, "scnc::build::missing_file");
    assert_eq!(
        only_error(Some(b"definitely not an image".to_vec())).0,
        "scnc::build::corrupt_image"
    );
    let mut truncated = pfm_bytes(4, 2, &[Vec3::ONE; 8]);
    truncated.truncate(30);
    assert_eq!(only_error(Some(truncated)).0, "scnc::build::corrupt_image");
    let (code, message) = only_error(Some(b"PF\n20000 10\n-1.0\n".to_vec()));
    assert_eq!(code, "scnc::build::image_too_large");
    assert!(message.contains("20000 × 10"), "{message}");
}

#[test]
fn nan_and_negative_pixels_are_black_with_one_warning() {
    let mut px = vec![Vec3::splat(0.5); 8 * 4];
    px[3] = Vec3::new(f32::NAN, 1.0, 1.0);
    px[9] = Vec3::new(-2.0, 0.5, 0.5);
    px[20] = Vec3::new(f32::INFINITY, 0.0, 0.0);
    let (sources, result) = build_sky(Some(pfm_bytes(8, 4, &px)));
    let (scene, warnings) = result.expect("warnings only");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = &warnings[0];
    assert_eq!(w.code, "scnc::build::invalid_environment_pixels");
    assert_eq!(w.severity, Severity::Warning);
    assert!(w.message.starts_with("3 of 32 pixels"), "{}", w.message);
    assert_eq!(
        sources.snippet(w.primary.as_ref().expect("labelled").span),
        "\"sky.pfm\""
    );
    let (film, _) = render_with(&scene, 1);
    assert!(film.pixels().iter().all(|p| p.is_finite()));
    assert!(film.mean().min_element() > 0.0);
}

#[test]
fn an_all_black_map_warns_and_lights_nothing() {
    let (_, result) = build_sky(Some(pfm_bytes(8, 4, &[Vec3::ZERO; 32])));
    let (scene, warnings) = result.expect("a warning only");
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].code, "scnc::build::black_environment");
    assert!(scene.lights.by_power.is_none(), "nothing to sample");
    let (film, stats) = render_with(&scene, 1);
    assert!(film.pixels().iter().all(|&p| p == Vec3::ZERO));
    assert_eq!(stats.shadow_rays + stats.brdf_rays, 0);
}

#[test]
fn a_surface_facing_away_from_the_sun_is_not_noisier_with_mis_than_with_cosine_sampling() {
    // The plane's normal leans 60° away from the sun (map azimuth 1 rad), so the sun is below
    // its horizon and only the dim sky lights it: MIS's light samples spent on the sun must
    // not cost more than the power heuristic gives back.
    let (_sources, file) = fixture();
    let mut loader = MemLoader::new();
    loader.insert("sky.pfm", pfm_bytes(W, H, &sky_texels()));
    let mut desc = plane_under(asset(file, SCN, "sky.pfm"), 0.0);
    let away = Vec3::new(-1.0f32.cos(), 0.0, -1.0f32.sin());
    let axis = Vec3::Y.cross(away).normalize();
    desc.objects = vec![object(
        0,
        0,
        Mat4::from_axis_angle(axis, 60f32.to_radians()),
    )];
    let (mut scene, _) = build_with(&desc, &loader).expect("builds");
    let normal = Mat4::from_axis_angle(axis, 60f32.to_radians()).transform_vector3(Vec3::Y);
    let eye = normal * 1.5 + Vec3::Y * 0.1;
    let ray = Ray::new(eye, -eye.normalize());
    let n = 4000;
    let mut variance = |strategy| {
        scene.strategy = strategy;
        let mut counts = RayCounts::default();
        let values: Vec<f64> = (0..n)
            .map(|i| radiance(&scene, &ray, &mut Sampler::new(8, 0, 0, i), &mut counts).x as f64)
            .collect();
        let mean = values.iter().sum::<f64>() / n as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        (mean, var)
    };
    let (m_mis, v_mis) = variance(DirectStrategy::Mis);
    let (m_cos, v_cos) = variance(DirectStrategy::BrdfOnly);
    eprintln!(
        "facing away: variance MIS {v_mis:.3e}, cosine {v_cos:.3e} (means {m_mis:.4}, {m_cos:.4})"
    );
    assert!(m_mis > 0.0 && m_cos > 0.0, "the sky lights the plane");
    // The sample variance of 4000 values is itself uncertain by a few percent.
    assert!(
        v_mis <= 1.1 * v_cos,
        "MIS {v_mis:.3e} vs cosine {v_cos:.3e}"
    );
}

/// The sampling towards a surface's hemisphere (`shade::light::env_sampler`): for any normal
/// its density integrates to one over the sphere, each sample's density is the one `pdf_facing`
/// gives back, every direction above the horizon of the normal keeps a positive density (so
/// no light is left to BRDF samples alone), and the samples lean further towards the normal
/// than the plain distribution's (a larger mean clamped cosine).
#[test]
fn sampling_towards_a_normal_is_a_density_and_favours_its_hemisphere() {
    let m = map(0.7);
    let normals = [
        Vec3::Y,
        Vec3::new(0.3, -0.2, 0.93).normalize(),
        Vec3::new(-1.0, 0.05, 0.0).normalize(),
        Vec3::new(0.6, 0.6, -0.53).normalize(),
    ];
    for n in normals {
        let total = sphere_integral(|d| m.pdf_facing(d, Some(n)) as f64);
        assert!((total - 1.0).abs() < 2e-3, "normal {n}: {total}");
        let grid = 128;
        let (mut above, mut above_plain, mut mismatched) = (0.0f64, 0.0f64, 0);
        for i in 0..grid {
            for j in 0..grid {
                let u = Vec2::new(
                    (i as f32 + 0.5) / grid as f32,
                    (j as f32 + 0.5) / grid as f32,
                );
                if let Some(s) = m.sample_facing(u, Some(n)) {
                    above += f64::from(s.wi.dot(n).max(0.0));
                    let pdf = m.pdf_facing(s.wi, Some(n));
                    if (pdf - s.pdf_solid_angle).abs() > 1e-4 * pdf {
                        mismatched += 1;
                    }
                }
                if let Some(s) = m.sample(u) {
                    above_plain += f64::from(s.wi.dot(n).max(0.0));
                }
            }
        }
        assert!(
            mismatched <= grid * grid / 1000,
            "normal {n}: {mismatched} mismatched"
        );
        assert!(
            above > 1.05 * above_plain,
            "normal {n}: {above} vs plain {above_plain}"
        );
        // Every lit direction above the horizon can be drawn.
        let lit_and_above = |d: Vec3| d.dot(n) > 1e-3 && m.radiance(d).max_element() > 0.0;
        let uncovered = sphere_integral(|d| {
            f64::from(u8::from(
                lit_and_above(d) && m.pdf_facing(d, Some(n)) <= 0.0,
            ))
        });
        assert_eq!(uncovered, 0.0, "normal {n}");
    }
}

/// Importance sampling towards a normal estimates the irradiance integral `∫ L · max(0, cos)`
/// without bias: a stratified estimate with many samples equals a direct quadrature.
#[test]
fn sampling_towards_a_normal_estimates_irradiance() {
    let m = map(0.3);
    let mut normals = vec![
        Vec3::Y,
        Vec3::new(-0.9, 0.3, 0.2).normalize(),
        Vec3::new(0.1, -0.5, 0.86).normalize(),
    ];
    // A ring of limb-like normals (z = 0) and a spread over the sphere.
    for k in 0..24 {
        let a = k as f32 * std::f32::consts::TAU / 24.0;
        normals.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    for k in 0..40 {
        let z = 1.0 - 2.0 * (k as f32 + 0.5) / 40.0;
        let r = (1.0 - z * z).sqrt();
        let a = k as f32 * 2.399_963;
        normals.push(Vec3::new(r * a.cos(), z, r * a.sin()));
    }
    for n in normals {
        let exact = sphere_integral(|d| f64::from(m.radiance(d).x * d.dot(n).max(0.0)));
        // A rank-1 lattice (Fibonacci): well spread in both coordinates at once.
        let count = 1 << 16;
        let mut sum = 0.0f64;
        for k in 0..count {
            let u = Vec2::new(
                (k as f32 + 0.5) / count as f32,
                (k as f64 * 0.618_033_988_749_894_9).fract() as f32,
            );
            if let Some(s) = m.sample_facing(u, Some(n)) {
                sum += f64::from(s.radiance.x * s.wi.dot(n).max(0.0) / s.pdf_solid_angle);
            }
        }
        let estimate = sum / count as f64;
        if exact < 1e-6 {
            // Facing the black lower half of this sky: nothing to estimate.
            assert!(estimate < 1e-6, "normal {n}: {estimate}");
            continue;
        }
        // 1%, or a thousandth of the zenith's irradiance for slivers of sky at the horizon
        // (where the quadrature itself is coarse).
        assert!(
            (estimate - exact).abs() < 0.01 * exact + 1e-3,
            "normal {n}: {estimate} vs {exact}"
        );
    }
}
