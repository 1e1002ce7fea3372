//! `scene::build_cached` (issue 6): the same scene as `scene::build`, rebuilding only what an
//! edit changed: meshes by source and content hash, the BVH by meshes and transforms.

use std::sync::atomic::AtomicBool;

use scnc::assets::{Loader, MemLoader};
use scnc::compile::compile_source;
use scnc::render::{self, RenderOptions};
use scnc::scene::cache::content_hash;
use scnc::scene::{self, BuildCache, BuildOptions, CacheReport, Scene};

const OBJ: &str = "v -2 -1 0\nv 2 -1 0\nv 0 2 0\nf 1 2 3\n";

fn text(eye_y: f32, shift_z: f32) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, {eye_y}, -4)  target (0, 0, 0)  up (0, 1, 0)  fov 40deg }}
material white = phong {{ diffuse rgb(0.8, 0.8, 0.8)  specular 0 }}
mesh ball = sphere {{ radius 1  segments 12 }}
mesh tri = obj(\"meshes/tri.obj\")
object ball {{ material white }}
object tri {{ material white  transform {{ translate (0, 0, {shift_z}) }} }}
light key = point {{ position (2, 4, -3)  intensity rgb(30, 30, 30) }}
render {{ resolution 24 x 16  samples 1 }}
"
    )
}

fn loader(obj: &str) -> MemLoader {
    let mut l = MemLoader::new();
    l.insert("meshes/tri.obj", obj.as_bytes());
    l
}

/// Builds `text` with or without a cache; the scene and, with a cache, its report.
fn build(text: &str, loader: &MemLoader, cache: Option<&mut BuildCache>) -> Scene {
    let compiled = compile_source("s.scn", text, loader);
    let desc = compiled.scene.expect("the test scene compiles");
    let opts = BuildOptions::default();
    match cache {
        Some(c) => scene::build_cached(&desc, loader, &opts, c),
        None => scene::build(&desc, loader, &opts),
    }
    .value
    .expect("the test scene builds")
}

fn image(scene: &Scene) -> Vec<glam::Vec3> {
    let (film, _) = render::render(
        scene,
        &RenderOptions::default(),
        &|_| {},
        &AtomicBool::new(false),
    )
    .expect("not cancelled");
    film.pixels().to_vec()
}

fn report(loaded: usize, reused: usize, accel_built: bool) -> CacheReport {
    CacheReport {
        meshes_loaded: loaded,
        meshes_reused: reused,
        accel_built,
        environment_loaded: false,
        ..CacheReport::default()
    }
}

#[test]
fn cached_builds_render_the_same_image_as_plain_builds() {
    let l = loader(OBJ);
    let mut cache = BuildCache::new();
    for (eye, shift) in [(1.0, 1.0), (1.5, 1.0), (1.5, 2.0)] {
        let cached = build(&text(eye, shift), &l, Some(&mut cache));
        let plain = build(&text(eye, shift), &l, None);
        assert_eq!(image(&cached), image(&plain), "eye {eye}, shift {shift}");
        cache.recycle(cached);
    }
}

#[test]
fn only_what_changed_is_rebuilt() {
    let l = loader(OBJ);
    let mut cache = BuildCache::new();
    let s = build(&text(1.0, 1.0), &l, Some(&mut cache));
    assert_eq!(*cache.report(), report(2, 0, true));
    assert_eq!(cache.report().rebuilt(), ["meshes", "bvh"]);
    cache.recycle(s);

    // Camera edit: nothing reloaded, BVH reused.
    let s = build(&text(2.0, 1.0), &l, Some(&mut cache));
    assert_eq!(*cache.report(), report(0, 2, false));
    assert!(cache.report().rebuilt().is_empty());
    cache.recycle(s);

    // Transform edit: meshes reused, BVH rebuilt.
    let s = build(&text(2.0, 1.5), &l, Some(&mut cache));
    assert_eq!(*cache.report(), report(0, 2, true));
    cache.recycle(s);

    // The OBJ's content changed: it alone is reloaded, and the BVH rebuilt.
    let edited = OBJ.replace("v 0 2 0", "v 0 3 0");
    let l2 = loader(&edited);
    let new_hash = content_hash(edited.as_bytes());
    cache.retain_current(|_| Some(new_hash));
    let s = build(&text(2.0, 1.5), &l2, Some(&mut cache));
    assert_eq!(*cache.report(), report(1, 1, true));
    assert_eq!(cache.files_in_use(), [("meshes/tri.obj".into(), new_hash)]);
    cache.recycle(s);

    // Same content as before: kept, and not read at all (the loader records nothing).
    cache.retain_current(|_| Some(new_hash));
    let fresh = loader(&edited);
    let compiled = compile_source("s.scn", &text(2.0, 1.5), &fresh);
    let desc = compiled.scene.expect("compiles");
    let s = scene::build_cached(&desc, &fresh, &BuildOptions::default(), &mut cache)
        .value
        .expect("builds");
    assert_eq!(*cache.report(), report(0, 2, false));
    assert!(scnc::assets::Loader::recorded(&fresh).is_empty());
    cache.recycle(s);
}

