//! The BVH against the brute-force oracle (`AccelKind::None`) on seeded random triangle soups,
//! grids and instanced scenes: same closest hit (instance, triangle, t) and same any-hit answer.
//!
//! With Möller–Trumbore in the BVH and identity instances both sides run the same arithmetic on
//! the same floats, so they must agree exactly. With the watertight test, or with instances whose
//! rays the BVH maps into object space, rounding differs: a disagreement is accepted only for a
//! ray that passes within a hair of a triangle edge (barycentric < 1e-4), and such rays must be
//! rare.

use glam::{Affine3A, Quat, Vec3};
use scnc::bvh::{Accel, AccelKind, Hit, Instance, MeshRef, Scratch, Simd, TriangleTest};
use scnc::geom::Ray;

use scnc::testing::SplitMix64 as Rng;

/// A uniform direction (rejection from the unit ball).
fn dir(rng: &mut Rng) -> Vec3 {
    loop {
        let v = rng.vec3(-1.0, 1.0);
        if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

struct Mesh {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

impl Mesh {
    fn as_ref(&self) -> MeshRef<'_> {
        MeshRef {
            positions: &self.positions,
            triangles: &self.triangles,
        }
    }
}

/// `n` independent triangles: centres uniform in a cube of side `spread`, edges up to `size`.
fn soup(rng: &mut Rng, n: usize, spread: f32, size: f32) -> Mesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for i in 0..n as u32 {
        let c = rng.vec3(-spread / 2.0, spread / 2.0);
        for _ in 0..3 {
            positions.push(c + rng.vec3(-size, size));
        }
        triangles.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    Mesh {
        positions,
        triangles,
    }
}

/// A bumpy `n × n` grid of quads in the xz-plane over [-1, 1]², two triangles per quad sharing
/// edges and vertices: the case where cracks would show.
fn grid(rng: &mut Rng, n: u32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (
                2.0 * i as f32 / n as f32 - 1.0,
                2.0 * j as f32 / n as f32 - 1.0,
            );
            positions.push(Vec3::new(x, 0.1 * rng.range_f32(-1.0, 1.0), z));
        }
    }
    let mut triangles = Vec::new();
    let at = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    Mesh {
        positions,
        triangles,
    }
}

fn random_instance(rng: &mut Rng, mesh: u32) -> Instance {
    let axis = dir(rng);
    let rot = Quat::from_axis_angle(axis, rng.range_f32(0.0, std::f32::consts::TAU));
    let scale = Vec3::new(
        rng.range_f32(0.3, 2.0),
        rng.range_f32(0.3, 2.0),
        rng.range_f32(0.3, 2.0),
    );
    let t = rng.vec3(-3.0, 3.0);
    Instance::new(
        mesh,
        Affine3A::from_scale_rotation_translation(scale, rot, t),
    )
}

/// A point on a random triangle of the scene, in world space.
fn random_surface_point(rng: &mut Rng, meshes: &[Mesh], instances: &[Instance]) -> Vec3 {
    let inst = &instances[rng.below(instances.len())];
    let mesh = &meshes[inst.mesh as usize];
    let t = mesh.triangles[rng.below(mesh.triangles.len())];
    let (mut u, mut v) = (rng.unit_f32(), rng.unit_f32());
    if u + v > 1.0 {
        (u, v) = (1.0 - u, 1.0 - v);
    }
    let p = |k: usize| mesh.positions[t[k] as usize];
    let local = p(0) + u * (p(1) - p(0)) + v * (p(2) - p(0));
    inst.world_from_object.transform_point3(local)
}

fn random_ray(rng: &mut Rng, extent: f32, segment: bool, aim: Vec3) -> Ray {
    let origin = rng.vec3(-extent, extent);
    // Half the rays aim at a surface point (so they mostly hit), half anywhere.
    let target = if rng.unit_f32() < 0.5 {
        aim
    } else {
        rng.vec3(-extent / 2.0, extent / 2.0)
    };
    let dir = (target - origin) * rng.range_f32(0.2, 3.0);
    if segment {
        Ray::segment(origin, dir, rng.range_f32(0.0, 1.5))
    } else {
        Ray::new(origin, dir)
    }
}

