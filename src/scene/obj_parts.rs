//! Stage 3: the materials of an OBJ mesh in the scene (`mesh m = obj("m.obj")` whose faces
//! say `usemtl`). Each `usemtl` name is a [`MeshPart`]; its MTL material becomes a Phong
//! material of the scene, or, with `Ke` > 0, an area light over that part's triangles (per
//! placement). Faces with no material, or one no library defines, use the placing `object`'s
//! material; `mesh m = obj("m.obj") { material "roof tiles" slate }` replaces an OBJ material
//! by a scene material (by `usemtl` name), `mtl false` skips the libraries altogether. The renderer asks [`Scene::surface_of`] which surface a triangle has.

use glam::{Affine3A, Vec3};

use super::mesh::{MeshPart, TriMesh};
use super::{BuildError, Scene, SceneInstance, Surface, SurfaceMaterial};
use std::path::PathBuf;
use std::sync::Arc;

use super::mesh::PartMaps;
use crate::assets::obj::phong::{phong_of, renders_map, ObjPhong};
use crate::assets::obj::report::{line_label, mtl_display_name};
use crate::assets::obj::{LoadedObj, TexRef};
use crate::assets::texture_image::{decode_texture, ImageError, MAX_TEXTURE_SIDE};
use crate::assets::Loader;
use crate::diag::{Code, Diagnostic};
use crate::ir::{
    ColorInput, Filter, GreenConvention, NormalMap, ObjOptions, ScalarInput, WrapMode,
};
use crate::shade::texture::image::ImageData;
use crate::shade::{AreaLight, Light, Texture, Textures};
use crate::source::Span;

/// `SceneInstance::part_base` of an instance whose mesh has no parts.
pub const NO_PARTS: u32 = u32::MAX;

/// The parts of a loaded OBJ and each triangle's part (empty when the whole mesh uses the
/// object's material), plus a warning per material whose texture maps are not rendered.
pub(super) fn parts_of(
    obj: &LoadedObj,
    written: &str,
    span: Span,
    loader: &dyn Loader,
) -> (Vec<MeshPart>, Vec<u32>, Vec<BuildError>) {
    let m = &obj.model;
    let mut maps = MapReader {
        obj,
        written,
        span,
        loader,
        decoded: Vec::new(),
        warnings: Vec::new(),
    };
    let mut parts: Vec<MeshPart> = Vec::new();
    let mut run_part = Vec::with_capacity(m.runs.len());
    for run in &m.runs {
        let index = match parts.iter().position(|p| p.name == run.name) {
            Some(i) => i,
            None => {
                parts.push(maps.part(run.name.as_deref()));
                parts.len() - 1
            }
        };
        run_part.push(index as u32);
    }
    if parts.iter().all(|p| p.name.is_none()) {
        return (Vec::new(), Vec::new(), maps.warnings);
    }
    let mut part_of = Vec::new();
    if parts.len() > 1 {
        part_of.reserve_exact(m.triangles.len());
        for (i, run) in m.runs.iter().enumerate() {
            let end = m.runs.get(i + 1).map_or(m.triangles.len(), |r| r.start);
            part_of.resize(end.max(part_of.len()), run_part[i]);
            debug_assert!(run.start <= end);
        }
    }
    (parts, part_of, maps.warnings)
}

/// Makes the parts of one OBJ: their MTL materials, and the texture maps those name.
struct MapReader<'a> {
    obj: &'a LoadedObj,
    written: &'a str,
    span: Span,
    loader: &'a dyn Loader,
    /// Maps decoded so far in this OBJ, by path and sRGB-ness: one decode however many parts
    /// name a file.
    decoded: Vec<(PathBuf, bool, Arc<ImageData>)>,
    warnings: Vec<BuildError>,
}

