//! "Model only what a scene requires" (issue 8): a scene without textures, environment or
//! specular materials builds none of their structures (`Scene::inventory`, what `--stats`
//! lists) and takes none of their code paths in the per-sample loop (the path counters of
//! `RenderStats::counts`), while a scene with them builds and uses each one, so the counters
//! are known to be live. Also the build's `light_faces_away` warning (issue 2): a one-sided area
//! light with every piece of geometry behind it.

mod render_common;

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use render_common::pfm_bytes;
use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::diag::Severity;
use scnc::render::{render, RenderOptions, RenderStats};
use scnc::scene::{build, BuildOptions, Features, Scene};
use scnc::shade::Texture;

/// The scene (set to 4 samples per pixel, as `render_small` renders it), its sources and its
/// build warnings.
fn build_src(
    src: &str,
    loader: &MemLoader,
) -> (Scene, scnc::source::SourceMap, Vec<scnc::diag::Diagnostic>) {
    let compiled = compile_source("scene.scn", src, loader);
    assert!(!compiled.has_errors(), "{:#?}", compiled.diagnostics);
    let mut desc = compiled.scene.expect("compiles");
    desc.render.fix_samples(4);
    let (scene, warnings) = build(&desc, loader, &BuildOptions::default())
        .into_result()
        .unwrap_or_else(|d| panic!("{d:#?}"));
    (scene, compiled.sources, warnings)
}

fn render_small(scene: &Scene) -> RenderStats {
    render(
        scene,
        &RenderOptions { threads: Some(2) },
        &|_| {},
        &AtomicBool::new(false),
    )
    .expect("not cancelled")
    .1
}

const PLAIN: &str = r#"scnc 1
camera main { eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }
material white = phong { diffuse 0.8  specular 0 }
material red = phong { diffuse rgb(0.7, 0.1, 0.1) }
mesh floor = quad { size (6, 6) }
mesh ball = sphere { radius 0.5  segments 16 }
object floor { material white }
object ball { material red  transform { translate (0, 0.5, 0) } }
light bulb = point { position (2, 3, -2)  intensity 20 }
light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 4 }
render { resolution 24 x 16 }
"#;

const RICH: &str = r#"scnc 1
camera main { eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }
texture board = checker { even #e8e8e8  odd #303030  scale 8 }
material floor = phong { diffuse board  specular 0.1  shininess 16 }
material chrome = phong { diffuse 0.1  specular 0.8  shininess 200 }
mesh floor = quad { size (6, 6) }
mesh ball = sphere { radius 0.5  segments 16 }
object floor { material floor }
object ball { material chrome  transform { translate (0, 0.5, 0) } }
light bulb = point { position (2, 3, -2)  intensity 20 }
light sky = environment { image("sky.pfm") }
render { resolution 24 x 16 }
"#;

fn what_was_built(scene: &Scene) -> Vec<&'static str> {
    scene.inventory().iter().map(|b| b.what).collect()
}

#[test]
fn a_plain_scene_builds_and_runs_nothing_it_does_not_use() {
    let (scene, _, _) = build_src(PLAIN, &MemLoader::new());
    assert_eq!(
        scene.features(),
        Features {
            textures: false,
            specular: false,
            environment: false,
            area_lights: true,
        }
    );
    assert_eq!(what_was_built(&scene), ["meshes", "bvh", "light table"]);
    assert!(scene.textures.slots.iter().all(Option::is_none));
    assert!(
        scene.tangents.iter().all(Vec::is_empty),
        "no normal map, no tangents"
    );
    assert!(scene.lights.environment.is_none());
    let stats = render_small(&scene);
    let c = stats.counts;
    // Diffuse surfaces without a sky: light sampling alone (`render::mis::strategy_at`), so
    // not one BRDF direction is drawn.
    assert!(c.shadow > 0, "{c:?}");
    assert_eq!((c.brdf, c.brdf_skipped), (0, 0), "{c:?}");
    assert_eq!((c.textured, c.specular, c.environment), (0, 0, 0), "{c:?}");
    assert_eq!(c.nonfinite, 0);
}