fn near_edge(h: &Hit) -> bool {
    h.u.min(h.v).min(1.0 - h.u - h.v) < 1e-4
}

/// Equal hit distances: the hit points agree to 1e-5 of the distances involved (origin from the
/// world origin and hit from the ray origin), so a hit close to a far-away origin is not held
/// to a relative precision that float coordinates cannot give.
/// For a hit on the same triangle the tolerance grows as the ray grazes it (t is then
/// ill-conditioned for any method): `cos` is the cosine between ray and triangle normal.
fn same_t(a: f32, b: f32, ray: &Ray, cos: f32) -> bool {
    let len = ray.dir.length();
    let scale = ray.origin.length() + a.abs().max(b.abs()) * len + 1.0;
    (a - b).abs() * len <= 1e-5 * scale / cos.abs().max(1e-3)
}

fn cos_to_normal(meshes: &[Mesh], instances: &[Instance], h: &Hit, ray: &Ray) -> f32 {
    let inst = &instances[h.instance as usize];
    let mesh = &meshes[inst.mesh as usize];
    let t = mesh.triangles[h.prim as usize];
    let p = |k: usize| {
        inst.world_from_object
            .transform_point3(mesh.positions[t[k] as usize])
    };
    let n = (p(1) - p(0)).cross(p(2) - p(0));
    n.normalize().dot(ray.dir.normalize())
}

/// The instruction sets this CPU can run the queries on (the portable one always).
fn paths() -> Vec<Simd> {
    let mut probe = Accel::build(&[], &[], AccelKind::Bvh);
    [Simd::Portable, Simd::Avx2, Simd::Avx512]
        .into_iter()
        .filter(|&s| probe.force_simd(s))
        .collect()
}

/// [`compare_on`] for every instruction set this CPU runs; the most excused of them.
fn compare(
    meshes: &[Mesh],
    instances: &[Instance],
    test: TriangleTest,
    seed: u64,
    rays: usize,
) -> usize {
    paths()
        .into_iter()
        .map(|simd| compare_on(simd, meshes, instances, test, seed, rays))
        .max()
        .unwrap_or(0)
}

/// Compares the BVH, its queries forced onto `simd`, with the oracle on `rays` random rays;
/// returns the number of rays whose disagreement was excused by passing near an edge (and
/// fails on any other disagreement).
fn compare_on(
    simd: Simd,
    meshes: &[Mesh],
    instances: &[Instance],
    test: TriangleTest,
    seed: u64,
    rays: usize,
) -> usize {
    let refs: Vec<MeshRef<'_>> = meshes.iter().map(Mesh::as_ref).collect();
    let oracle = Accel::build(&refs, instances, AccelKind::None);
    let mut bvh = Accel::build_with(&refs, instances, AccelKind::Bvh, test);
    assert!(bvh.force_simd(simd), "{simd:?} was detected");
    assert_eq!(bvh.simd(), simd);
    assert_eq!(bvh.check_invariants(&refs), Ok(()));
    let mut rng = Rng(seed);
    let mut excused = 0;
    let mut hits = 0;
    let mut scratch = Scratch::new();
    for i in 0..rays {
        let aim = random_surface_point(&mut rng, meshes, instances);
        let ray = random_ray(&mut rng, 4.0, i % 2 == 1, aim);
        let want = oracle.closest_hit(&ray);
        let got = bvh.closest_hit(&ray);
        // The caller's stacks give the same answers, bit for bit.
        assert_eq!(
            hit_bits(bvh.closest_hit_with(&ray, &mut scratch)),
            hit_bits(got),
            "{simd:?}, ray {i}: closest_hit_with"
        );
        assert_eq!(
            bvh.any_hit_with(&ray, &mut scratch),
            bvh.any_hit(&ray),
            "{simd:?}, ray {i}: any_hit_with"
        );
        hits += want.is_some() as usize;
        assert_eq!(
            bvh.any_hit(&ray),
            got.is_some(),
            "any-hit vs closest-hit, ray {i}: {ray:?}"
        );
        let agree = match (want, got) {
            (None, None) => true,
            (Some(w), Some(g)) => {
                let cos = cos_to_normal(meshes, instances, &w, &ray);
                (w.instance == g.instance && w.prim == g.prim && same_t(w.t, g.t, &ray, cos))
                    || same_t(w.t, g.t, &ray, 1.0)
            }
            _ => false,
        };
        let any_agree = oracle.any_hit(&ray) == bvh.any_hit(&ray);
        if !agree || !any_agree {
            let explained =
                want.is_some_and(|h| near_edge(&h)) || got.is_some_and(|h| near_edge(&h));
            assert!(
                explained,
                "{simd:?}, ray {i} {ray:?}: oracle {want:?}, bvh {got:?}"
            );
            excused += 1;
        }
    }
    assert!(
        hits > rays / 5,
        "too few rays hit ({hits} of {rays}): the test would prove little"
    );
    excused
}

