//! Stage 3, scene build: the materials and the textures they reach.
//!
//! Syntax given meaning here: `material m = phong { diffuse T  specular T  shininess T
//! normal_map T  normal_strength s  normal_green opengl|directx }` and `texture T = image(…) |
//! checker {…} | constant {…}`. Only textures reachable from materials that objects use are
//! built. Image files are grouped by (path, encoding): each is read and decoded once however
//! many textures and materials name it, and its mip pyramid is built once, only when one of
//! those textures is mip-filtered (trilinear or anisotropic). Each failure is one error at the
//! path literal.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

use super::Builder;
use crate::ir::{self, ColorInput, ScalarInput, TextureEncoding, TextureSource};
use crate::scene::texture_load::load_image_texture;
use crate::scene::SurfaceMaterial;
use crate::shade::texture::image::ImageData;
use crate::shade::{Texture, Textures};

/// The textures a material looks up directly (its inputs and normal map).
pub(super) fn texture_roots(m: &ir::Material) -> Vec<ir::TextureId> {
    let mut roots = Vec::new();
    for input in [m.diffuse, m.specular] {
        if let ColorInput::Texture(t) = input {
            roots.push(t);
        }
    }
    if let ScalarInput::Texture(t) = m.shininess {
        roots.push(t);
    }
    if let Some(n) = &m.normal_map {
        roots.push(n.texture);
    }
    roots
}

impl Builder<'_> {
    pub(super) fn materials(&mut self) -> (Vec<SurfaceMaterial>, Textures) {
        let mut reachable = vec![false; self.desc.textures.len()];
        for o in &self.desc.objects {
            if let Some(m) = self.desc.materials.get(o.material as usize) {
                for t in texture_roots(m) {
                    self.reach(t, &mut reachable);
                }
            }
        }
        // One load per (file, encoding); mipmaps if any texture on it is mip-filtered.
        let mut files: BTreeMap<(PathBuf, bool), (&ir::AssetPath, TextureEncoding, bool)> =
            BTreeMap::new();
        for (t, _) in reachable.iter().enumerate().filter(|(_, r)| **r) {
            if let TextureSource::Image {
                file,
                encoding,
                filter,
                ..
            } = &self.desc.textures[t].source
            {
                let key = (file.path.clone(), *encoding == TextureEncoding::Srgb);
                let entry = files.entry(key).or_insert((file, *encoding, false));
                entry.2 |= filter.is_mip_filtered();
            }
        }
        let mut loaded: BTreeMap<(PathBuf, bool), Arc<ImageData>> = BTreeMap::new();
        for (key, (file, encoding, mipmaps)) in files {
            let result = match self.cache.as_deref_mut() {
                Some(cache) => cache.load_texture(file, encoding, mipmaps, self.loader),
                None => load_image_texture(file, encoding, mipmaps, self.loader),
            };
            match result {
                Ok(data) => {
                    loaded.insert(key, data);
                }
                Err(e) => self.problems.push(e),
            }
        }
        let mut textures = Textures {
            slots: vec![None; self.desc.textures.len()],
        };
        for (t, decl) in self.desc.textures.iter().enumerate() {
            if !reachable[t] {
                continue;
            }
            textures.slots[t] = match &decl.source {
                TextureSource::Constant(c) => Some(Texture::Constant(*c)),
                TextureSource::Checker { even, odd, scale } => Some(Texture::Checker {
                    even: *even,
                    odd: *odd,
                    scale: *scale,
                }),
                TextureSource::Image {
                    file,
                    encoding,
                    wrap,
                    filter,
                } => loaded
                    .get(&(file.path.clone(), *encoding == TextureEncoding::Srgb))
                    .map(|data| Texture::Image {
                        data: data.clone(),
                        wrap: *wrap,
                        filter: *filter,
                    }),
            };
        }
        let materials = self
            .desc
            .materials
            .iter()
            .map(|m| SurfaceMaterial {
                diffuse: m.diffuse,
                specular: m.specular,
                shininess: m.shininess,
                ambient: m.ambient,
                normal_map: m.normal_map.clone(),
            })
            .collect();
        (materials, textures)
    }

    /// Marks `id` and the textures it nests (checker squares) as reachable.
    fn reach(&self, id: ir::TextureId, reachable: &mut [bool]) {
        let Some(seen) = reachable.get_mut(id as usize) else {
            return;
        };
        if std::mem::replace(seen, true) {
            return;
        }
        if let Some(TextureSource::Checker { even, odd, .. }) =
            self.desc.textures.get(id as usize).map(|t| &t.source)
        {
            for input in [*even, *odd] {
                if let ColorInput::Texture(inner) = input {
                    self.reach(inner, reachable);
                }
            }
        }
    }
}
