//! Stage 3, inside [`build`](super::build): the asset phase (camera, materials, environment,
//! every object's mesh and placement, lights, tangents) and the acceleration structure over
//! the placed meshes.

use glam::Vec4;

use super::super::mesh::TriMesh;
use super::super::obj_parts::PartTables;
use super::super::{BuildError, BuildOptions, SceneInstance, Surface, SurfaceMaterial, Textures};
use super::Builder;
use crate::bvh::{Accel, Instance, MeshRef};
use crate::ir;
use crate::shade::Lights;

/// What the asset phase made, before the acceleration structure.
pub(super) struct Assembled {
    pub(super) camera: ir::Camera,
    pub(super) materials: Vec<SurfaceMaterial>,
    pub(super) textures: Textures,
    pub(super) instances: Vec<SceneInstance>,
    pub(super) parts: PartTables,
    pub(super) lights: Lights,
    pub(super) tangents: Vec<Vec<Vec4>>,
}

impl Builder<'_> {
    /// Loads and places everything the scene uses; `None` without a camera (recorded as a
    /// problem). Problems of every other kind are recorded and the rest still built, so one
    /// build reports them all.
    pub(super) fn assemble(&mut self, options: &BuildOptions) -> Option<Assembled> {
        let desc = self.desc;
        let camera_index = options.camera.unwrap_or(desc.active_camera);
        let mut camera = desc.cameras.get(camera_index).cloned();
        if camera.is_none() {
            self.problems.push(BuildError::NoCamera {
                which: match options.camera {
                    Some(i) => format!("number {i}"),
                    None => "to render from".into(),
                },
            });
        }
        let (mut materials, mut textures) = self.materials();
        let mut parts = PartTables::default();
        let environment = self.environment();
        // Every position from here on is relative to the world origin (`origin.rs`).
        self.origin = self.world_origin();
        if let Some(c) = camera.as_mut() {
            c.eye -= self.origin;
        }
        let mut instances = Vec::new();
        for object in &desc.objects {
            let Some(mesh) = self.mesh(object.mesh) else {
                continue;
            };
            let Some((world_from_object, normal_from_object)) =
                self.transform(object.world_from_object, object.span)
            else {
                continue;
            };
            let part_base = parts.place(
                &self.meshes[mesh as usize],
                desc.meshes[object.mesh as usize].obj_options(),
                object.material,
                world_from_object,
                &mut materials,
                &mut textures,
            );
            instances.push(SceneInstance {
                mesh,
                surface: Surface::Material(object.material),
                world_from_object,
                normal_from_object,
                part_base,
            });
            self.check_resolution(object.mesh, object.world_from_object, object.span, mesh);
        }
        let lights = self.lights(&mut instances, environment, &mut parts);
        self.problems.append(&mut parts.unknown);
        let tangents = self.uvs_and_tangents();
        Some(Assembled {
            camera: camera?,
            materials,
            textures,
            instances,
            parts,
            lights,
            tangents,
        })
    }

    /// The acceleration structure over every instance (from the cache when there is one);
    /// `None` when there are no triangles.
    pub(super) fn accel(
        &mut self,
        instances: &[SceneInstance],
        options: &BuildOptions,
    ) -> Option<Accel> {
        let triangles: usize = instances
            .iter()
            .map(|i| self.meshes[i.mesh as usize].triangles.len())
            .sum();
        if triangles == 0 {
            return None;
        }
        if let Some(cache) = self.cache.as_deref_mut() {
            return Some(cache.accel(&self.meshes, instances, options.accel));
        }
        let refs: Vec<MeshRef<'_>> = self.meshes.iter().map(TriMesh::as_mesh_ref).collect();
        let accel_instances: Vec<Instance> = instances
            .iter()
            .map(|i| Instance::new(i.mesh, i.world_from_object))
            .collect();
        Some(Accel::build(&refs, &accel_instances, options.accel))
    }
}