const TESTS: [TriangleTest; 2] = [TriangleTest::MollerTrumbore, TriangleTest::Watertight];

#[test]
fn soups_of_several_sizes_and_shapes_match_brute_force_exactly_with_moller_trumbore() {
    let mut rng = Rng(1);
    // (triangles, spread, size): sparse big triangles, dense small ones, long thin slivers.
    for (k, &(n, spread, size)) in [
        (1, 2.0, 1.0),
        (7, 4.0, 1.0),
        (100, 4.0, 0.5),
        (3000, 6.0, 0.2),
        (2000, 6.0, 2.0),
    ]
    .iter()
    .enumerate()
    {
        let meshes = [soup(&mut rng, n, spread, size)];
        let inst = [Instance::new(0, Affine3A::IDENTITY)];
        let excused = compare(
            &meshes,
            &inst,
            TriangleTest::MollerTrumbore,
            100 + k as u64,
            3000,
        );
        assert_eq!(
            excused, 0,
            "soup {k}: identical arithmetic must agree exactly"
        );
    }
}

#[test]
fn soups_match_brute_force_with_the_watertight_test() {
    let mut rng = Rng(2);
    for (k, &(n, size)) in [(50, 1.0), (2000, 0.3)].iter().enumerate() {
        let meshes = [soup(&mut rng, n, 6.0, size)];
        let inst = [Instance::new(0, Affine3A::IDENTITY)];
        let excused = compare(
            &meshes,
            &inst,
            TriangleTest::Watertight,
            200 + k as u64,
            4000,
        );
        assert!(excused <= 4, "soup {k}: {excused} near-edge disagreements");
    }
}

#[test]
fn grids_match_brute_force() {
    let mut rng = Rng(3);
    let meshes = [grid(&mut rng, 40)];
    let inst = [Instance::new(0, Affine3A::IDENTITY)];
    for (k, test) in TESTS.into_iter().enumerate() {
        let excused = compare(&meshes, &inst, test, 300 + k as u64, 4000);
        assert!(excused <= 8, "{test:?}: {excused} near-edge disagreements");
    }
}

#[test]
fn rotated_and_scaled_instances_match_brute_force() {
    let mut rng = Rng(4);
    let meshes = [
        soup(&mut rng, 300, 2.0, 0.3),
        grid(&mut rng, 10),
        soup(&mut rng, 5, 1.0, 1.0),
    ];
    let mut instances: Vec<Instance> = (0..12).map(|i| random_instance(&mut rng, i % 3)).collect();
    instances.push(Instance::new(1, Affine3A::IDENTITY));
    for (k, test) in TESTS.into_iter().enumerate() {
        let excused = compare(&meshes, &instances, test, 400 + k as u64, 5000);
        assert!(excused <= 10, "{test:?}: {excused} near-edge disagreements");
    }
}

/// Every field of a hit, as bits.
fn hit_bits(h: Option<Hit>) -> Option<(u32, u32, u32, u32, u32)> {
    h.map(|h| {
        (
            h.t.to_bits(),
            h.u.to_bits(),
            h.v.to_bits(),
            h.instance,
            h.prim,
        )
    })
}

