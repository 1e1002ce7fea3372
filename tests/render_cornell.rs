//! The Cornell box of `shared/bench/scenes/gen.py` (exact geometry, camera, materials and
//! light), built as IR in Rust: a small render has the light where the camera sees it, the red
//! wall on the left, the green wall on the right, and soft shadows that differ between the one-
//! and four-thread renders by not a single bit.

mod render_common;

use glam::{Mat4, Vec3};
use render_common::*;
use scnc::bvh::AccelKind;
use scnc::ir::{InlineMesh, Mesh, MeshSource, SceneDesc};

fn inline(name: &str, positions: &[[f32; 3]], indices: &[[u32; 3]]) -> Mesh {
    Mesh {
        name: name.into(),
        source: MeshSource::Inline(Box::new(InlineMesh {
            positions: positions.iter().map(|&p| Vec3::from(p)).collect(),
            normals: Vec::new(),
            uvs: Vec::new(),
            indices: indices.to_vec(),
        })),
        span: span(),
        obj: Default::default(),
    }
}

const QUAD: [[u32; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

/// A block from its four top corners down to y = 0 (no bottom), as gen.py builds it.
fn block(name: &str, top: [[f32; 3]; 4]) -> Mesh {
    let mut positions = top.to_vec();
    positions.extend(top.iter().map(|t| [t[0], 0.0, t[2]]));
    let mut faces = vec![[0, 1, 2], [0, 2, 3]];
    for i in 0..4u32 {
        let j = (i + 1) % 4;
        faces.push([i, i + 4, j + 4]);
        faces.push([i, j + 4, j]);
    }
    inline(name, &positions, &faces)
}

pub fn cornell(size: u32, spp: u32) -> SceneDesc {
    let mut desc = empty_desc(
        camera(
            Vec3::new(278.0, 273.0, -800.0),
            Vec3::new(278.0, 273.0, 0.0),
            Vec3::Y,
            39.3077,
        ),
        settings(size, size, spp),
    );
    desc.meshes = vec![
        inline(
            "floor",
            &[
                [552.8, 0.0, 0.0],
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 559.2],
                [549.6, 0.0, 559.2],
            ],
            &QUAD,
        ),
        inline(
            "ceiling",
            &[
                [556.0, 548.8, 0.0],
                [556.0, 548.8, 559.2],
                [0.0, 548.8, 559.2],
                [0.0, 548.8, 0.0],
            ],
            &QUAD,
        ),
        inline(
            "back",
            &[
                [549.6, 0.0, 559.2],
                [0.0, 0.0, 559.2],
                [0.0, 548.8, 559.2],
                [556.0, 548.8, 559.2],
            ],
            &QUAD,
        ),
        inline(
            "left",
            &[
                [552.8, 0.0, 0.0],
                [549.6, 0.0, 559.2],
                [556.0, 548.8, 559.2],
                [556.0, 548.8, 0.0],
            ],
            &QUAD,
        ),
        inline(
            "right",
            &[
                [0.0, 0.0, 559.2],
                [0.0, 0.0, 0.0],
                [0.0, 548.8, 0.0],
                [0.0, 548.8, 559.2],
            ],
            &QUAD,
        ),
        block(
            "short",
            [
                [130.0, 165.0, 65.0],
                [82.0, 165.0, 225.0],
                [240.0, 165.0, 272.0],
                [290.0, 165.0, 114.0],
            ],
        ),
        block(
            "tall",
            [
                [423.0, 330.0, 247.0],
                [265.0, 330.0, 296.0],
                [314.0, 330.0, 456.0],
                [472.0, 330.0, 406.0],
            ],
        ),
        inline(
            "light",
            &[
                [343.0, 548.7, 227.0],
                [343.0, 548.7, 332.0],
                [213.0, 548.7, 332.0],
                [213.0, 548.7, 227.0],
            ],
            &QUAD,
        ),
    ];
    desc.materials = vec![
        phong("white", Vec3::new(0.725, 0.71, 0.68), 0.0, 1.0),
        phong("red", Vec3::new(0.63, 0.065, 0.05), 0.0, 1.0),
        phong("green", Vec3::new(0.14, 0.45, 0.091), 0.0, 1.0),
    ];
    let material = [0, 0, 0, 1, 2, 0, 0];
    desc.objects = (0..7)
        .map(|m| object(m, material[m as usize], Mat4::IDENTITY))
        .collect();
    let mut light = area_light(7, Mat4::IDENTITY, 1.0, false, 1);
    if let scnc::ir::Light::Area(a) = &mut light {
        a.radiance = Vec3::new(17.0, 12.0, 4.0);
    }
    desc.lights = vec![light];
    desc
}

#[test]
fn cornell_box_looks_like_the_cornell_box() {
    let scene = build(&cornell(32, 4), AccelKind::Bvh);
    assert_eq!(scene.triangle_count(), 2 * 5 + 10 * 2 + 2);
    let (film, stats) = render_with(&scene, 2);
    assert_eq!(film, render_with(&scene, 1).0);
    assert!(stats.shadow_rays > 0);
    // The light, seen from below through the opening at the top centre of the image.
    let top = film.get(16, 4);
    assert!(top == Vec3::new(17.0, 12.0, 4.0), "light pixel {top}");
    // Red wall on the image's left, green on its right, at mid height.
    let left = film.get(1, 16);
    let right = film.get(30, 16);
    assert!(left.x > 3.0 * left.y && left.x > 0.02, "left {left}");
    assert!(right.y > 1.5 * right.x && right.y > 0.02, "right {right}");
    // Direct lighting only: the ceiling, level with the downward-facing light, stays black,
    // while the back wall and most of the image are lit.
    assert_eq!(film.get(16, 0), Vec3::ZERO);
    assert!(
        film.get(16, 10).min_element() > 0.02,
        "back wall {}",
        film.get(16, 10)
    );
    let lit = film
        .pixels()
        .iter()
        .filter(|p| p.max_element() > 0.0)
        .count();
    assert!(lit > 32 * 32 * 6 / 10, "{lit} lit pixels");
}

/// Pixels whose footprint may see the area light take 16× the samples of a fixed-count render
/// (`render::emitter_pixels`): every pixel that shows the light is among them, pixels far from
/// it are not, they are a small share of the image, and the camera rays count them.
#[test]
fn pixels_that_may_see_the_light_take_more_samples() {
    use scnc::render::camera::PinholeCamera;
    use scnc::render::emitter_pixels::{EmitterPixels, SIDE_FACTOR};
    let size = 48;
    let scene = build(&cornell(size, 4), AccelKind::Bvh);
    let camera = PinholeCamera::new(&scene.camera, size, size);
    let marked = EmitterPixels::find(&scene, &camera, 2);
    assert_eq!(marked.factor(), SIDE_FACTOR);
    let boosted = marked.boosted();
    assert!(
        boosted > 0 && boosted < u64::from(size * size) / 20,
        "{boosted}"
    );
    let (film, stats) = render_with(&scene, 2);
    let per_boosted = 4 * SIDE_FACTOR * SIDE_FACTOR;
    assert_eq!(stats.emitter_pixels, (boosted, per_boosted));
    let extra = boosted * u64::from(per_boosted - 4);
    assert_eq!(stats.camera_rays, u64::from(size * size * 4) + extra);
    for y in 0..size {
        for x in 0..size {
            // The light (radiance 17, 12, 4) is the only thing this bright.
            if film.get(x, y).x > 1.0 {
                assert_eq!(
                    marked.factor_at(x, y),
                    SIDE_FACTOR,
                    "({x}, {y}) shows the light"
                );
            }
        }
    }
    // The floor at the bottom and the walls at mid height are far from the light.
    for (x, y) in [(24, 46), (2, 24), (45, 24)] {
        assert_eq!(marked.factor_at(x, y), 1, "({x}, {y})");
    }
    // One sample per pixel stays point-sampled, whatever the scene.
    assert_eq!(EmitterPixels::find(&scene, &camera, 1).boosted(), 0);
}

/// The cost pre-pass of `--tile K/N` counts the light pixels' extra samples: rows that cross
/// them cost more than the same rows of a one-sample render (whose pixels are not boosted);
/// the other rows cost the same.
#[test]
fn tile_costs_count_the_light_pixels() {
    use scnc::render::balance::row_costs;
    use scnc::render::camera::PinholeCamera;
    use scnc::render::emitter_pixels::EmitterPixels;
    let size = 48;
    let boosted = build(&cornell(size, 4), AccelKind::Bvh);
    let plain = build(&cornell(size, 1), AccelKind::Bvh);
    let (with, without) = (row_costs(&boosted), row_costs(&plain));
    let camera = PinholeCamera::new(&boosted.camera, size, size);
    let marked = EmitterPixels::find(&boosted, &camera, 2);
    let mut heavier = 0;
    for y in 0..size {
        let crosses = (0..size).any(|x| marked.factor_at(x, y) > 1);
        let (a, b) = (with[y as usize], without[y as usize]);
        if crosses {
            assert!(a > b, "row {y}: {a} vs {b}");
            heavier += 1;
        } else {
            assert_eq!(a, b, "row {y}");
        }
    }
    assert!(heavier > 0);
}
