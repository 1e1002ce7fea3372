//! Stage 3: bad input found while building (files, geometry) becomes diagnostics labelled at the
//! path literal or declaration in the `.scn`, never a panic; good OBJ files load through the
//! Loader.

mod render_common;

use glam::{Mat4, Vec3};
use render_common::*;
use scnc::assets::{Loader, MemLoader};
use scnc::diag::{Diagnostic, Severity};
use scnc::ir::*;
use scnc::scene::{self, BuildOptions, Scene};
use scnc::source::{FileId, SourceMap, Span};

const SCN: &str = r#"mesh m = obj("meshes/m.obj")
texture wood = image("wood.png")
light sky = environment { image("sky.hdr") }
"#;

struct Fixture {
    sources: SourceMap,
    file: FileId,
}

impl Fixture {
    fn new() -> Fixture {
        let mut sources = SourceMap::new();
        let file = sources.add("scenes/test.scn", "test.scn", SCN);
        Fixture { sources, file }
    }

    /// The span of the string literal `"text"` in the fake .scn.
    fn literal(&self, text: &str) -> Span {
        let quoted = format!("\"{text}\"");
        let start = SCN.find(&quoted).expect("literal in the fixture");
        Span::new(self.file, start, start + quoted.len())
    }

    fn asset(&self, text: &str) -> AssetPath {
        AssetPath {
            path: format!("scenes/{text}").into(),
            written: text.into(),
            span: self.literal(text),
        }
    }

