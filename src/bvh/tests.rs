//! Degenerate input never panics and still gives the oracle's answers: empty scenes, zero-area,
//! NaN/inf and out-of-range triangles, huge and tiny coordinates, coincident centroids, instances
//! of missing meshes. (The random-soup oracle tests live in `tests/bvh_oracle.rs`.)

use glam::{Affine3A, Vec3};

use super::*;

fn identity(mesh: u32) -> Instance {
    Instance::new(mesh, Affine3A::IDENTITY)
}

/// Builds both kinds, checks the invariants, and compares answers on a fan of rays through
/// `centre` from every side.
fn agrees_with_oracle(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    instances: &[Instance],
    centre: Vec3,
    scale: f32,
) -> Accel {
    let meshes = [MeshRef {
        positions,
        triangles,
    }];
    let oracle = Accel::build(&meshes, instances, AccelKind::None);
    let bvh = Accel::build_with(
        &meshes,
        instances,
        AccelKind::Bvh,
        TriangleTest::MollerTrumbore,
    );
    assert_eq!(bvh.check_invariants(&meshes), Ok(()));
    for i in 0..200 {
        let a = i as f32 * 0.7;
        let dir = Vec3::new(a.cos(), (a * 1.3).sin(), (a * 0.4).cos() + 0.1);
        let ray = Ray::new(
            centre - 3.0 * scale * dir + Vec3::splat(scale * 0.01 * (i % 7) as f32),
            dir * scale,
        );
        let (w, g) = (oracle.closest_hit(&ray), bvh.closest_hit(&ray));
        // Same distance; a different triangle only as a tie at exactly that distance.
        assert_eq!(w.map(|h| h.t), g.map(|h| h.t), "ray {i}");
        assert_eq!(oracle.any_hit(&ray), bvh.any_hit(&ray), "ray {i}");
    }
    bvh
}

#[test]
fn empty_scene_builds_nothing_and_misses() {
    for (meshes, instances) in [
        (vec![], vec![]),
        (
            vec![MeshRef {
                positions: &[],
                triangles: &[],
            }],
            vec![identity(0)],
        ),
    ] {
        let bvh = Accel::build(&meshes, &instances, AccelKind::Bvh);
        assert_eq!(bvh.stats().nodes, 0);
        assert_eq!(bvh.stats().triangles, 0);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        assert!(bvh.closest_hit(&ray).is_none() && !bvh.any_hit(&ray));
        assert_eq!(bvh.check_invariants(&meshes), Ok(()));
    }
}

#[test]
fn unused_meshes_are_not_built() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let meshes = [MeshRef {
        positions: &p,
        triangles: &[[0, 1, 2]],
    }];
    let bvh = Accel::build(&meshes, &[], AccelKind::Bvh);
    assert_eq!(bvh.stats(), AccelStats::default());
}

#[test]
fn bad_triangles_are_skipped() {
    let p = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(f32::NAN, 0.0, 0.0),
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::new(0.5, 0.5, 0.0),
    ];
    let tris = [
        [0, 1, 2],  // good
        [0, 1, 3],  // NaN vertex
        [0, 4, 2],  // infinite vertex
        [0, 1, 99], // index out of range
        [0, 0, 1],  // zero area
        [0, 2, 5],  // zero area: collinear
        [1, 2, 5],
    ];
    let bvh = agrees_with_oracle(&p, &tris, &[identity(0)], Vec3::ZERO, 1.0);
    assert_eq!(
        bvh.stats().triangles,
        4,
        "three triangles with bad vertices are left out"
    );
    assert!(bvh
        .closest_hit(&Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z))
        .is_some());
}

#[test]
fn huge_and_tiny_coordinates() {
    for scale in [1e30f32, 1e-30, 1e18, 1e-18] {
        let p: Vec<Vec3> = (0..60)
            .map(|i| {
                let a = i as f32;
                scale * Vec3::new((a * 0.37).sin(), (a * 0.71).cos(), (a * 0.13).sin())
            })
            .collect();
        let tris: Vec<[u32; 3]> = (0..20).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        agrees_with_oracle(&p, &tris, &[identity(0)], Vec3::ZERO, scale);
        // The watertight kind must not panic either.
        let meshes = [MeshRef {
            positions: &p,
            triangles: &tris,
        }];
        let wt = Accel::build(&meshes, &[identity(0)], AccelKind::Bvh);
        assert_eq!(wt.check_invariants(&meshes), Ok(()));
        let _ = wt.closest_hit(&Ray::new(Vec3::splat(-2.0 * scale), Vec3::splat(scale)));
    }
}

