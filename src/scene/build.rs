//! Stage 3 entry point: [`build`] turns a validated `ir::SceneDesc` into a render-ready
//! [`Scene`], loading files through the [`Loader`] and collecting every problem it finds
//! (one diagnostic per faulty file or mesh, not just the first).
//!
//! Only what is used is built: meshes named by objects or area lights (each loaded once however
//! many instances place it), textures reachable from used materials, light tables only when
//! there are lights, the environment map's sampling table only when there is geometry for it
//! to light (see `environment`), and no acceleration structure at all when there are no
//! triangles.

mod assemble;
mod materials;
mod origin;
mod placement;

use std::time::Instant;

use glam::{Affine3A, DVec3, Mat3, Vec3, Vec4};

use super::cache::BuildCache;
use super::env_load::load_env_map;
use super::face_normals::unmoved_face_normals;
use super::facing::{faces_away, world_boxes};
use super::load::load_mesh;
use super::mesh::TriMesh;
use super::obj_parts::PartTables;
use super::tangents::vertex_tangents;
use super::{BuildError, BuildOptions, BuildTimings, Scene, SceneInstance, Surface};

use crate::assets::Loader;
use crate::diag::{Diagnostic, Severity, Staged};
use crate::ir::{self, EnvSource};
use crate::shade::{AreaLight, Environment, Light, Lights, PointLight};
use crate::source::Span;

/// Stage entry: builds the scene. On failure, the value is `None` and the diagnostics hold
/// every error found (errors first) together with the warnings; on success, the warnings.
pub fn build(desc: &ir::SceneDesc, loader: &dyn Loader, options: &BuildOptions) -> Staged<Scene> {
    build_with(desc, loader, options, None)
}

/// [`build`] reusing what `cache` kept from earlier builds (meshes by source and content,
/// the accel by meshes and transforms); the same scene as [`build`] would make. Hand the scene
/// back with [`BuildCache::recycle`] when done; [`BuildCache::report`] says what was rebuilt.
pub fn build_cached(
    desc: &ir::SceneDesc,
    loader: &dyn Loader,
    options: &BuildOptions,
    cache: &mut BuildCache,
) -> Staged<Scene> {
    cache.begin();
    build_with(desc, loader, options, Some(cache))
}

fn build_with(
    desc: &ir::SceneDesc,
    loader: &dyn Loader,
    options: &BuildOptions,
    cache: Option<&mut BuildCache>,
) -> Staged<Scene> {
    let start = Instant::now();
    let mut b = Builder {
        desc,
        loader,
        cache,
        problems: Vec::new(),
        meshes: Vec::new(),
        mesh_slots: vec![None; desc.meshes.len()],
        mesh_bounds: Vec::new(),
        origin: DVec3::ZERO,
    };
    let assets_start = Instant::now();
    let assembled = b.assemble(options);
    let asset_load = assets_start.elapsed();

    let mut diags: Vec<Diagnostic> = b.problems.iter().map(BuildError::to_diagnostic).collect();
    let (Some(a), false) = (
        assembled,
        diags.iter().any(|d| d.severity == Severity::Error),
    ) else {
        diags.sort_by_key(|d| std::cmp::Reverse(d.severity));
        if let Some(cache) = b.cache {
            cache.give_back(b.meshes, None);
        }
        return Staged::failed(diags);
    };

    let accel_start = Instant::now();
    let accel = b.accel(&a.instances, options);
    let accel_build = if accel.is_some() {
        accel_start.elapsed()
    } else {
        Default::default()
    };

    let face_normals = unmoved_face_normals(&b.meshes, &a.instances);
    let scene = Scene {
        world_origin: b.origin,
        camera: a.camera,
        settings: desc.render.clone(),
        meshes: b.meshes,
        instances: a.instances,
        accel,
        materials: a.materials,
        part_surfaces: a.parts.surfaces,
        textures: a.textures,
        tangents: a.tangents,
        face_normals,
        lights: a.lights,
        light_sampling: Default::default(),
        strategy: Default::default(),
        shading_path: Default::default(),
        timings: BuildTimings {
            asset_load,
            accel_build,
            total: start.elapsed(),
        },
    };
    Staged::new(Some(scene), diags)
}