    /// A scene placing the OBJ mesh once, built with `loader`.
    fn build_obj(&self, loader: &dyn Loader) -> Result<(Scene, Vec<Diagnostic>), Vec<Diagnostic>> {
        let mut desc = empty_desc(
            camera(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
            settings(8, 8, 1),
        );
        desc.meshes = vec![Mesh {
            name: "m".into(),
            source: MeshSource::Obj(Box::new(self.asset("meshes/m.obj"))),
            span: self.literal("meshes/m.obj"),
            obj: Default::default(),
        }];
        desc.materials = vec![phong("grey", Vec3::splat(0.5), 0.0, 1.0)];
        desc.objects = vec![
            object(0, 0, Mat4::IDENTITY),
            object(0, 0, Mat4::from_translation(Vec3::X)),
        ];
        desc.lights = vec![point_light(Vec3::new(0.0, 0.0, -2.0), 1.0)];
        scene::build(&desc, loader, &BuildOptions::default()).into_result()
    }

    /// Builds with `bytes` as the OBJ file and returns the one error diagnostic.
    fn obj_error(&self, bytes: &[u8]) -> Diagnostic {
        let mut loader = MemLoader::new();
        loader.insert("scenes/meshes/m.obj", bytes);
        let diags = self.build_obj(&loader).expect_err("bad OBJ");
        assert_eq!(
            diags.len(),
            1,
            "one diagnostic per faulty file, not per use: {diags:#?}"
        );
        let d = diags.into_iter().next().expect("one");
        assert_eq!(d.severity, Severity::Error);
        self.assert_at_path(&d);
        d
    }

    fn assert_at_path(&self, d: &Diagnostic) {
        let label = d.primary.as_ref().expect("labelled");
        assert_eq!(self.sources.snippet(label.span), "\"meshes/m.obj\"");
    }
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn missing_obj_points_at_the_path() {
    let fx = Fixture::new();
    let loader = MemLoader::new();
    let diags = fx.build_obj(&loader).expect_err("missing file");
    assert_eq!(diags.len(), 1);
    assert_eq!(diags[0].code, "scnc::build::missing_file");
    assert!(
        diags[0].message.contains("meshes/m.obj"),
        "{}",
        diags[0].message
    );
    fx.assert_at_path(&diags[0]);
    assert_eq!(
        loader.recorded(),
        vec![std::path::PathBuf::from("scenes/meshes/m.obj")]
    );
}

#[test]
fn corrupt_obj_bytes() {
    let fx = Fixture::new();
    let d = fx.obj_error(b"v 1.0 banana 2\nf 1 2 3\n");
    assert_eq!(d.code, "scnc::obj::bad_number");
    // Both places: the OBJ's line with a snippet, and the path literal in the .scn.
    let ext = &d.external[0];
    assert_eq!(
        (ext.file.as_str(), ext.line, ext.text.as_str()),
        ("meshes/m.obj", 1, "v 1.0 banana 2")
    );
    // A UTF-16 byte-order mark followed by junk: transcoded, nothing readable, warnings only.
    let mut loader = MemLoader::new();
    loader.insert(
        "scenes/meshes/m.obj",
        b"\xff\xfe\x00\x01binary junk".to_vec(),
    );
    let (_scene, warnings) = fx.build_obj(&loader).expect("loads, with warnings");
    let codes: Vec<&str> = warnings.iter().map(|w| w.code.as_str()).collect();
    assert_eq!(
        codes,
        [
            "scnc::obj::utf16",
            "scnc::obj::unsupported_statement",
            "scnc::build::empty_mesh"
        ]
    );
}

#[test]
fn obj_with_out_of_range_indices() {
    let fx = Fixture::new();
    let d = fx.obj_error(format!("{TRIANGLE}f 1 2 7\n").as_bytes());
    assert_eq!(d.code, "scnc::obj::index_out_of_range");
    assert_eq!(d.external[0].line, 4);
    let d = fx.obj_error(format!("{TRIANGLE}f 1 2 -9\n").as_bytes());
    assert_eq!(d.code, "scnc::obj::index_out_of_range");
}

#[test]
fn obj_with_a_nan_vertex() {
    // Its only triangle has a NaN corner: nothing is left to render.
    let fx = Fixture::new();
    let d = fx.obj_error(b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_eq!(d.code, "scnc::build::degenerate_mesh");
    // With a good triangle beside it, the NaN and infinite ones are dropped with a warning.
    let mut loader = MemLoader::new();
    loader.insert(
        "scenes/meshes/m.obj",
        format!("{TRIANGLE}v nan 0 0\nv 0 inf 0\nf 1 2 3\nf 1 2 4\nf 5 2 3\n").into_bytes(),
    );
    let (scene, warnings) = fx.build_obj(&loader).expect("one good triangle");
    assert_eq!(scene.meshes[0].triangles.len(), 1);
    assert_eq!(warnings[0].code, "scnc::build::degenerate_triangles");
    assert!(warnings[0].message.starts_with("2 of 3"));
    assert!(scene.meshes[0].positions.iter().all(|p| p.is_finite()));
}

#[test]
fn all_degenerate_is_an_error_some_degenerate_a_warning() {
    let fx = Fixture::new();
    let d = fx.obj_error(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n");
    assert_eq!(d.code, "scnc::build::degenerate_mesh");
    assert!(d.message.contains("2 triangles"), "{}", d.message);

    let mut loader = MemLoader::new();
    loader.insert(
        "scenes/meshes/m.obj",
        format!("{TRIANGLE}v 2 0 0\nf 1 2 3\nf 1 2 4\n").into_bytes(),
    );
    let (scene, warnings) = fx.build_obj(&loader).expect("one good triangle");
    assert_eq!(scene.meshes[0].triangles.len(), 1);
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].code, "scnc::build::degenerate_triangles");
    assert_eq!(warnings[0].severity, Severity::Warning);
    fx.assert_at_path(&warnings[0]);
}

#[test]
fn a_good_obj_loads_once_for_two_instances_and_renders() {
    let fx = Fixture::new();
    let mut loader = MemLoader::new();
    loader.insert(
        "scenes/meshes/m.obj",
        "mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         usemtl red\nf 1/1/1 4/4/1 3/3/1 2/2/1\n",
    );
    let (scene, warnings) = fx.build_obj(&loader).expect("valid");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.meshes[0].triangles.len(), 2);
    assert_eq!(scene.meshes[0].normals.len(), 4);
    assert_eq!(scene.meshes[0].uvs.len(), 4);
    // The BVH stores the shared mesh's triangles once, however many instances place it.
    assert_eq!(scene.accel_stats().triangles, 2);
    // Its MTL is absent: warnings at the OBJ's lines, the default material is used.
    let codes: Vec<&str> = warnings.iter().map(|w| w.code.as_str()).collect();
    assert_eq!(
        codes,
        ["scnc::obj::missing_mtl", "scnc::obj::unknown_material"]
    );
    assert_eq!(warnings[0].external[0].line, 1);
    let (film, _) = render_with(&scene, 1);
    assert!(
        film.get(4, 4).x > 0.0,
        "the quad faces the camera and the light"
    );
    // The OBJ and the MTL it names were asked for (through the Loader: the watch set).
    assert_eq!(
        loader.recorded(),
        ["scenes/meshes/m.mtl", "scenes/meshes/m.obj"].map(std::path::PathBuf::from)
    );
}

#[test]
fn a_missing_image_texture_and_environment_map_are_missing_at_their_paths() {
    let fx = Fixture::new();
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
        settings(8, 8, 1),
    );
    desc.meshes = vec![quad("floor", 1.0, 1.0)];
    desc.textures = vec![Texture {
        name: "wood".into(),
        source: TextureSource::Image {
            file: fx.asset("wood.png"),
            encoding: TextureEncoding::Srgb,
            wrap: WrapMode::Repeat,
            filter: Filter::Bilinear,
        },
        span: span(),
    }];
    let mut wood = phong("wood", Vec3::ONE, 0.0, 1.0);
    wood.diffuse = ColorInput::Texture(0);
    desc.materials = vec![wood];
    desc.objects = vec![object(0, 0, Mat4::IDENTITY)];
    desc.lights = vec![Light::Environment(EnvironmentLight {
        name: "sky".into(),
        source: EnvSource::Image(fx.asset("sky.hdr")),
        intensity: 1.0,
        rotation_y_rad: 0.0,
        visible: true,
        span: span(),
    })];
    let diags = scene::build(&desc, &MemLoader::new(), &BuildOptions::default())
        .into_result()
        .expect_err("missing files");
    let mut labelled: Vec<(&str, &str)> = diags
        .iter()
        .map(|d| {
            assert!(d.help.is_some());
            let at = fx
                .sources
                .snippet(d.primary.as_ref().expect("labelled").span);
            (at, d.code.as_str())
        })
        .collect();
    labelled.sort();
    assert_eq!(
        labelled,
        [
            ("\"sky.hdr\"", "scnc::build::missing_file"),
            ("\"wood.png\"", "scnc::build::missing_file")
        ]
    );
}

#[test]
fn no_camera_and_singular_transforms_are_errors() {
    let mut desc = empty_desc(
        camera(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 40.0),
        settings(8, 8, 1),
    );
    desc.meshes = vec![quad("floor", 1.0, 1.0)];
    desc.materials = vec![phong("grey", Vec3::ONE, 0.0, 1.0)];
    desc.objects = vec![object(0, 0, Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)))];
    let opts = BuildOptions {
        camera: Some(3),
        ..BuildOptions::default()
    };
    let diags = scene::build(&desc, &MemLoader::new(), &opts)
        .into_result()
        .expect_err("bad");
    let codes: Vec<&str> = diags.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(
        codes,
        ["scnc::build::no_camera", "scnc::build::singular_transform"]
    );
}
