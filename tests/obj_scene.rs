//! An OBJ's MTL materials in the scene (examples/obj_import.scn): each `usemtl` part gets its
//! Phong material, the `Ke` part becomes an area light, faces before any `usemtl` take the
//! object's material, and a hit reports the surface of its triangle's part.

use std::path::Path;

use scnc::assets::{FsLoader, Loader, MemLoader};
use scnc::compile::compile_file;
use scnc::scene::{build, BuildOptions, Surface};
use scnc::shade::Light;

#[test]
fn mtl_parts_become_materials_and_an_area_light() {
    let loader = FsLoader::new();
    let compiled = compile_file(Path::new("examples/obj_import.scn"), &loader);
    let desc = compiled.scene.expect("compiles");
    let (scene, warnings) = build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .expect("builds");
    assert!(warnings.is_empty(), "{:?}", warnings);
    // The point light, then the lamp part.
    assert_eq!(scene.lights.lights.len(), 2);
    let Light::Area(lamp) = &scene.lights.lights[1] else {
        panic!("the lamp part is an area light");
    };
    assert_eq!(lamp.radiance, glam::Vec3::new(6.0, 6.0, 5.0));
    assert!((lamp.total_area - 1.44).abs() < 1e-4);
    // trim and stone (the .scn's), then blue and bricks (the MTL's; `white floor` is replaced
    // by stone).
    assert_eq!(desc.materials.len(), 2);
    assert_eq!(scene.materials.len(), desc.materials.len() + 2);
    let inst = &scene.instances[0];
    let mesh = &scene.meshes[inst.mesh as usize];
    let names: Vec<Option<&str>> = mesh.parts.iter().map(|p| p.name.as_deref()).collect();
    assert_eq!(
        names,
        [
            None,
            Some("white floor"),
            Some("lamp"),
            Some("blue"),
            Some("bricks")
        ]
    );
    let surfaces: Vec<Surface> = (0..mesh.triangles.len() as u32)
        .map(|t| scene.surface_of(inst, mesh, t))
        .collect();
    // The concave panel (4 triangles) uses the object's material 0.
    assert!(surfaces[..4].iter().all(|&s| s == Surface::Material(0)));
    assert_eq!(surfaces[4], Surface::Material(1));
    assert_eq!(surfaces[6], Surface::Emitter(1));
    assert_eq!(
        surfaces[surfaces.len() - 3],
        Surface::Material(2),
        "the ball"
    );
    // The brick wall (the last two triangles): map_Kd and norm made it a textured material.
    assert_eq!(*surfaces.last().expect("wall"), Surface::Material(3));
    assert!(scene.materials[3].is_textured() && scene.materials[3].normal_map.is_some());
}

fn build_mem(
    scn: &str,
    obj: &str,
    mtl: &str,
) -> (scnc::scene::Scene, usize, Vec<scnc::diag::Diagnostic>) {
    let mut loader = MemLoader::new();
    loader.insert("s.scn", scn.as_bytes().to_vec());
    loader.insert("m.obj", obj.as_bytes().to_vec());
    loader.insert("m.mtl", mtl.as_bytes().to_vec());
    let compiled = compile_file(Path::new("s.scn"), &loader);
    assert!(!compiled.has_errors(), "{:?}", compiled.diagnostics);
    let desc = compiled.scene.expect("compiles");
    let n = desc.materials.len();
    let (scene, warnings) = build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .expect("builds");
    (scene, n, warnings)
}

const HEAD: &str = "scnc 1\ncamera c { eye (0, 1, -4)  target (0, 0, 0)  fov 40deg }\n\
    material m = phong { diffuse 0.5 }\nmaterial gold = phong { diffuse rgb(0.8, 0.6, 0.2) }\n\
    light p = point { position (0, 3, 0)  intensity rgb(5, 5, 5) }\n";
const OBJ: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl my red\nf 1 2 3\nusemtl lamp\nf 2 4 3\n";
const MTL: &str = "newmtl my red\nKd 1 0 0\nnewmtl lamp\nKe 3 3 3\n";

#[test]
fn scn_overrides_replace_obj_materials_by_name_and_mtl_false_skips_the_library() {
    let scn = format!("{HEAD}mesh o = obj(\"m.obj\") {{ material \"my red\" gold  material nothing m }}\nobject o {{ material m }}\n");
    let (scene, n, warnings) = build_mem(&scn, OBJ, MTL);
    let inst = &scene.instances[0];
    let mesh = &scene.meshes[inst.mesh as usize];
    let gold = 1; // materials are numbered in declaration order (both used)
    assert_eq!(n, 2);
    assert_eq!(scene.surface_of(inst, mesh, 0), Surface::Material(gold));
    assert_eq!(scene.surface_of(inst, mesh, 1), Surface::Emitter(1));
    let codes: Vec<&str> = warnings.iter().map(|w| w.code.as_str()).collect();
    assert_eq!(codes, ["scnc::obj::unknown_override"]);

    // `mtl false`: the library is not read; no emitter, the object's material everywhere
    // except the override.
    let scn = format!("{HEAD}mesh o = obj(\"m.obj\") {{ mtl false  material lamp gold }}\nobject o {{ material m }}\n");
    let (scene, _, warnings) = build_mem(&scn, OBJ, MTL);
    let inst = &scene.instances[0];
    let mesh = &scene.meshes[inst.mesh as usize];
    assert_eq!(scene.lights.lights.len(), 1);
    assert_eq!(scene.surface_of(inst, mesh, 0), Surface::Material(0));
    assert_eq!(scene.surface_of(inst, mesh, 1), Surface::Material(gold));
    assert!(warnings.is_empty(), "{:?}", warnings);
}

