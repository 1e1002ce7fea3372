//! Shared builders for the renderer's integration tests: `ir::SceneDesc` values written in Rust
//! (the front end that parses `.scn` text is developed separately).
#![allow(dead_code)] // reason: each test crate uses a different subset of these helpers

use std::sync::atomic::AtomicBool;

use glam::{Mat4, Vec2, Vec3};
use scnc::assets::MemLoader;
use scnc::bvh::AccelKind;
use scnc::film::Film;
use scnc::ir::{self, *};
use scnc::render::{self, RenderOptions, RenderStats};
use scnc::scene::{self, BuildOptions, Scene};
use scnc::source::{FileId, Span};

pub fn span() -> Span {
    Span::new(FileId(0), 0, 0)
}

/// A camera at `eye` looking at `target`; `up_hint` must not be parallel to the view direction.
pub fn camera(eye: Vec3, target: Vec3, up_hint: Vec3, fov_y_deg: f32) -> Camera {
    let forward = (target - eye).normalize();
    let right = forward.cross(up_hint).normalize();
    let up = right.cross(forward);
    Camera {
        name: "main".into(),
        eye: eye.as_dvec3(),
        forward,
        up,
        right,
        fov_y_rad: fov_y_deg.to_radians(),
        span: span(),
    }
}

pub fn settings(width: u32, height: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        samples_per_pixel: spp,
        pattern: SamplePattern::RotatedGrid,
        light_samples: 1,
        seed: 0,
        exposure: 0.0,
        tonemap: ToneMap::Clamp,
        outputs: Vec::new(),
        quality: None,
        noise: None,
        max_samples: None,
    }
}

pub fn phong(name: &str, diffuse: Vec3, specular: f32, shininess: f32) -> Material {
    Material {
        name: name.into(),
        diffuse: ColorInput::Constant(diffuse),
        specular: ColorInput::Constant(Vec3::splat(specular)),
        shininess: ScalarInput::Constant(shininess),
        ambient: Vec3::ZERO,
        normal_map: None,
        span: span(),
    }
}

pub fn builtin(name: &str, shape: BuiltinShape) -> Mesh {
    Mesh {
        name: name.into(),
        source: MeshSource::Builtin(shape),
        span: span(),
        obj: Default::default(),
    }
}

pub fn quad(name: &str, w: f32, d: f32) -> Mesh {
    builtin(
        name,
        BuiltinShape::Quad {
            size: Vec2::new(w, d),
        },
    )
}

pub fn object(mesh: u32, material: u32, world_from_object: Mat4) -> Object {
    Object {
        mesh,
        material,
        world_from_object: world_from_object.as_dmat4(),
        span: span(),
    }
}

pub fn point_light(position: Vec3, intensity: f32) -> Light {
    Light::Point(PointLight {
        name: "bulb".into(),
        position: position.as_dvec3(),
        intensity: Vec3::splat(intensity),
        span: span(),
    })
}

pub fn area_light(
    mesh: u32,
    world_from_object: Mat4,
    radiance: f32,
    two_sided: bool,
    samples: u32,
) -> Light {
    Light::Area(AreaLight {
        name: "panel".into(),
        mesh,
        world_from_object: world_from_object.as_dmat4(),
        radiance: Vec3::splat(radiance),
        two_sided,
        samples,
        span: span(),
    })
}

pub fn empty_desc(camera: Camera, settings: RenderSettings) -> SceneDesc {
    SceneDesc {
        cameras: vec![camera],
        active_camera: 0,
        meshes: Vec::new(),
        textures: Vec::new(),
        materials: Vec::new(),
        objects: Vec::new(),
        lights: Vec::new(),
        render: settings,
    }
}

pub fn build(desc: &ir::SceneDesc, accel: AccelKind) -> Scene {
    build_warned(desc, accel).0
}

/// [`build`], also returning the build's warnings.
pub fn build_warned(
    desc: &ir::SceneDesc,
    accel: AccelKind,
) -> (Scene, Vec<scnc::diag::Diagnostic>) {
    scene::build(
        desc,
        &MemLoader::new(),
        &BuildOptions {
            accel,
            camera: None,
        },
    )
    .into_result()
    .unwrap_or_else(|d| panic!("scene should build: {d:#?}"))
}

