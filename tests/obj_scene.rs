//! An OBJ's MTL materials in the scene (examples/obj_import.scn): each `usemtl` part gets its
//! Phong material, the `Ke` part becomes an area light, faces before any `usemtl` take the
//! object's material, and a hit reports the surface of its triangle's part.

use std::path::Path;

use scnc::assets::FsLoader;
use scnc::compile::compile_file;
use scnc::scene::{build, BuildOptions, Light, Surface};

#[test]
fn mtl_parts_become_materials_and_an_area_light() {
    let loader = FsLoader::new();
    let compiled = compile_file(Path::new("examples/obj_import.scn"), &loader);
    let desc = compiled.scene.expect("compiles");
    let scene = build(&desc, &compiled.sources, &loader, &BuildOptions::default()).expect("builds");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The point light, then the lamp part.
    assert_eq!(scene.lights.lights.len(), 2);
    let Light::Area(lamp) = &scene.lights.lights[1] else {
        panic!("the lamp part is an area light");
    };
    assert_eq!(lamp.radiance, glam::Vec3::new(6.0, 6.0, 5.0));
    assert!((lamp.total_area - 1.44).abs() < 1e-4);
    // trim (the .scn's), then white floor and blue (the MTL's).
    assert_eq!(scene.materials.len(), desc.materials.len() + 2);
    let inst = &scene.instances[0];
    let mesh = &scene.meshes[inst.mesh as usize];
    let names: Vec<Option<&str>> = mesh.parts.iter().map(|p| p.name.as_deref()).collect();
    assert_eq!(
        names,
        [None, Some("white floor"), Some("lamp"), Some("blue")]
    );
    let surfaces: Vec<Surface> = (0..mesh.triangles.len() as u32)
        .map(|t| scene.surface_of(inst, mesh, t))
        .collect();
    // The concave panel (4 triangles) uses the object's material 0.
    assert!(surfaces[..4].iter().all(|&s| s == Surface::Material(0)));
    assert_eq!(surfaces[4], Surface::Material(1));
    assert_eq!(surfaces[6], Surface::Emitter(1));
    assert_eq!(*surfaces.last().expect("ball"), Surface::Material(2));
}