struct Builder<'a> {
    desc: &'a ir::SceneDesc,
    loader: &'a dyn Loader,
    cache: Option<&'a mut BuildCache>,
    problems: Vec<BuildError>,
    meshes: Vec<TriMesh>,
    /// Per `ir::MeshId`: not tried yet, or `Some(index into meshes)` / `Some(None)` if it failed.
    mesh_slots: Vec<Option<Option<u32>>>,
    /// Per loaded mesh: its object-space bounds once computed (`Some(None)`: no positions).
    /// Many objects place one mesh; its bounds are found once, not once per object.
    mesh_bounds: Vec<Option<Option<(Vec3, Vec3)>>>,
    /// World position of the render-ready scene's (0, 0, 0) (see `origin`).
    origin: DVec3,
}

impl Builder<'_> {
    /// Warns about textured objects whose mesh has no UVs, and derives per-vertex tangents for
    /// the meshes (with UVs) that normal-mapped objects use; empty for every other mesh.
    fn uvs_and_tangents(&mut self) -> Vec<Vec<Vec4>> {
        let mut tangents = vec![Vec::new(); self.meshes.len()];
        for object in &self.desc.objects {
            let (Some(Some(Some(mesh))), Some(material)) = (
                self.mesh_slots.get(object.mesh as usize),
                self.desc.materials.get(object.material as usize),
            ) else {
                continue;
            };
            let mesh = *mesh as usize;
            // The object's material, or the MTL maps of the OBJ's parts.
            let mapped_part = self.meshes[mesh].parts.iter().find(|p| !p.maps.is_empty());
            if materials::texture_roots(material).is_empty() && mapped_part.is_none() {
                continue;
            }
            let normal_mapped = material.normal_map.is_some()
                || self.meshes[mesh]
                    .parts
                    .iter()
                    .any(|p| p.maps.normal.is_some());
            if self.meshes[mesh].uvs.is_empty() {
                let name = self.desc.meshes.get(object.mesh as usize);
                let material = match mapped_part {
                    Some(p) if materials::texture_roots(material).is_empty() => {
                        p.name.clone().unwrap_or_default()
                    }
                    _ => material.name.clone(),
                };
                self.problems.push(BuildError::NoUvs {
                    mesh: name.map(|m| m.name.clone()).unwrap_or_default(),
                    material,
                    span: object.span,
                });
            } else if normal_mapped && tangents[mesh].is_empty() {
                tangents[mesh] = vertex_tangents(&self.meshes[mesh]);
            }
        }
        tangents
    }

    /// Constant environments add up; the first image is loaded (a second is an error).
    fn environment(&mut self) -> Option<Environment> {
        let mut env: Option<Environment> = None;
        let mut image_seen = false;
        for light in &self.desc.lights {
            let ir::Light::Environment(e) = light else {
                continue;
            };
            let env = env.get_or_insert_with(|| Environment::new(Vec3::ZERO, None, false));
            env.visible |= e.visible;
            match &e.source {
                EnvSource::Constant(c) => env.constant += *c * e.intensity,
                EnvSource::Image(file) if image_seen => {
                    self.problems.push(BuildError::Unsupported {
                        what: format!("a second environment image (`{}`)", file.written),
                        span: file.span,
                        help: "merge the maps into one image, or keep one".into(),
                    })
                }
                EnvSource::Image(file) => {
                    image_seen = true;
                    let (map, problems) = match self.cache.as_deref_mut() {
                        Some(cache) => {
                            cache.load_env_map(file, e.intensity, e.rotation_y_rad, self.loader)
                        }
                        None => load_env_map(file, e.intensity, e.rotation_y_rad, self.loader),
                    };
                    self.problems.extend(problems);
                    env.map = map;
                }
            }
        }
        env
    }

    /// Radius of the bounding sphere of every instance (0 with none).
    fn scene_radius(&self, instances: &[SceneInstance]) -> f32 {
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for inst in instances {
            for &p in &self.meshes[inst.mesh as usize].positions {
                let w = inst.world_from_object.transform_point3(p);
                lo = lo.min(w);
                hi = hi.max(w);
            }
        }
        if lo.cmple(hi).all() {
            (hi - lo).length() / 2.0
        } else {
            0.0
        }
    }

    /// The lights and their table. The environment's sampling tables are built only when there
    /// is geometry for it to light.
    fn lights(
        &mut self,
        instances: &mut Vec<SceneInstance>,
        mut env: Option<Environment>,
        parts: &mut PartTables,
    ) -> Lights {
        // Only a one-sided area light asks where the geometry is.
        let one_sided = |l: &ir::Light| matches!(l, ir::Light::Area(a) if !a.two_sided);
        let boxes = if self.desc.lights.iter().any(one_sided) {
            world_boxes(&self.meshes, instances)
        } else {
            Vec::new()
        };
        let mut lights = Vec::new();
        for light in &self.desc.lights {
            match light {
                ir::Light::Point(p) => lights.push(Light::Point(PointLight {
                    position: origin::relative(p.position, self.origin),
                    intensity: p.intensity,
                })),
                ir::Light::Area(a) => {
                    let Some(mesh) = self.mesh(a.mesh) else {
                        continue;
                    };
                    let Some((world_from_object, normal_from_object)) =
                        self.transform(a.world_from_object, a.span)
                    else {
                        continue;
                    };
                    self.check_resolution(a.mesh, a.world_from_object, a.span, mesh);
                    let m = &self.meshes[mesh as usize];
                    let world: Vec<[Vec3; 3]> = m
                        .triangles
                        .iter()
                        .map(|t| {
                            t.map(|i| world_from_object.transform_point3(m.positions[i as usize]))
                        })
                        .collect();
                    if !a.two_sided && faces_away(&world, &boxes) {
                        self.problems.push(BuildError::LightFacesAway {
                            light: a.name.clone(),
                            span: a.span,
                        });
                    }
                    if let Some(area) = AreaLight::new(a.radiance, a.two_sided, a.samples, world) {
                        instances.push(SceneInstance {
                            mesh,
                            surface: Surface::Emitter(lights.len() as u32),
                            world_from_object,
                            normal_from_object,
                            part_base: super::obj_parts::NO_PARTS,
                        });
                        lights.push(Light::Area(area));
                    }
                }
                ir::Light::Environment(_) => {}
            }
        }
        parts.attach(&mut lights);
        let mut radius = 0.0;
        if let Some(e) = env.as_mut().filter(|_| !instances.is_empty()) {
            e.prepare_sampling();
            radius = self.scene_radius(instances);
        }
        Lights::new(lights, env, radius)
    }

    /// The affine map and its normal matrix, or an error if it cannot place anything.
    fn transform(&mut self, m: glam::DMat4, span: Span) -> Option<(Affine3A, Mat3)> {
        let affine = origin::recentred(m, self.origin);
        let linear = Mat3::from(affine.matrix3);
        let det = linear.determinant();
        if !(det.is_finite() && det != 0.0 && m.is_finite()) {
            self.problems.push(BuildError::SingularTransform { span });
            return None;
        }
        Some((affine, linear.inverse().transpose()))
    }

    /// Loads (once) and validates mesh `id`; `None` if it failed (the problem is recorded).
    fn mesh(&mut self, id: ir::MeshId) -> Option<u32> {
        let slot = self.mesh_slots.get(id as usize)?;
        if let Some(done) = slot {
            return *done;
        }
        let decl = self.desc.meshes.get(id as usize)?;
        let loaded = match self.cache.as_deref_mut() {
            Some(cache) => cache.load_mesh(decl, self.loader),
            None => load_mesh(decl, self.loader),
        };
        let index = match loaded {
            Ok((mesh, warning)) => {
                self.problems.extend(warning);
                self.meshes.push(mesh);
                Some(self.meshes.len() as u32 - 1)
            }
            Err(e) => {
                self.problems.push(e);
                None
            }
        };
        self.mesh_slots[id as usize] = Some(index);
        index
    }
}