pub fn render_with(scene: &Scene, threads: usize) -> (Film, RenderStats) {
    render::render(
        scene,
        &RenderOptions {
            threads: Some(threads),
        },
        &|_| {},
        &AtomicBool::new(false),
    )
    .expect("not cancelled")
}

/// A small scene with every feature: shapes, instancing, checker texture, point, area and
/// environment lights, specular highlights.
pub fn showcase(size: u32, spp: u32) -> SceneDesc {
    let mut desc = empty_desc(
        camera(
            Vec3::new(0.0, 2.0, -5.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::Y,
            45.0,
        ),
        settings(size, size, spp),
    );
    desc.meshes = vec![
        quad("floor", 8.0, 8.0),
        builtin(
            "ball",
            BuiltinShape::Sphere {
                radius: 0.6,
                segments: 16,
            },
        ),
        builtin(
            "crate",
            BuiltinShape::Box {
                size: Vec3::splat(0.8),
            },
        ),
        quad("panel", 1.0, 1.0),
    ];
    desc.textures = vec![Texture {
        name: "board".into(),
        source: TextureSource::Checker {
            even: ColorInput::Constant(Vec3::new(0.8, 0.8, 0.8)),
            odd: ColorInput::Constant(Vec3::new(0.2, 0.3, 0.6)),
            scale: 4.0,
        },
        span: span(),
    }];
    let mut floor = phong("floor", Vec3::ONE, 0.0, 1.0);
    floor.diffuse = ColorInput::Texture(0);
    floor.ambient = Vec3::splat(0.01);
    desc.materials = vec![floor, phong("shiny", Vec3::new(0.6, 0.2, 0.1), 0.3, 40.0)];
    desc.objects = vec![
        object(0, 0, Mat4::IDENTITY),
        object(1, 1, Mat4::from_translation(Vec3::new(-0.8, 0.6, 0.0))),
        object(1, 1, Mat4::from_translation(Vec3::new(0.9, 0.6, 0.8))),
        object(
            2,
            1,
            Mat4::from_translation(Vec3::new(0.2, 0.4, -1.0)) * Mat4::from_rotation_y(0.5),
        ),
    ];
    desc.lights = vec![
        point_light(Vec3::new(2.0, 3.0, -2.0), 6.0),
        area_light(
            3,
            Mat4::from_translation(Vec3::new(0.0, 2.5, 0.0))
                * Mat4::from_rotation_x(std::f32::consts::PI),
            5.0,
            false,
            4,
        ),
        Light::Environment(EnvironmentLight {
            name: "sky".into(),
            source: EnvSource::Constant(Vec3::new(0.1, 0.15, 0.2)),
            intensity: 1.0,
            rotation_y_rad: 0.0,
            visible: true,
            span: span(),
        }),
    ];
    desc
}

/// An environment light.
pub fn environment(source: EnvSource, intensity: f32, rotation_y_rad: f32, visible: bool) -> Light {
    Light::Environment(EnvironmentLight {
        name: "sky".into(),
        source,
        intensity,
        rotation_y_rad,
        visible,
        span: span(),
    })
}

/// A little-endian colour PFM of `width × height` pixels given top row first.
pub fn pfm_bytes(width: usize, height: usize, top_first: &[Vec3]) -> Vec<u8> {
    let mut bytes = format!("PF\n{width} {height}\n-1.0\n").into_bytes();
    for row in (0..height).rev() {
        for p in &top_first[row * width..(row + 1) * width] {
            for c in p.to_array() {
                bytes.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    bytes
}

/// A build's scene and warnings, or every diagnostic.
pub type Built = Result<(Scene, Vec<scnc::diag::Diagnostic>), Vec<scnc::diag::Diagnostic>>;

/// Builds with files served by `loader`.
pub fn build_with(desc: &ir::SceneDesc, loader: &dyn scnc::assets::Loader) -> Built {
    scene::build(desc, loader, &BuildOptions::default()).into_result()
}