#[test]
fn a_rich_scene_builds_and_uses_each_structure() {
    let mut loader = MemLoader::new();
    let texels: Vec<Vec3> = (0..32)
        .map(|k| Vec3::splat(0.1 + k as f32 * 0.05))
        .collect();
    loader.insert("sky.pfm", pfm_bytes(8, 4, &texels));
    let (scene, _, _) = build_src(RICH, &loader);
    assert_eq!(
        scene.features(),
        Features {
            textures: true,
            specular: true,
            environment: true,
            area_lights: false,
        }
    );
    assert_eq!(
        what_was_built(&scene),
        [
            "meshes",
            "bvh",
            "textures",
            "light table",
            "environment map",
            "environment table"
        ]
    );
    for b in scene.inventory() {
        assert!(b.bytes > 0, "{b:?}");
    }
    let c = render_small(&scene).counts;
    assert!(
        c.textured > 0 && c.specular > 0 && c.environment > 0,
        "{c:?}"
    );
}

/// A 4 × 2 grey PNG.
fn png() -> Vec<u8> {
    let img = image::GrayImage::from_fn(4, 2, |x, _| image::Luma([40 * x as u8 + 30]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("encodes");
    out.into_inner()
}

#[test]
fn image_textures_are_built_only_when_used_and_mipmapped_only_for_trilinear() {
    let scene_with = |floor: &str| {
        format!(
            r#"scnc 1
camera main {{ eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }}
texture near = image("a.png") {{ filter nearest }}
texture tri = image("b.png") {{ filter trilinear }}
texture unused = image("missing.png")
texture bumps = image("a.png") {{ encoding data  filter bilinear }}
material floor = phong {{ {floor}  specular 0 }}
mesh floor = quad {{ size (6, 6) }}
object floor {{ material floor }}
light bulb = point {{ position (2, 3, -2)  intensity 20 }}
render {{ resolution 24 x 16 }}
"#
        )
    };
    let mut loader = MemLoader::new();
    loader.insert("a.png", png());
    loader.insert("b.png", png());
    // Nearest only: one image, one level; the trilinear texture is not used, not loaded.
    let (scene, _, _) = build_src(&scene_with("diffuse near"), &loader);
    let images: Vec<usize> = scene
        .textures
        .slots
        .iter()
        .flatten()
        .filter_map(|t| match t {
            Texture::Image { data, .. } => Some(data.levels.len()),
            _ => None,
        })
        .collect();
    assert_eq!(images, [1]);
    let detail = |scene: &Scene| {
        scene
            .inventory()
            .into_iter()
            .find(|b| b.what == "textures")
            .expect("textures listed")
            .detail
    };
    assert!(
        detail(&scene).ends_with("4x2 1 mip level"),
        "{}",
        detail(&scene)
    );
    assert!(scene.tangents.iter().all(Vec::is_empty));
    assert!(render_small(&scene).counts.textured > 0);
    // Trilinear: the pyramid 4x2, 2x1, 1x1; a normal map (data: a second decode of a.png)
    // brings tangents for the floor.
    let (scene, _, _) = build_src(&scene_with("diffuse tri  normal_map bumps"), &loader);
    let d = detail(&scene);
    assert!(d.contains("2 image from 2 files"), "{d}");
    assert!(
        d.contains("4x2 3 mip levels") && d.contains("4x2 1 mip level"),
        "{d}"
    );
    assert_eq!(
        what_was_built(&scene),
        ["meshes", "bvh", "textures", "tangents", "light table"]
    );
    let files: Vec<_> = scnc::assets::Loader::recorded(&loader);
    assert!(
        !files.iter().any(|p| p.ends_with("missing.png")),
        "{files:?}"
    );
}

#[test]
fn an_environment_with_nothing_to_light_builds_no_sampling_table() {
    let src = r#"scnc 1
camera main { eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }
light sky = environment { image("sky.pfm") }
render { resolution 8 x 8 }
"#;
    let mut loader = MemLoader::new();
    loader.insert("sky.pfm", pfm_bytes(2, 1, &[Vec3::ONE, Vec3::splat(2.0)]));
    let (scene, _, _) = build_src(src, &loader);
    assert_eq!(what_was_built(&scene), ["environment map"]);
    assert!(scene.accel.is_none());
}

/// Normal-bin tables of the environment built so far, and the inventory's line for them.
fn normal_bins_built(scene: &Scene) -> (usize, String) {
    let map = scene
        .lights
        .environment
        .as_ref()
        .and_then(|e| e.map.as_ref());
    let detail = scene
        .inventory()
        .into_iter()
        .find(|b| b.what == "environment table")
        .map(|b| b.detail)
        .unwrap_or_default();
    (map.map_or(0, |m| m.normal_bins_built()), detail)
}

#[test]
fn a_sky_left_to_cosine_rays_builds_no_normal_bin_tables_and_an_adaptive_render_does() {
    let src = r#"scnc 1
camera main { eye (0, 2, -5)  target (0, 0.5, 0)  fov 40deg }
material white = phong { diffuse 0.8  specular 0 }
mesh floor = quad { size (6, 6) }
mesh ball = sphere { radius 0.5  segments 16 }
object floor { material white }
object ball { material white  transform { translate (0, 0.5, 0) } }
light sky = environment { image("sky.pfm") }
render { resolution 24 x 16 }
"#;
    // A smooth sky, `1 + 0.5 cos θ` (brighter towards the zenith): its harmonic fit is close,
    // so a fixed-count render leaves it to cosine rays (`render::mis::sky_by_cosine`).
    let texels: Vec<Vec3> = (0..128 * 64)
        .map(|i| {
            let theta = std::f32::consts::PI * ((i / 128) as f32 + 0.5) / 64.0;
            Vec3::splat(1.0 + 0.5 * theta.cos())
        })
        .collect();
    let mut loader = MemLoader::new();
    loader.insert("sky.pfm", pfm_bytes(128, 64, &texels));
    let (mut scene, _, _) = build_src(src, &loader);
    assert_eq!(normal_bins_built(&scene).0, 0, "none before a render");
    let c = render_small(&scene).counts;
    assert!(c.environment > 0 && c.brdf > 0, "{c:?}");
    let (built, detail) = normal_bins_built(&scene);
    assert_eq!(built, 0, "the fixed-count render reads no bin's table");
    assert!(detail.contains("for 0 of 256 normal bins"), "{detail}");

    // The same scene (as the watch cache keeps it) rendered adaptively samples the sky by its
    // tables, and builds those its normals fall in.
    scene.settings.noise = Some(0.5);
    scene.settings.max_samples = Some(8);
    render_small(&scene);
    let (built, detail) = normal_bins_built(&scene);
    assert!(built > 0 && built <= 256, "{built}");
    assert!(
        detail.contains(&format!("for {built} of 256 normal bins")),
        "{detail}"
    );
}

#[test]
fn a_one_sided_light_facing_away_from_everything_is_warned_about() {
    let with_light = |light: &str| {
        PLAIN
            .replace(
                "light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 4 }",
                light,
            )
            .replace("light bulb = point { position (2, 3, -2)  intensity 20 }", "")
    };
    // Corners counter-clockwise seen from above: the front faces up, away from the scene.
    let up = "light panel = area { quad (-1, 3, -1) (-1, 3, 1) (1, 3, 1) (1, 3, -1)  radiance 4 }";
    let (_, sources, warnings) = build_src(&with_light(up), &MemLoader::new());
    let w: Vec<_> = warnings
        .iter()
        .filter(|d| d.code == "scnc::build::light_faces_away")
        .collect();
    assert_eq!(w.len(), 1, "{warnings:#?}");
    assert_eq!(w[0].severity, Severity::Warning);
    assert!(w[0].message.contains("`panel`"), "{}", w[0].message);
    let label = w[0].primary.as_ref().expect("labelled at the light");
    assert_eq!(sources.snippet(label.span), "panel");
    assert!(w[0]
        .help
        .as_deref()
        .is_some_and(|h| h.contains("two_sided")));

    // Facing down (the file's own winding), two-sided, or with geometry above it: no warning.
    let down =
        "light panel = area { quad (-1, 3, -1) (1, 3, -1) (1, 3, 1) (-1, 3, 1)  radiance 4 }";
    let two_sided = "light panel = area { quad (-1, 3, -1) (-1, 3, 1) (1, 3, 1) (1, 3, -1)  radiance 4  two_sided true }";
    let low = "light panel = area { quad (-1, 0.7, -1) (-1, 0.7, 1) (1, 0.7, 1) (1, 0.7, -1)  radiance 4 }";
    for light in [down, two_sided, low] {
        let (_, _, warnings) = build_src(&with_light(light), &MemLoader::new());
        assert!(
            warnings
                .iter()
                .all(|d| d.code != "scnc::build::light_faces_away"),
            "{light}: {warnings:#?}"
        );
    }
}