#[test]
fn coincident_centroids_fall_back_to_median_splits() {
    // 1000 copies of rotated triangles around the same centroid: SAH cannot separate them.
    let mut p = Vec::new();
    let mut tris = Vec::new();
    for i in 0..1000u32 {
        let a = i as f32 * 0.01;
        let (c, s) = (a.cos(), a.sin());
        let q = [
            Vec3::new(c, s, 0.0),
            Vec3::new(-s, c, 0.3),
            -Vec3::new(c, s, 0.0) - Vec3::new(-s, c, 0.3),
        ];
        p.extend_from_slice(&q);
        tris.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let bvh = agrees_with_oracle(&p, &tris, &[identity(0)], Vec3::ZERO, 1.0);
    let s = bvh.stats();
    assert_eq!(s.triangles, 1000);
    assert!(s.leaves >= 1000 / MAX_LEAF as usize);
}

#[test]
fn instances_of_missing_meshes_and_bad_transforms_are_skipped() {
    let p = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let t = [[0, 1, 2]];
    let nan = Instance {
        mesh: 0,
        world_from_object: Affine3A::from_translation(Vec3::NAN),
        object_from_world: Affine3A::from_translation(Vec3::NAN),
    };
    let meshes = [MeshRef {
        positions: &p,
        triangles: &t,
    }];
    let bvh = Accel::build(
        &meshes,
        &[Instance::new(7, Affine3A::IDENTITY), nan, identity(0)],
        AccelKind::Bvh,
    );
    assert_eq!(bvh.check_invariants(&meshes), Ok(()));
    let hit = bvh
        .closest_hit(&Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z))
        .expect("hits the good instance");
    assert_eq!(hit.instance, 2);
}

#[test]
fn non_finite_rays_miss() {
    let p = [
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let meshes = [MeshRef {
        positions: &p,
        triangles: &[[0, 1, 2]],
    }];
    let bvh = Accel::build(&meshes, &[identity(0)], AccelKind::Bvh);
    for ray in [
        Ray::new(Vec3::new(0.0, 0.0, f32::NAN), -Vec3::Z),
        Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, f32::NAN, -1.0)),
        Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO),
        Ray::segment(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z, f32::NAN),
    ] {
        assert!(
            bvh.closest_hit(&ray).is_none() && !bvh.any_hit(&ray),
            "{ray:?}"
        );
    }
    // A NaN or an infinity in any one coordinate of the origin or the direction (the
    // finiteness test is one vector compare per vector: every lane must count), on a ray
    // that hits when that coordinate is finite.
    let (o, d) = (Vec3::new(0.1, 0.1, 1.0), Vec3::new(0.0, 0.0, -1.0));
    assert!(bvh.closest_hit(&Ray::new(o, d)).is_some());
    for axis in 0..3 {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (mut o2, mut d2) = (o, d);
            o2[axis] = bad;
            d2[axis] = bad;
            for ray in [Ray::new(o2, d), Ray::new(o, d2)] {
                assert!(
                    bvh.closest_hit(&ray).is_none() && !bvh.any_hit(&ray),
                    "{ray:?}"
                );
            }
        }
    }
}

#[test]
fn build_is_the_same_whatever_the_thread_count() {
    let mut p = Vec::new();
    let mut tris = Vec::new();
    for i in 0..40_000u32 {
        let a = i as f32;
        let c = Vec3::new((a * 0.123).sin(), (a * 0.0457).cos(), (a * 0.0311).sin()) * 10.0;
        p.extend_from_slice(&[
            c,
            c + Vec3::new(0.1, 0.0, 0.02),
            c + Vec3::new(0.0, 0.1, 0.05),
        ]);
        tris.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let meshes = [MeshRef {
        positions: &p,
        triangles: &tris,
    }];
    let build = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        pool.install(
            || match Accel::build(&meshes, &[identity(0)], AccelKind::Bvh) {
                Accel::Bvh(b) => {
                    // One identity instance: its mesh is the merged group, the last BVH.
                    let m = b.meshes.last().expect("the merged group always exists");
                    assert_eq!(m.triangle_count(), 40_000);
                    (m.tree.nodes.clone(), m.ids.clone())
                }
                Accel::None(_) => unreachable!("asked for a BVH"),
            },
        )
    };
    assert_eq!(build(1), build(4));
}

#[test]
fn instances_cost_records_not_copies() {
    // One small mesh (a fan of 16 triangles) placed 2,000 and then 20,000 times.
    let mut positions = vec![Vec3::ZERO];
    let mut triangles = Vec::new();
    for i in 0..17u32 {
        let a = i as f32 * 0.3;
        positions.push(Vec3::new(a.cos(), a.sin(), 0.1 * a));
        if i > 0 {
            triangles.push([0, i, i + 1]);
        }
    }
    let meshes = [MeshRef {
        positions: &positions,
        triangles: &triangles,
    }];
    let placed = |n: usize| -> Vec<Instance> {
        (0..n)
            .map(|i| {
                let at = Vec3::new((i % 150) as f32 * 3.0, 0.0, (i / 150) as f32 * 3.0);
                Instance::new(0, Affine3A::from_translation(at))
            })
            .collect()
    };
    let few = Accel::build(&meshes, &placed(2_000), AccelKind::Bvh).stats();
    let many = Accel::build(&meshes, &placed(20_000), AccelKind::Bvh).stats();
    // The mesh is stored once however often it is placed.
    assert_eq!(few.triangles, triangles.len());
    assert_eq!(many.triangles, triangles.len());
    // What grows is the top level only, and by a record's worth per placement.
    assert_eq!(
        many.bytes - many.instance_bytes,
        few.bytes - few.instance_bytes
    );
    let per = (many.instance_bytes - few.instance_bytes) as f64 / 18_000.0;
    assert!(per < 256.0, "{per} bytes per placement");
    let per_many = many.instance_bytes as f64 / 20_000.0;
    assert!(per_many < 256.0, "{per_many} bytes per placement");
    // Brute force, by contrast, copies every triangle per placement.
    let brute = Accel::build(&meshes, &placed(2_000), AccelKind::None).stats();
    assert_eq!(brute.triangles, 2_000 * triangles.len());
}