#[test]
fn every_instruction_set_gives_the_same_bits() {
    let paths = paths();
    if paths.len() < 2 {
        eprintln!("only the portable path runs on this CPU: nothing to compare");
        return;
    }
    let mut rng = Rng(6);
    // A dense soup (deep tree, full leaves), a grid (rays through shared edges and vertices),
    // and instanced copies (the top level and object-space rays).
    let meshes = [soup(&mut rng, 3000, 4.0, 0.3), grid(&mut rng, 30)];
    let mut instances: Vec<Instance> = (0..6).map(|i| random_instance(&mut rng, i % 2)).collect();
    instances.push(Instance::new(0, Affine3A::IDENTITY));
    let refs: Vec<MeshRef<'_>> = meshes.iter().map(Mesh::as_ref).collect();
    for test in TESTS {
        for inst in [&instances[6..], &instances[..]] {
            let accels: Vec<Accel> = paths
                .iter()
                .map(|&simd| {
                    let mut a = Accel::build_with(&refs, inst, AccelKind::Bvh, test);
                    assert!(a.force_simd(simd));
                    a
                })
                .collect();
            let mut hits = 0;
            for i in 0..6000 {
                // Every third ray aimed at a vertex: ties between the triangles around it.
                let aim = if i % 3 == 0 {
                    let p = &inst[rng.below(inst.len())];
                    let m = &meshes[p.mesh as usize];
                    let v = m.positions[rng.below(m.positions.len())];
                    p.world_from_object.transform_point3(v)
                } else {
                    random_surface_point(&mut rng, &meshes, inst)
                };
                let mut ray = random_ray(&mut rng, 4.0, i % 2 == 1, aim);
                if i % 5 == 0 {
                    ray.t_max = 3.0;
                }
                let want = hit_bits(accels[0].closest_hit(&ray));
                let blocked = accels[0].any_hit(&ray);
                hits += usize::from(want.is_some());
                for (a, simd) in accels.iter().zip(&paths).skip(1) {
                    assert_eq!(
                        hit_bits(a.closest_hit(&ray)),
                        want,
                        "{simd:?} {test:?} ray {i}"
                    );
                    assert_eq!(a.any_hit(&ray), blocked, "{simd:?} {test:?} ray {i}");
                }
            }
            assert!(hits > 1500, "too few hits to test anything: {hits}");
        }
    }
}

#[test]
fn instances_report_their_own_index_and_share_the_mesh() {
    let mut rng = Rng(5);
    let meshes = [soup(&mut rng, 1, 0.0, 1.0)];
    let tri = &meshes[0].positions;
    let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
    let far = Vec3::new(100.0, 0.0, 0.0);
    let instances = [
        Instance::new(0, Affine3A::IDENTITY),
        Instance::new(0, Affine3A::from_translation(far)),
    ];
    let refs: Vec<MeshRef<'_>> = meshes.iter().map(Mesh::as_ref).collect();
    let bvh = Accel::build(&refs, &instances, AccelKind::Bvh);
    let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize();
    for (i, offset) in [Vec3::ZERO, far].into_iter().enumerate() {
        let ray = Ray::new(centroid + offset + 2.0 * normal, -normal);
        let hit = bvh
            .closest_hit(&ray)
            .expect("ray through the centroid hits");
        assert_eq!(hit.instance, i as u32);
        assert!((hit.t - 2.0).abs() < 1e-4, "t is in world units: {}", hit.t);
    }
    // One mesh, placed twice, is stored once.
    assert_eq!(bvh.stats().triangles, 1);
}

#[test]
fn merged_identity_instances_report_the_right_instance() {
    // Meshes 0..3 are placed once each with the identity (merged into one tree); mesh 3 is
    // placed three times (its own tree, shared); instance order is mixed on purpose.
    let mut rng = Rng(6);
    let meshes = [
        soup(&mut rng, 200, 4.0, 0.3),
        grid(&mut rng, 8),
        soup(&mut rng, 50, 3.0, 0.6),
        soup(&mut rng, 40, 1.5, 0.4),
    ];
    let instances = [
        random_instance(&mut rng, 3),
        Instance::new(2, Affine3A::IDENTITY),
        Instance::new(3, Affine3A::IDENTITY),
        Instance::new(0, Affine3A::IDENTITY),
        random_instance(&mut rng, 3),
        Instance::new(1, Affine3A::IDENTITY),
    ];
    for (k, test) in TESTS.into_iter().enumerate() {
        let excused = compare(&meshes, &instances, test, 600 + k as u64, 5000);
        assert!(excused <= 10, "{test:?}: {excused} near-edge disagreements");
    }
}
