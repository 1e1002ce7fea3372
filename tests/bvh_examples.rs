//! The BVH against the brute-force oracle on the meshes of every example scene, as the
//! renderer builds them (instancing, area-light geometry, built-in shapes, inline meshes):
//! seeded rays from inside and around each scene give the same closest hit and the same
//! any-hit answer. The BVH uses the watertight test and the oracle Möller–Trumbore, so a
//! differing hit is accepted only where the two tests may round differently: at the same
//! distance (a shared edge) or within a hair of an edge; such rays must be rare.

use glam::Vec3;
use scnc::assets::FsLoader;
use scnc::bvh::{Accel, AccelKind, Hit};
use scnc::compile::compile_file;
use scnc::geom::{Aabb, Ray};
use scnc::scene::{build, BuildOptions, Scene};

use scnc::testing::SplitMix64 as Rng;

/// A point uniform in the box.
fn in_box(rng: &mut Rng, b: &Aabb) -> Vec3 {
    let t = Vec3::new(rng.unit_f32(), rng.unit_f32(), rng.unit_f32());
    b.min + t * (b.max - b.min)
}

/// A uniform direction (rejection from the unit ball).
fn dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(rng.unit_f32(), rng.unit_f32(), rng.unit_f32()) * 2.0 - 1.0;
        if (1e-4..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

fn world_bounds(scene: &Scene) -> Aabb {
    scene.instances.iter().fold(Aabb::EMPTY, |b, inst| {
        let mesh = &scene.meshes[inst.mesh as usize];
        b.union(Aabb::from_points(&mesh.positions).transformed(&inst.world_from_object))
    })
}

fn scene_with(path: &str, accel: AccelKind) -> Scene {
    let loader = FsLoader::new();
    let compiled = compile_file(std::path::Path::new(path), &loader);
    let desc = compiled.scene.unwrap_or_else(|| panic!("{path} compiles"));
    let options = BuildOptions {
        accel,
        ..BuildOptions::default()
    };
    build(&desc, &loader, &options)
        .value
        .unwrap_or_else(|| panic!("{path} builds"))
}

fn near_edge(h: &Hit) -> bool {
    h.u.min(h.v).min(1.0 - h.u - h.v) < 1e-3
}

#[test]
fn bvh_equals_brute_force_on_every_example() {
    // The dense example has ~131k triangles: brute force over it costs too much per ray for a
    // test, so it gets fewer rays.
    for (path, rays) in [
        ("examples/cornell.scn", 4000),
        ("examples/showcase.scn", 1500),
        ("examples/include_demo.scn", 1500),
        ("examples/dense.scn", 60),
    ] {
        let fast = scene_with(path, AccelKind::Bvh);
        let slow = scene_with(path, AccelKind::None);
        let (Some(bvh), Some(oracle)): (Option<&Accel>, Option<&Accel>) =
            (fast.accel.as_ref(), slow.accel.as_ref())
        else {
            panic!("{path} has triangles");
        };
        let bounds = world_bounds(&fast);
        let grown = Aabb {
            min: bounds.min - 0.1 * bounds.extent(),
            max: bounds.max + 0.1 * bounds.extent(),
        };
        // Both tests round with the size of the coordinates, not with t: compare distances
        // to a tolerance relative to the scene's extent (rays have unit directions).
        let scale = bounds.extent().max_element();
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * scale + 1e-5 * b;
        let mut rng = Rng(0x5eed ^ rays as u64);
        let (mut hits, mut tolerated) = (0, 0);
        for _ in 0..rays {
            let origin = in_box(&mut rng, &grown);
            let ray = Ray::new(origin, dir(&mut rng));
            let (a, b) = (bvh.closest_hit(&ray), oracle.closest_hit(&ray));
            match (a, b) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    if (a.instance, a.prim) != (b.instance, b.prim) {
                        let same_t = close(a.t, b.t);
                        assert!(
                            same_t || near_edge(&a) || near_edge(&b),
                            "{path}: {a:?} vs {b:?} for {ray:?}"
                        );
                        tolerated += 1;
                    } else {
                        assert!(close(a.t, b.t), "{path}: t {} vs {}", a.t, b.t);
                    }
                }
                (None, None) => {}
                (a, b) => {
                    let h = a.or(b).expect("one side hit");
                    assert!(near_edge(&h), "{path}: only one side hit {h:?} for {ray:?}");
                    tolerated += 1;
                }
            }
            // Any-hit on a segment to a random point agrees with the oracle's closest hit.
            let target = in_box(&mut rng, &bounds);
            let seg = Ray::segment(origin, target - origin, 1.0);
            let closest = oracle.closest_hit(&seg);
            if bvh.any_hit(&seg) != closest.is_some() {
                assert!(
                    closest.is_none_or(|h| near_edge(&h)),
                    "{path}: any-hit disagrees for {seg:?}"
                );
                tolerated += 1;
            }
        }
        assert!(
            hits > rays / 10,
            "{path}: only {hits} of {rays} rays hit: the test sees nothing"
        );
        assert!(
            tolerated * 100 <= rays,
            "{path}: {tolerated} of {rays} rays needed the edge tolerance"
        );
    }
}
