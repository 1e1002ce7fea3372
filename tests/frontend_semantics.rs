//! Front-end semantics through `compile_source`: expression folding (precedence, vectors,
//! functions, units), colour encodings, transform order, name resolution, unused declarations,
//! include paths, and the CLI's exit codes and JSON diagnostics.

use glam::Vec3;
use scnc::assets::{Loader, MemLoader};
use scnc::compile::{compile_source, Compiled};
use scnc::ir::{ColorInput, Light, MeshSource};

const CAMERA: &str = "camera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }\n";

fn compile(body: &str) -> Compiled {
    let text = format!("scnc 1\n{CAMERA}{body}");
    compile_source("scene.scn", &text, &MemLoader::new())
}

fn codes(c: &Compiled) -> Vec<&'static str> {
    c.diagnostics.iter().map(|d| d.code.as_str()).collect()
}

/// Folds `expr` by placing it as a point light's position.
fn position_of(lets: &str) -> Vec3 {
    let c = compile(&format!("{lets}\nlight l = point {{ position p }}\n"));
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    match &scene.lights[0] {
        Light::Point(p) => p.position.as_vec3(),
        other => panic!("not a point light: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn folding_respects_precedence_and_types() {
    assert_eq!(
        position_of("let p = (1 + 2 * 3, (1 + 2) * 3, 10 - 4 - 3)"),
        Vec3::new(7.0, 9.0, 3.0)
    );
    assert_eq!(
        position_of("let p = (8 / 2 / 2, -2 * -3, --4)"),
        Vec3::new(2.0, 6.0, 4.0)
    );
    assert_eq!(
        position_of("let a = (1, 2, 3)\nlet p = a * 2 - (1, 1, 1) / 1"),
        Vec3::new(1.0, 3.0, 5.0)
    );
    assert_eq!(
        position_of("let p = (1, 2, 3) * (2, 2, 2)"),
        Vec3::new(2.0, 4.0, 6.0)
    );
    assert_eq!(position_of("let p = cross((1, 0, 0), (0, 1, 0))"), Vec3::Z);
    assert!(close(
        position_of("let p = normalize((3, 0, 4)) * length((0, 5, 0))"),
        Vec3::new(3.0, 0.0, 4.0)
    ));
    assert!(close(
        position_of("let p = (sin(30deg), cos(radians(60)), degrees(0.5rad) / 28.64788975654116)"),
        Vec3::new(0.5, 0.5, 1.0)
    ));
    assert_eq!(
        position_of(
            "let p = (min(1, 2), max(1, 2), pow(2, 3) + sqrt(16) + abs(-1) + dot((1, 2), (3, 4)))"
        ),
        Vec3::new(1.0, 2.0, 24.0)
    );
    // Angles combine with numbers but not with angles multiplicatively.
    assert!(codes(&compile("let a = 10deg * 10deg\n")).contains(&"scnc::check::bad_operands"));
    assert!(codes(&compile("let a = 1 / 0\n")).contains(&"scnc::check::not_finite"));
}

#[test]
fn colours_are_linear_in_the_ir() {
    let c = compile(
        "material a = phong { diffuse srgb(0.5, 0.5, 0.5) }\nmaterial b = phong { diffuse #ff0000 }\n\
         material c = phong { diffuse rgb(0.25, 0.5, 1) }\nmaterial d = phong { diffuse 0.3 }\n\
         mesh m = quad { }\nobject m { material a }\nobject m { material b }\nobject m { material c }\n\
         object m { material d }\n",
    );
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    let diffuse: Vec<Vec3> = scene
        .materials
        .iter()
        .map(|m| match m.diffuse {
            ColorInput::Constant(v) => v,
            ColorInput::Texture(_) => panic!("constant expected"),
        })
        .collect();
    assert!(close(diffuse[0], Vec3::splat(0.214_041_14)));
    assert_eq!(diffuse[1], Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(diffuse[2], Vec3::new(0.25, 0.5, 1.0));
    assert_eq!(diffuse[3], Vec3::splat(0.3));
}

#[test]
fn transforms_compose_in_written_order_and_groups_nest() {
    let c = compile(
        "material w = phong { }\nmesh m = box { }\n\
         object m { material w  transform { rotate y 90deg  translate (10, 0, 0) } }\n\
         object m { material w  transform { translate (10, 0, 0)  rotate y 90deg } }\n\
         group g { transform { translate (0, 5, 0) }  group h { transform { scale 2 }  object m { material w  transform { translate (1, 0, 0) } } } }\n",
    );
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    let p = |m: glam::DMat4| m.as_mat4().transform_point3(Vec3::new(1.0, 0.0, 0.0));
    // Rotate first: (1,0,0) -> (0,0,-1), then translate -> (10,0,-1).
    assert!(close(
        p(scene.objects[0].world_from_object),
        Vec3::new(10.0, 0.0, -1.0)
    ));
    // Translate first: (11,0,0), then rotate about y -> (0,0,-11).
    assert!(close(
        p(scene.objects[1].world_from_object),
        Vec3::new(0.0, 0.0, -11.0)
    ));
    // world = group g · group h · object: ((1,0,0) + (1,0,0)) * 2 + (0,5,0).
    assert!(close(
        p(scene.objects[2].world_from_object),
        Vec3::new(4.0, 5.0, 0.0)
    ));
}

#[test]
fn camera_frames_are_orthonormal_and_right_handed() {
    let c = compile("camera side { transform { look_at (5, 1, 0) (0, 1, 0) (0, 1, 0) }  fov 30deg }\nrender { camera side }\n");
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    assert_eq!(scene.active_camera, 1);
    let cam = scene.camera().expect("active camera exists");
    assert!(close(cam.eye.as_vec3(), Vec3::new(5.0, 1.0, 0.0)));
    assert!(close(cam.forward, Vec3::new(-1.0, 0.0, 0.0)));
    assert!(close(cam.up, Vec3::Y));
    assert!(close(cam.right, cam.forward.cross(cam.up)));
    let main = &scene.cameras[0];
    // Looking down +z with +y up, image right is -x (forward × up).
    assert!(close(main.right, Vec3::new(-1.0, 0.0, 0.0)));
}

#[test]
fn unused_declarations_are_warned_and_dropped_with_indices_compacted() {
    let c = compile(
        "texture unused_tex = checker { }\ntexture used_tex = checker { scale 2 }\n\
         material unused = phong { diffuse unused_tex }\nmaterial used = phong { diffuse used_tex }\n\
         mesh spare = box { }\nmesh ball = sphere { }\nobject ball { material used }\n\
         light dark = point { position (0, 1, 0)  intensity 0 }\n",
    );
    let warnings = codes(&c);
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    assert_eq!(
        warnings
            .iter()
            .filter(|c| **c == "scnc::check::unused")
            .count(),
        3,
        "{warnings:?}"
    );
    assert!(warnings.contains(&"scnc::check::dark_light"));
    assert!(c.diagnostics.iter().all(|d| !d.is_error()));
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.materials[0].diffuse, ColorInput::Texture(0));
    assert_eq!(scene.objects[0].mesh, 0);
    assert_eq!(scene.objects[0].material, 0);
}

#[test]
fn includes_and_asset_paths_resolve_relative_to_their_file() {
    let mut loader = MemLoader::new();
    loader.insert(
        "scenes/lib/mats.scn",
        b"scnc 1\ntexture wood = image(\"tex/wood.png\")\nmaterial oak = phong { diffuse wood }\n"
            .to_vec(),
    );
    let text = format!(
        "scnc 1\ninclude \"lib/mats.scn\"\n{CAMERA}mesh m = obj(\"meshes/m.obj\")\nobject m {{ material oak }}\n\
         render {{ output \"out/a.exr\" output \"b.png\" }}\n"
    );
    let c = compile_source("scenes/main.scn", &text, &loader);
    let scene = c.scene.unwrap_or_else(|| panic!("{:#?}", c.diagnostics));
    match &scene.textures[0].source {
        scnc::ir::TextureSource::Image { file, .. } => {
            assert_eq!(file.path, std::path::Path::new("scenes/lib/tex/wood.png"));
            assert_eq!(c.sources.snippet(file.span), "\"tex/wood.png\"");
            assert_eq!(c.sources.get(file.span.file).name, "scenes/lib/mats.scn");
        }
        other => panic!("{other:?}"),
    }
    match &scene.meshes[0].source {
        MeshSource::Obj(p) => assert_eq!(p.path, std::path::Path::new("scenes/meshes/m.obj")),
        other => panic!("{other:?}"),
    }
    assert_eq!(scene.render.outputs.len(), 2);
    assert_eq!(scene.render.outputs[0].format, scnc::ir::OutputFormat::Exr);
    assert!(loader
        .recorded()
        .contains(&std::path::PathBuf::from("scenes/lib/mats.scn")));
}

#[test]
fn diagnostics_inside_includes_name_the_included_file() {
    let mut loader = MemLoader::new();
    loader.insert(
        "lib.scn",
        b"scnc 1\nmaterial m = phong { difuse 0.5 }\n".to_vec(),
    );
    let c = compile_source(
        "main.scn",
        &format!("scnc 1\ninclude \"lib.scn\"\n{CAMERA}"),
        &loader,
    );
    let d = c
        .diagnostics
        .iter()
        .find(|d| d.code == "scnc::check::unknown_key")
        .expect("the typo is found");
    let span = d.primary.as_ref().expect("labelled").span;
    assert_eq!(c.sources.get(span.file).name, "lib.scn");
    assert_eq!(c.sources.snippet(span), "difuse");
    assert_eq!(d.help.as_deref(), Some("did you mean `diffuse`?"));
}

#[test]
fn one_run_reports_every_error() {
    let c = compile(
        "material a = phong { difuse 0.5  shininess -1 }\nmesh m = sphere { segments 2 }\n\
         object m { material b }\nrender { samples 5  resolution 0 x 10 }\n",
    );
    let codes = codes(&c);
    for code in [
        "scnc::check::unknown_key",
        "scnc::check::out_of_range",
        "scnc::check::unknown_material",
        "scnc::check::samples_not_square",
    ] {
        assert!(codes.contains(&code), "{code} missing from {codes:?}");
    }
    assert!(
        codes
            .iter()
            .filter(|c| **c == "scnc::check::out_of_range")
            .count()
            >= 3
    );
}

#[test]
fn cli_check_exit_codes_and_json() {
    let dir = std::env::temp_dir().join(format!("scnc-front-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let good = dir.join("good.scn");
    let bad = dir.join("bad.scn");
    std::fs::write(&good, format!("scnc 1\n{CAMERA}")).expect("write");
    std::fs::write(
        &bad,
        format!("scnc 1\n{CAMERA}material m = phong {{ difuse 1 }}\n"),
    )
    .expect("write");
    let exe = env!("CARGO_BIN_EXE_scnc");
    let run = |args: &[&std::ffi::OsStr]| {
        std::process::Command::new(exe)
            .args(args)
            .output()
            .expect("runs")
    };
    let ok = run(&["check".as_ref(), good.as_os_str()]);
    assert!(ok.status.success());
    let fail = run(&[
        "check".as_ref(),
        bad.as_os_str(),
        "--diagnostic-format".as_ref(),
        "json".as_ref(),
    ]);
    assert_eq!(fail.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&fail.stdout).expect("valid JSON");
    assert_eq!(json["errors"], 1);
    let diags = json["diagnostics"].as_array().expect("a list");
    let key = diags
        .iter()
        .find(|d| d["code"] == "scnc::check::unknown_key")
        .expect("the typo is reported");
    assert_eq!(key["severity"], "error");
    assert_eq!(key["labels"][0]["line"], 3);
    assert_eq!(key["labels"][0]["column"], 22);
    let ir = run(&["ir".as_ref(), good.as_os_str()]);
    assert!(ir.status.success());
    let ir: serde_json::Value = serde_json::from_slice(&ir.stdout).expect("IR is JSON");
    assert_eq!(ir["render"]["width"], 640);
    let _ = std::fs::remove_dir_all(&dir);
}