#[test]
fn a_failed_build_gives_its_meshes_back() {
    let l = loader(OBJ);
    let mut cache = BuildCache::new();
    let s = build(&text(1.0, 1.0), &l, Some(&mut cache));
    cache.recycle(s);
    // A third mesh whose file is missing: the build fails after taking the other two.
    let broken = format!(
        "{}mesh gone = obj(\"missing.obj\")\nobject gone {{ material white }}\n",
        text(1.0, 1.0)
    );
    let compiled = compile_source("s.scn", &broken, &l);
    let desc = compiled.scene.expect("the checker does not read files");
    let r = scene::build_cached(&desc, &l, &BuildOptions::default(), &mut cache);
    assert!(r.value.is_none());
    assert_eq!(cache.report().meshes_reused, 2);
    let s = build(&text(1.0, 1.0), &l, Some(&mut cache));
    assert_eq!(cache.report().meshes_reused, 2);
    cache.recycle(s);
}

/// A 4×2 PFM sky (little-endian colour), brightest in its first texel, times `gain`.
fn sky_pfm(gain: f32) -> Vec<u8> {
    let mut bytes = b"PF\n4 2\n-1.0\n".to_vec();
    for i in 0..8 {
        let v = gain * if i == 0 { 40.0 } else { 0.5 };
        for _ in 0..3 {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

fn sky_scene(eye_y: f32, intensity: f32) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, {eye_y}, -4)  target (0, 0, 0)  up (0, 1, 0)  fov 40deg }}
material white = phong {{ diffuse rgb(0.8, 0.8, 0.8)  specular 0 }}
mesh ball = sphere {{ radius 1  segments 12 }}
object ball {{ material white }}
light sky = environment {{ image(\"sky.pfm\")  intensity {intensity} }}
render {{ resolution 24 x 16  samples 1 }}
"
    )
}

#[test]
fn an_environment_map_is_read_once_while_its_file_and_settings_stay() {
    let mut l = MemLoader::new();
    l.insert("sky.pfm", sky_pfm(1.0));
    let mut cache = BuildCache::new();
    let s = build(&sky_scene(1.0, 1.0), &l, Some(&mut cache));
    assert!(cache.report().environment_loaded);
    assert_eq!(cache.report().rebuilt(), ["meshes", "bvh", "environment"]);
    let first = image(&s);
    cache.recycle(s);

    // Camera edit: the map (and its sampling table) is reused, the file not read again.
    let hash = content_hash(&sky_pfm(1.0));
    cache.retain_current(|_| Some(hash));
    assert_eq!(cache.files_in_use(), [("sky.pfm".into(), hash)]);
    let fresh = {
        let mut f = MemLoader::new();
        f.insert("sky.pfm", sky_pfm(1.0));
        f
    };
    let s = build(&sky_scene(1.5, 1.0), &fresh, Some(&mut cache));
    assert!(!cache.report().environment_loaded);
    assert!(cache.report().rebuilt().is_empty());
    assert!(fresh.recorded().is_empty(), "{:?}", fresh.recorded());
    assert_eq!(image(&s), image(&build(&sky_scene(1.5, 1.0), &l, None)));
    cache.recycle(s);

    // Intensity edit: loaded again (intensity is baked into the texels).
    let s = build(&sky_scene(1.5, 2.0), &l, Some(&mut cache));
    assert!(cache.report().environment_loaded);
    cache.recycle(s);

    // The file changed: loaded again, and the image follows the new content.
    let mut brighter = MemLoader::new();
    brighter.insert("sky.pfm", sky_pfm(2.0));
    let new_hash = content_hash(&sky_pfm(2.0));
    cache.retain_current(|_| Some(new_hash));
    let s = build(&sky_scene(1.0, 1.0), &brighter, Some(&mut cache));
    assert!(cache.report().environment_loaded);
    assert_ne!(image(&s), first);
    assert_eq!(
        image(&s),
        image(&build(&sky_scene(1.0, 1.0), &brighter, None))
    );
}

/// A 4 × 4 PNG with one grey level everywhere.
fn grey_png(level: u8) -> Vec<u8> {
    let img = image::GrayImage::from_pixel(4, 4, image::Luma([level]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("encodes");
    out.into_inner()
}

fn textured_scene(diffuse_texture: &str, specular: f32) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, 1, -4)  target (0, 0, 0)  up (0, 1, 0)  fov 40deg }}
texture wood = image(\"wood.png\") {{ filter trilinear }}
texture wood_flat = image(\"wood.png\") {{ filter nearest  wrap clamp }}
texture other = image(\"other.png\") {{ filter bilinear }}
material a = phong {{ diffuse {diffuse_texture}  specular {specular} }}
material b = phong {{ diffuse wood_flat  specular 0  shininess other }}
mesh ball = sphere {{ radius 1  segments 12 }}
object ball {{ material a }}
object ball {{ material b  transform {{ translate (2, 0, 0) }} }}
light key = point {{ position (2, 4, -3)  intensity 30 }}
render {{ resolution 24 x 16  samples 1 }}
"
    )
}

#[test]
fn textures_are_loaded_once_and_a_material_edit_does_not_reload_them() {
    let files = |wood: u8| {
        let mut l = MemLoader::new();
        l.insert("wood.png", grey_png(wood));
        l.insert("other.png", grey_png(10));
        l
    };
    let mut cache = BuildCache::new();
    // `wood.png` is named by two textures (one trilinear): one load, with its pyramid.
    let s = build(&textured_scene("wood", 0.0), &files(200), Some(&mut cache));
    assert_eq!(cache.report().textures_loaded, 2);
    assert!(cache.report().rebuilt().contains(&"textures"));
    let first = image(&s);
    let mut files_in_use = cache.files_in_use();
    files_in_use.sort();
    let (wood, other) = (content_hash(&grey_png(200)), content_hash(&grey_png(10)));
    assert_eq!(
        files_in_use,
        [("other.png".into(), other), ("wood.png".into(), wood)]
    );
    cache.recycle(s);

    // A material edit: both textures come from the cache; no image file is read.
    cache.retain_current(|p| Some(if p.ends_with("wood.png") { wood } else { other }));
    let fresh = files(200);
    let s = build(&textured_scene("wood", 0.3), &fresh, Some(&mut cache));
    assert_eq!(
        (
            cache.report().textures_loaded,
            cache.report().textures_reused
        ),
        (0, 2)
    );
    assert!(!scnc::assets::Loader::recorded(&fresh)
        .iter()
        .any(|p| p.extension().is_some_and(|e| e == "png")));
    let plain = build(&textured_scene("wood", 0.3), &fresh, None);
    assert_eq!(image(&s), image(&plain));
    cache.recycle(s);

    // The image changed on disk: it alone is reloaded, and the picture follows it.
    let darker = content_hash(&grey_png(60));
    cache.retain_current(|p| {
        Some(if p.ends_with("wood.png") {
            darker
        } else {
            other
        })
    });
    let s = build(&textured_scene("wood", 0.0), &files(60), Some(&mut cache));
    assert_eq!(
        (
            cache.report().textures_loaded,
            cache.report().textures_reused
        ),
        (1, 1)
    );
    assert_ne!(image(&s), first);
    cache.recycle(s);
}

/// The diffuse colour of the first material an OBJ part brought (after the scene's own).
fn part_diffuse(scene: &Scene) -> glam::Vec3 {
    match scene.materials.last().map(|m| m.diffuse) {
        Some(scnc::ir::ColorInput::Constant(c)) => c,
        other => panic!("a constant diffuse: {other:?}"),
    }
}

#[test]
fn an_mtl_edit_reloads_its_obj_and_an_unchanged_one_does_not() {
    let obj = "mtllib tri.mtl\nv -2 -1 0\nv 2 -1 0\nv 0 2 0\nusemtl paint\nf 1 2 3\n";
    let files = |kd: &str| {
        let mut l = loader(obj);
        l.insert(
            "meshes/tri.mtl",
            format!("newmtl paint\nKd {kd}\n").as_bytes(),
        );
        l
    };
    let hashes = |l: &MemLoader| {
        let h = |p: &str| {
            l.read(std::path::Path::new(p))
                .map(|b| content_hash(&b))
                .ok()
        };
        (h("meshes/tri.obj"), h("meshes/tri.mtl"))
    };
    let mut cache = BuildCache::new();
    let red = files("0.5 0 0");
    let first = build(&text(1.0, 0.0), &red, Some(&mut cache));
    assert_eq!(part_diffuse(&first), glam::Vec3::new(0.5, 0.0, 0.0));
    // The MTL is in the watch set even on builds that do not read it again.
    assert!(cache
        .files_in_use()
        .iter()
        .any(|(p, _)| p.ends_with("meshes/tri.mtl")));
    cache.recycle(first);

    let (obj_hash, red_hash) = hashes(&red);
    cache.retain_current(|p| {
        if p.ends_with("tri.mtl") {
            red_hash
        } else {
            obj_hash
        }
    });
    let again = build(&text(1.0, 0.0), &red, Some(&mut cache));
    assert_eq!(cache.report().meshes_loaded, 0, "nothing changed");
    cache.recycle(again);

    let blue = files("0 0 0.5");
    let (_, blue_hash) = hashes(&blue);
    cache.retain_current(|p| {
        if p.ends_with("tri.mtl") {
            blue_hash
        } else {
            obj_hash
        }
    });
    let edited = build(&text(1.0, 0.0), &blue, Some(&mut cache));
    assert_eq!(
        cache.report().meshes_loaded,
        1,
        "the OBJ is reloaded for its MTL"
    );
    assert_eq!(part_diffuse(&edited), glam::Vec3::new(0.0, 0.0, 0.5));
}

/// A field of `n` small boxes on a grid, the camera above it; box `moved` lifted by `lift`.
fn field(n: usize, moved: usize, lift: f32) -> String {
    let mut s = String::from(
        "scnc 1
camera main { eye (50, 60, -40)  target (50, 0, 25)  up (0, 1, 0)  fov 60deg }
material white = phong { diffuse rgb(0.8, 0.8, 0.8)  specular 0 }
mesh cube = box { size (0.6, 0.6, 0.6) }
light key = point { position (50, 80, 0)  intensity rgb(3000, 3000, 3000) }
render { resolution 48 x 32  samples 1 }
",
    );
    for i in 0..n {
        let y = if i == moved { lift } else { 0.0 };
        s += &format!(
            "object cube {{ material white  transform {{ rotate y {}deg  translate ({}, {y}, {}) }} }}\n",
            i % 90,
            (i % 100) as f32 + 0.25,
            (i / 100) as f32 * 0.5
        );
    }
    s
}

/// Issue 22: after one instance among many moves, the cached build rebuilds the BVH's top
/// level beside the last build's trace (copying the subtrees over unmoved instances); its
/// image is the plain build's, bit for bit. 10,000 instances: above the builder's parallel
/// threshold, so copied subtrees include the fixed slot ranges of parallel builds.
#[test]
fn moving_one_instance_among_many_renders_the_plain_builds_image() {
    let l = MemLoader::new();
    let mut cache = BuildCache::new();
    let bits = |s: &Scene| -> Vec<[u32; 3]> {
        image(s)
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    let n = 10_000;
    for (moved, lift) in [
        (0, 0.0),
        (5050, 0.5),
        (5050, 1.5),
        (0, 3.0),
        (9999, 0.25),
        (5051, 0.0),
    ] {
        let text = field(n, moved, lift);
        let cached = build(&text, &l, Some(&mut cache));
        let plain = build(&text, &l, None);
        assert_eq!(bits(&cached), bits(&plain), "object {moved} lifted {lift}");
        cache.recycle(cached);
    }
}
