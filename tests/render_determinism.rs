//! Stage 4: renders are a pure function of the scene: identical bits for any thread count, and
//! the same image to rounding for either acceleration structure; cancellation and progress; only what is used is built.

mod render_common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use glam::Vec3;
use render_common::*;
use scnc::bvh::AccelKind;
use scnc::render::{render, Cancelled, RenderOptions};

#[test]
fn one_and_four_threads_give_identical_bits() {
    let scene = build(&showcase(32, 4), AccelKind::Bvh);
    let (one, s1) = render_with(&scene, 1);
    let (four, s4) = render_with(&scene, 4);
    assert_eq!(one, four);
    assert_eq!(
        (s1.camera_rays, s1.shadow_rays),
        (s4.camera_rays, s4.shadow_rays)
    );
    // Four per pixel, and 64 in the pixels that may see the area light.
    let (boosted, spp) = s1.emitter_pixels;
    assert_eq!(
        s1.camera_rays,
        32 * 32 * 4 + boosted * u64::from(spp.saturating_sub(4))
    );
    assert!(s1.shadow_rays > 0);
    // The scene is lit: not a black image that would trivially match.
    assert!(one.mean().min_element() > 0.01, "mean {}", one.mean());
}

/// The BVH traces with the watertight test, the oracle with Möller–Trumbore: hit distances and
/// barycentrics agree to rounding, so pixels agree to a few ulps of shading, except where a
/// shadow ray passes within rounding of an occluder's edge and the two tests decide the tie
/// differently. Allow that on at most 1% of pixels.
#[test]
fn brute_force_and_bvh_give_the_same_image_to_rounding() {
    let desc = showcase(24, 1);
    let (a, _) = render_with(&build(&desc, AccelKind::None), 2);
    let (b, _) = render_with(&build(&desc, AccelKind::Bvh), 2);
    let close = |x: Vec3, y: Vec3| (x - y).abs().max_element() <= 1e-4 * x.max_element().max(1e-3);
    let differing = a
        .pixels()
        .iter()
        .zip(b.pixels())
        .filter(|(x, y)| !close(**x, **y))
        .count();
    assert!(
        differing * 100 <= a.pixels().len(),
        "{differing} of {} pixels differ beyond rounding",
        a.pixels().len()
    );
    assert!((a.mean() - b.mean()).abs().max_element() < 1e-3 * a.mean().max_element());
}

#[test]
fn the_seed_changes_the_noise_but_not_the_mean_much() {
    let mut desc = showcase(24, 4);
    let (a, _) = render_with(&build(&desc, AccelKind::Bvh), 2);
    desc.render.seed = 12345;
    let (b, _) = render_with(&build(&desc, AccelKind::Bvh), 2);
    assert_ne!(a, b);
    let (ma, mb) = (a.mean(), b.mean());
    assert!(
        (ma - mb).abs().max_element() < 0.05 * ma.max_element(),
        "{ma} vs {mb}"
    );
}

#[test]
fn cancelling_stops_the_render_and_progress_reaches_one() {
    let scene = build(&showcase(40, 1), AccelKind::Bvh);
    let cancel = AtomicBool::new(true);
    let r = render(&scene, &RenderOptions::default(), &|_| {}, &cancel);
    assert_eq!(r.err(), Some(Cancelled));

    let seen = Mutex::new(Vec::new());
    let cancel = AtomicBool::new(false);
    let progress = |f: f32| seen.lock().expect("no panics while held").push(f);
    render(
        &scene,
        &RenderOptions { threads: Some(2) },
        &progress,
        &cancel,
    )
    .expect("not cancelled");
    let seen = seen.into_inner().expect("no panics while held");
    assert_eq!(seen.len(), 9, "40×40 is 3×3 tiles of 16");
    assert!(seen.contains(&1.0));

    // Cancelling from the progress callback (as Ctrl-C would, mid-render).
    let cancel = AtomicBool::new(false);
    let stop = |_: f32| cancel.store(true, Ordering::Relaxed);
    let r = render(&scene, &RenderOptions { threads: Some(1) }, &stop, &cancel);
    assert_eq!(r.err(), Some(Cancelled));
}

#[test]
fn an_empty_scene_builds_no_accel_and_shows_the_environment() {
    let mut desc = showcase(8, 1);
    desc.objects.clear();
    desc.lights
        .retain(|l| matches!(l, scnc::ir::Light::Environment(_)));
    let scene = build(&desc, AccelKind::Bvh);
    assert!(scene.accel.is_none());
    assert!(scene.meshes.is_empty(), "unused meshes are not built");
    assert!(scene.lights.by_power.is_none());
    let (film, stats) = render_with(&scene, 1);
    assert_eq!(stats.shadow_rays, 0);
    assert!(film
        .pixels()
        .iter()
        .all(|&p| p == Vec3::new(0.1, 0.15, 0.2)));
}

#[test]
fn instances_share_one_mesh() {
    let scene = build(&showcase(8, 1), AccelKind::Bvh);
    // floor, ball (placed twice), crate, light panel.
    assert_eq!(scene.meshes.len(), 4);
    assert_eq!(scene.instances.len(), 5);
    assert_eq!(scene.instances[1].mesh, scene.instances[2].mesh);
}

#[test]
fn a_hundred_lights_trace_as_many_shadow_rays_as_one() {
    let mut desc = showcase(16, 1);
    desc.lights = vec![point_light(Vec3::new(0.0, 3.0, 0.0), 10.0)];
    let (_, one) = render_with(&build(&desc, AccelKind::Bvh), 2);
    desc.lights = (0..100)
        .map(|i| point_light(Vec3::new(i as f32 * 0.05 - 2.5, 3.0, 0.0), 0.1))
        .collect();
    let (film, hundred) = render_with(&build(&desc, AccelKind::Bvh), 2);
    // One pick per shading point either way; only which points face their picked light differs.
    let (a, b) = (one.shadow_rays as f64, hundred.shadow_rays as f64);
    assert!((a - b).abs() <= 0.05 * a, "{a} vs {b}");
    assert!(b <= hundred.camera_rays as f64);
    assert!(film.mean().max_element() > 0.0);
}