#[test]
fn mtl_texture_maps_warn_at_the_mtl_line_when_missing_or_corrupt() {
    let mut loader = MemLoader::new();
    let scn = format!("{HEAD}mesh o = obj(\"m.obj\")\nobject o {{ material m }}\n");
    loader.insert("s.scn", scn.into_bytes());
    loader.insert("m.obj", OBJ.as_bytes().to_vec());
    loader.insert("m.mtl", b"newmtl my red\nKd 1 0 0\nmap_Kd -s 2 2 1 red tex.png\nnewmtl lamp\nKe 1 1 1\nmap_Ks gone.png\n".to_vec());
    loader.insert("red tex.png", b"not really a png".to_vec());
    let compiled = compile_file(Path::new("s.scn"), &loader);
    let desc = compiled.scene.expect("compiles");
    let (_scene, warnings) = build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .expect("builds");
    let got: Vec<(&str, u32)> = warnings
        .iter()
        .map(|w| (w.code.as_str(), w.external.first().map_or(0, |e| e.line)))
        .collect();
    assert_eq!(
        got,
        [
            ("scnc::obj::bad_texture", 3),
            ("scnc::obj::missing_texture", 6)
        ]
    );
    assert!(loader
        .recorded()
        .contains(&std::path::PathBuf::from("gone.png")));
}

/// A 2 x 1 PNG: a red texel and a green one.
fn two_texel_png() -> Vec<u8> {
    let img = image::RgbImage::from_fn(2, 1, |x, _| {
        if x == 0 {
            image::Rgb([255, 0, 0])
        } else {
            image::Rgb([0, 255, 0])
        }
    });
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .expect("encodes");
    bytes.into_inner()
}

#[test]
fn mtl_colour_and_normal_maps_become_image_textures() {
    use scnc::ir::ColorInput;
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl painted\nf 1/1 2/2 3/3\n";
    let mtl = "newmtl painted\nKd 0.5 0.5 0.5\nmap_Kd t.png\nmap_Ks t.png\nmap_Ns t.png\nnorm -bm 0.5 n.png\n";
    let mut loader = MemLoader::new();
    let scn = format!("{HEAD}mesh o = obj(\"m.obj\")\nobject o {{ material m }}\n");
    loader.insert("s.scn", scn.into_bytes());
    loader.insert("m.obj", obj.as_bytes().to_vec());
    loader.insert("m.mtl", mtl.as_bytes().to_vec());
    loader.insert("t.png", two_texel_png());
    loader.insert("n.png", two_texel_png());
    let compiled = compile_file(Path::new("s.scn"), &loader);
    let desc = compiled.scene.expect("compiles");
    let (scene, warnings) = build(&desc, &loader, &BuildOptions::default())
        .into_result()
        .expect("builds");
    // map_Ns keeps the constant exponent, with one warning at its MTL line.
    let got: Vec<(&str, u32)> = warnings
        .iter()
        .map(|w| (w.code.as_str(), w.external.first().map_or(0, |e| e.line)))
        .collect();
    assert_eq!(got, [("scnc::obj::texture_not_rendered", 5)]);
    let inst = &scene.instances[0];
    let mesh = &scene.meshes[inst.mesh as usize];
    let Surface::Material(m) = scene.surface_of(inst, mesh, 0) else {
        panic!("the part is a material");
    };
    let material = &scene.materials[m as usize];
    let (ColorInput::Texture(kd), ColorInput::Texture(ks)) = (material.diffuse, material.specular)
    else {
        panic!("map_Kd and map_Ks are textures: {material:?}");
    };
    let normal = material.normal_map.as_ref().expect("norm is a normal map");
    assert_eq!(normal.strength, 0.5);
    // Colour maps are sRGB-decoded: the left texel is pure red, the right pure green.
    let red = scene.textures.color(
        ColorInput::Texture(kd),
        glam::Vec2::new(0.25, 0.5),
        scnc::shade::texture::Footprint::isotropic(1e-6),
        &mut Default::default(),
    );
    let green = scene.textures.color(
        ColorInput::Texture(ks),
        glam::Vec2::new(0.75, 0.5),
        scnc::shade::texture::Footprint::isotropic(1e-6),
        &mut Default::default(),
    );
    assert!((red - glam::Vec3::X).abs().max_element() < 1e-3, "{red}");
    assert!(
        (green - glam::Vec3::Y).abs().max_element() < 1e-3,
        "{green}"
    );
    // map_Kd and map_Ks name one file with one encoding: decoded once, shared; the normal map
    // is data (decoded raw), a second decode.
    let image = |id: u32| match &scene.textures.slots[id as usize] {
        Some(scnc::shade::Texture::Image { data, .. }) => data.clone(),
        other => panic!("an image texture: {other:?}"),
    };
    assert!(std::sync::Arc::ptr_eq(&image(kd), &image(ks)));
    assert!(!std::sync::Arc::ptr_eq(&image(kd), &image(normal.texture)));
    // The mesh has UVs and a normal-mapped part: tangents were derived for it.
    assert!(!scene.tangents[inst.mesh as usize].is_empty());
}
