//! Stage 4: the per-sample path specialised for scenes lit by one rectangle (`render::rect_lit`)
//! gives the general integrator's image bit for bit, and the same ray counts: cornell (flat
//! meshes, a one-sided light, emitter pixels sampled 16× as often), and soft_shadows (a sphere
//! with vertex normals, a rotated box) made two-sided and ambient, at sample counts that fill
//! the runs of lanes, leave them partly empty, and are not powers of two; and adaptive renders
//! of both (batches of 2, 2, 16, …: the sequences continued across batches), whose images,
//! error images and counts are the general path's on any thread count.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use scnc::assets::FsLoader;
use scnc::compile::compile_file;
use scnc::film::Film;
use scnc::render::{render, render_with_error, RenderOptions, RenderStats};
use scnc::scene::{build, BuildOptions, Scene, ShadingPath};

/// `examples/NAME.scn` at `size`² and `spp` samples per pixel, after `edit` of its source
/// text's description.
fn example(name: &str, size: u32, spp: u32, edit: impl Fn(&mut scnc::ir::SceneDesc)) -> Scene {
    let path = Path::new("examples").join(format!("{name}.scn"));
    let loader = FsLoader::new();
    let mut desc = compile_file(&path, &loader)
        .scene
        .unwrap_or_else(|| panic!("{name} compiles"));
    desc.render.width = size;
    desc.render.height = size;
    desc.render.fix_samples(spp);
    edit(&mut desc);
    build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .map(|(scene, _)| scene)
        .unwrap_or_else(|_| panic!("{name} builds"))
}

fn render_on(scene: &Scene, threads: usize) -> (Film, RenderStats) {
    let options = RenderOptions {
        threads: Some(threads),
    };
    render(scene, &options, &|_| {}, &AtomicBool::new(false)).expect("not cancelled")
}

/// Renders `scene` on both paths and asserts the same bits and counts.
fn same_on_both_paths(mut scene: Scene, what: &str) {
    scene.shading_path = ShadingPath::Specialised;
    let (fast, fast_stats) = render_on(&scene, 2);
    scene.shading_path = ShadingPath::General;
    let (general, general_stats) = render_on(&scene, 1);
    let bits = |f: &Film| {
        f.pixels()
            .iter()
            .flat_map(|p| p.to_array())
            .map(f32::to_bits)
            .collect::<Vec<_>>()
    };
    assert!(bits(&fast) == bits(&general), "{what}: the images differ");
    assert_eq!(fast_stats.counts, general_stats.counts, "{what}");
    // Lit, with shadow rays: not an image that would match trivially.
    assert!(
        fast.mean().min_element() > 1e-3,
        "{what}: mean {}",
        fast.mean()
    );
    assert!(fast_stats.shadow_rays > 0, "{what}");
}

#[test]
fn cornell_is_the_general_paths_image() {
    for spp in [1, 4, 9, 16] {
        same_on_both_paths(
            example("cornell", 40, spp, |_| ()),
            &format!("cornell, {spp} spp"),
        );
    }
}

#[test]
fn curved_rotated_two_sided_and_ambient_are_the_general_paths_image() {
    let edit = |desc: &mut scnc::ir::SceneDesc| {
        for m in &mut desc.materials {
            m.ambient = glam::Vec3::new(0.01, 0.02, 0.0);
        }
        for l in &mut desc.lights {
            if let scnc::ir::Light::Area(a) = l {
                a.two_sided = true;
            }
        }
    };
    for spp in [4, 25] {
        same_on_both_paths(
            example("soft_shadows", 32, spp, edit),
            &format!("soft_shadows, {spp} spp"),
        );
    }
}

/// Renders adaptive `scene` on both paths (the fast one on 1 and 2 threads) and asserts the
/// same image, error image and counts.
fn adaptive_same_on_both_paths(mut scene: Scene, what: &str) {
    let run = |scene: &Scene, threads: usize| {
        let options = RenderOptions {
            threads: Some(threads),
        };
        render_with_error(scene, &options, &|_| {}, &AtomicBool::new(false)).expect("not cancelled")
    };
    let bits = |f: &Film| {
        f.pixels()
            .iter()
            .flat_map(|p| p.to_array())
            .map(f32::to_bits)
            .collect::<Vec<_>>()
    };
    scene.shading_path = ShadingPath::Specialised;
    let fast = run(&scene, 2);
    let fast_one = run(&scene, 1);
    scene.shading_path = ShadingPath::General;
    let general = run(&scene, 1);
    for (name, other) in [("general path", &general), ("one thread", &fast_one)] {
        assert!(
            bits(&fast.film) == bits(&other.film),
            "{what}: images differ from the {name}'s"
        );
        assert!(
            bits(&fast.std_error) == bits(&other.std_error),
            "{what}: error images differ from the {name}'s"
        );
        assert_eq!(fast.stats.counts, other.stats.counts, "{what}, {name}");
    }
    assert!(fast.film.mean().min_element() > 1e-3, "{what}");
    assert!(fast.stats.shadow_rays > 0, "{what}");
    // Pixels went past their first batches (the replicates' sequences are used).
    assert!(fast.stats.noise.mean_samples() > 4.0, "{what}");
}

#[test]
fn adaptive_renders_are_the_general_paths_images() {
    for noise in [0.1, 0.02] {
        let adaptive = |desc: &mut scnc::ir::SceneDesc| desc.render.noise = Some(noise);
        for name in ["cornell", "soft_shadows"] {
            adaptive_same_on_both_paths(
                example(name, 24, 1, adaptive),
                &format!("{name}, noise {noise}"),
            );
        }
    }
}