impl MapReader<'_> {
    /// The part of `usemtl name`: its MTL material (if a library defines it) and maps.
    fn part(&mut self, name: Option<&str>) -> MeshPart {
        let found = name.and_then(|n| self.obj.find_material(n));
        let mut maps = PartMaps::default();
        let phong = found.map(|(l, i)| {
            let src = &self.obj.mtls[l];
            let mat = &src.library.materials[i];
            let phong = phong_of(mat);
            for (key, tex) in &phong.maps {
                if let Err(d) = self.map(&mut maps, key, tex, l, &mat.name) {
                    let file = mtl_display_name(self.written, &src.written);
                    self.warnings.push(BuildError::Obj(Box::new(
                        (*d).in_file(line_label(&file, &src.text, tex.at, "this map"))
                            .at(self.span, "the OBJ file named here"),
                    )));
                }
            }
            phong
        });
        MeshPart {
            name: name.map(str::to_string),
            phong,
            maps,
        }
    }

    /// Sets map `key` of a part of library `lib` (decoding the file once per OBJ), or says
    /// why it is not rendered.
    fn map(
        &mut self,
        maps: &mut PartMaps,
        key: &str,
        tex: &TexRef,
        lib: usize,
        material: &str,
    ) -> Result<(), Box<Diagnostic>> {
        let src = &self.obj.mtls[lib];
        // Read through the Loader, so `scnc watch` watches it too.
        let dir = src.path.parent().unwrap_or(std::path::Path::new(""));
        let path = dir.join(&tex.file);
        let srgb = key != "norm";
        let earlier = self
            .decoded
            .iter()
            .find(|(p, s, _)| *p == path && *s == srgb)
            .map(|(_, _, data)| data.clone());
        if let (Some(data), true) = (earlier, renders_map(key)) {
            maps.set(key, data, tex.bump_multiplier);
            return Ok(());
        }
        let bytes = self.loader.read(&path).map_err(|e| {
            Box::new(Diagnostic::warning(
                Code::ObjMissingTexture,
                format!("cannot read the texture `{}` of material `{material}` ({e}); its constant colour is used", tex.file),
            )
            .help("texture paths in an MTL are relative to the MTL file"))
        })?;
        if !renders_map(key) {
            return Err(Box::new(Diagnostic::warning(
                Code::ObjTextureNotRendered,
                format!("`{key} {}` of material `{material}` is not rendered; its constant is used", tex.file),
            )
            .help("scnc renders `map_Kd`, `map_Ks` and `norm` (normal maps); for others declare a `texture … = image(…)` and replace this material with `material NAME mat` in the mesh's block")));
        }
        let img = decode_texture(&bytes, srgb).map_err(|e| {
            Box::new(Diagnostic::warning(
                Code::ObjBadTexture,
                format!("the texture `{}` of material `{material}` cannot be used ({}); its constant colour is used", tex.file, match e {
                    ImageError::Corrupt(reason) => reason,
                    ImageError::TooLarge { width, height } => format!("{width} x {height} is beyond the {MAX_TEXTURE_SIDE} x {MAX_TEXTURE_SIDE} cap"),
                }),
            ))
        })?;
        let data = Arc::new(ImageData::new(img.width, img.height, img.texels, true));
        self.decoded.push((path, srgb, data.clone()));
        maps.set(key, data, tex.bump_multiplier);
        Ok(())
    }
}

/// Surfaces of OBJ parts, per placement, and the area lights of their emissive parts.
#[derive(Debug, Default)]
pub(super) struct PartTables {
    /// Every placement's part surfaces, in placement order.
    pub surfaces: Vec<Surface>,
    /// (index into `surfaces`, the light): numbered once every other light is known.
    pending: Vec<(usize, AreaLight)>,
    /// `.scn` overrides naming no `usemtl` of their OBJ (each reported once).
    pub unknown: Vec<BuildError>,
}

impl PartTables {
    /// Surfaces for one placement of `mesh`; returns its `part_base` ([`NO_PARTS`] if none).
    /// `options` are the mesh's `.scn` overrides (`obj("f.obj") { material NAME mat }`).
    pub fn place(
        &mut self,
        mesh: &TriMesh,
        options: &ObjOptions,
        object_material: u32,
        world_from_object: Affine3A,
        materials: &mut Vec<SurfaceMaterial>,
        textures: &mut Textures,
    ) -> u32 {
        self.check_overrides(mesh, options);
        let overridden = |p: &MeshPart| {
            options
                .materials
                .iter()
                .find(|o| p.name.as_deref() == Some(&o.obj_name))
                .map(|o| o.material)
        };
        if mesh
            .parts
            .iter()
            .all(|p| p.phong.is_none() && overridden(p).is_none())
        {
            return NO_PARTS;
        }
        let base = self.surfaces.len() as u32;
        for (i, part) in mesh.parts.iter().enumerate() {
            let surface = match (&part.phong, overridden(part)) {
                (_, Some(m)) => Surface::Material(m),
                (None, None) => Surface::Material(object_material),
                (Some(p), None) if p.is_emitter() => {
                    let world = part_triangles(mesh, i, world_from_object);
                    match AreaLight::new(p.emission, false, 1, world) {
                        Some(light) => {
                            self.pending.push((self.surfaces.len(), light));
                            Surface::Emitter(0)
                        }
                        None => Surface::Material(object_material),
                    }
                }
                (Some(p), None) => {
                    materials.push(part_material(p, &part.maps, textures));
                    Surface::Material(materials.len() as u32 - 1)
                }
            };
            self.surfaces.push(surface);
        }
        base
    }

