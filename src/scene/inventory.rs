//! Stage 3 → `--stats`: what [`Scene`] built and the memory each structure holds.
//!
//! The build makes only what a scene uses (see `build`); this lists it, one line per kind of
//! structure, so a user can see that a scene without textures, an environment or specular
//! materials carries none of their tables. `tests/accuracy_model_only.rs` asserts it, together
//! with the per-sample counters of `render::integrator::RayCounts`.
//!
//! No `.scn` syntax of its own.

use std::mem::size_of;
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::Scene;
use crate::shade::texture::image::ImageData;
use crate::shade::{Light, Texture};

/// One kind of built structure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Built {
    /// Stable short name: `meshes`, `bvh`, `textures`, `tangents`, `light table`, `environment map`,
    /// `environment table`.
    pub what: &'static str,
    /// Human-readable detail (counts, sizes, mip levels).
    pub detail: String,
    /// Heap memory, bytes.
    pub bytes: usize,
}

/// Which optional features the scene's materials and lights use (decided at build time; the
/// per-sample loop checks them through the same data, never more).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Features {
    /// A used material looks up a texture.
    pub textures: bool,
    /// A used material has a specular lobe.
    pub specular: bool,
    /// The scene has an environment light.
    pub environment: bool,
    /// The scene has area lights (emitting geometry).
    pub area_lights: bool,
}

impl Scene {
    /// The optional features this scene actually has.
    pub fn features(&self) -> Features {
        let used: Vec<&super::SurfaceMaterial> = self
            .instances
            .iter()
            .filter_map(|i| match i.surface {
                super::Surface::Material(m) => self.materials.get(m as usize),
                super::Surface::Emitter(_) => None,
            })
            .collect();
        Features {
            textures: self.textures.slots.iter().any(Option::is_some),
            specular: used.iter().any(
                |m| !matches!(m.specular, crate::ir::ColorInput::Constant(c) if c == Vec3::ZERO),
            ),
            environment: self.lights.environment.is_some(),
            area_lights: self.lights.has_emitters(),
        }
    }

    /// Every structure the build made, with its memory. Kinds the scene does not use are absent.
    pub fn inventory(&self) -> Vec<Built> {
        let mut out: Vec<Built> = [
            self.mesh_inventory(),
            self.bvh_inventory(),
            self.texture_inventory(),
            self.tangent_inventory(),
            self.light_table_inventory(),
        ]
        .into_iter()
        .flatten()
        .collect();
        out.extend(self.environment_inventory());
        out
    }

    fn mesh_inventory(&self) -> Option<Built> {
        if self.meshes.is_empty() {
            return None;
        }
        let (mut tris, mut bytes) = (0, 0);
        for m in &self.meshes {
            tris += m.triangles.len();
            bytes += m.positions.len() * size_of::<Vec3>()
                + m.normals.len() * size_of::<Vec3>()
                + m.uvs.len() * size_of::<Vec2>()
                + m.triangles.len() * size_of::<[u32; 3]>();
        }
        // The face normals computed at the build for unmoved placements (`face_normals`).
        bytes += self.face_normals.iter().map(Vec::len).sum::<usize>() * size_of::<Vec3>();
        Some(Built {
            what: "meshes",
            detail: format!(
                "{} meshes, {tris} triangles, {} instances",
                self.meshes.len(),
                self.instances.len()
            ),
            bytes,
        })
    }

    fn bvh_inventory(&self) -> Option<Built> {
        self.accel.as_ref()?;
        let a = self.accel_stats();
        Some(Built {
            what: "bvh",
            detail: format!(
                "{} nodes, {} leaves, {} triangles",
                a.nodes, a.leaves, a.triangles
            ),
            bytes: a.bytes,
        })
    }

    fn texture_inventory(&self) -> Option<Built> {
        let textures: Vec<&Texture> = self.textures.slots.iter().flatten().collect();
        if textures.is_empty() {
            return None;
        }
        let (mut constant, mut checker, mut image) = (0, 0, 0);
        let mut bytes = textures.len() * size_of::<Texture>();
        // Images shared by several textures are counted once.
        let mut seen: Vec<*const ImageData> = Vec::new();
        let mut images = Vec::new();
        for t in &textures {
            match t {
                Texture::Constant(_) => constant += 1,
                Texture::Checker { .. } => checker += 1,
                Texture::Image { data, .. } => {
                    image += 1;
                    let ptr = Arc::as_ptr(data);
                    if !seen.contains(&ptr) {
                        seen.push(ptr);
                        bytes += data.bytes();
                        images.push(image_detail(data));
                    }
                }
            }
        }
        let files = if images.is_empty() {
            String::new()
        } else {
            format!(": {}", images.join(", "))
        };
        Some(Built {
            what: "textures",
            detail: format!(
                "{} built ({constant} constant, {checker} procedural checker, {image} image from {} file{}){files}",
                textures.len(),
                seen.len(),
                if seen.len() == 1 { "" } else { "s" }
            ),
            bytes,
        })
    }

    fn tangent_inventory(&self) -> Option<Built> {
        let tangents: usize = self.tangents.iter().map(Vec::len).sum();
        (tangents > 0).then(|| Built {
            what: "tangents",
            detail: format!("{tangents} per-vertex tangents for normal maps"),
            bytes: tangents * size_of::<glam::Vec4>(),
        })
    }

    fn light_table_inventory(&self) -> Option<Built> {
        let table = self.lights.by_power.as_ref()?;
        let (mut points, mut areas, mut area_tris, mut bytes) = (0, 0, 0, table.bytes());
        for light in &self.lights.lights {
            match light {
                Light::Point(_) => points += 1,
                Light::Area(a) => {
                    areas += 1;
                    area_tris += a.triangles.len();
                    bytes += a.bytes();
                }
            }
        }
        Some(Built {
            what: "light table",
            detail: format!(
                "{} entries by power: {points} point, {areas} area ({area_tris} triangles){}",
                table.len(),
                if self.lights.pmf_environment() > 0.0 {
                    ", environment"
                } else {
                    ""
                }
            ),
            bytes,
        })
    }

    fn environment_inventory(&self) -> Vec<Built> {
        let Some(map) = self
            .lights
            .environment
            .as_ref()
            .and_then(|e| e.map.as_ref())
        else {
            return Vec::new();
        };
        let (w, h) = map.size();
        let (texels, table) = map.bytes();
        let mut out = vec![Built {
            what: "environment map",
            detail: format!("{w}x{h} texels"),
            bytes: texels,
        }];
        if map.has_distribution() {
            out.push(Built {
                what: "environment table",
                detail: format!(
                    "{w}x{h} luminance x sin(theta), in {}x{} cells, weighted for {} of {} normal bins (built on first use)",
                    crate::shade::light::env_sampler::CELLS_X.min(w),
                    crate::shade::light::env_sampler::CELLS_Y.min(h),
                    map.normal_bins_built(),
                    crate::shade::light::env_sampler::NORMAL_BINS.pow(2)
                ),
                bytes: table,
            });
        }
        out
    }
}

/// `512x256 10 mip levels`.
fn image_detail(data: &ImageData) -> String {
    format!(
        "{}x{} {} mip level{}",
        data.width(),
        data.height(),
        data.levels.len(),
        if data.levels.len() == 1 { "" } else { "s" }
    )
}