    /// Warns (once per override) about `.scn` overrides naming no `usemtl` of the OBJ.
    fn check_overrides(&mut self, mesh: &TriMesh, options: &ObjOptions) {
        for o in &options.materials {
            let known = mesh
                .parts
                .iter()
                .any(|p| p.name.as_deref() == Some(&o.obj_name));
            if !known && !self.unknown.iter().any(|u| matches!(u, BuildError::Obj(d) if d.primary.as_ref().is_some_and(|l| l.span == o.span))) {
                let names: Vec<String> = mesh.parts.iter().filter_map(|p| p.name.clone()).map(|n| format!("`{n}`")).collect();
                self.unknown.push(BuildError::Obj(Box::new(
                    Diagnostic::warning(
                        Code::ObjUnknownOverride,
                        format!("the OBJ has no material `{}` to replace", o.obj_name),
                    )
                    .at(o.span, "no `usemtl` of this name")
                    .help(if names.is_empty() {
                        "the OBJ uses no `usemtl` at all".to_string()
                    } else {
                        format!("its materials are {}", names.join(", "))
                    }),
                )));
            }
        }
    }

    /// Appends the emissive parts' lights after `lights` and points their surfaces at them.
    pub fn attach(&mut self, lights: &mut Vec<Light>) {
        for (slot, light) in self.pending.drain(..) {
            self.surfaces[slot] = Surface::Emitter(lights.len() as u32);
            lights.push(Light::Area(light));
        }
    }
}

/// Part `part`'s triangles of `mesh`, in world space.
fn part_triangles(mesh: &TriMesh, part: usize, world_from_object: Affine3A) -> Vec<[Vec3; 3]> {
    mesh.triangles
        .iter()
        .enumerate()
        .filter(|(t, _)| mesh.part_of.get(*t).map_or(0, |&p| p as usize) == part)
        .map(|(_, tri)| tri.map(|v| world_from_object.transform_point3(mesh.positions[v as usize])))
        .collect()
}

/// An MTL material as a scene material, its maps added to `textures`.
fn part_material(p: &ObjPhong, maps: &PartMaps, textures: &mut Textures) -> SurfaceMaterial {
    let mut image = |data: &Arc<ImageData>| {
        textures.slots.push(Some(Texture::Image {
            data: data.clone(),
            wrap: WrapMode::Repeat,
            filter: Filter::Anisotropic,
        }));
        textures.slots.len() as u32 - 1
    };
    let color = |map: Option<u32>, constant: Vec3| {
        map.map_or(ColorInput::Constant(constant), ColorInput::Texture)
    };
    let diffuse = color(maps.diffuse.as_ref().map(&mut image), p.diffuse);
    let specular = color(maps.specular.as_ref().map(&mut image), p.specular);
    let normal_map = maps.normal.as_ref().map(|(data, strength)| NormalMap {
        texture: image(data),
        strength: *strength,
        green: GreenConvention::OpenGl,
    });
    SurfaceMaterial {
        diffuse,
        specular,
        shininess: ScalarInput::Constant(p.shininess),
        ambient: Vec3::ZERO,
        normal_map,
    }
}

impl Scene {
    /// What triangle `prim` of instance `inst` (placing `mesh`) is: its OBJ part's surface, or
    /// the instance's.
    pub fn surface_of(&self, inst: &SceneInstance, mesh: &TriMesh, prim: u32) -> Surface {
        if inst.part_base == NO_PARTS {
            return inst.surface;
        }
        let part = mesh.part_of.get(prim as usize).copied().unwrap_or(0);
        self.part_surfaces
            .get((inst.part_base + part) as usize)
            .copied()
            .unwrap_or(inst.surface)
    }
}
