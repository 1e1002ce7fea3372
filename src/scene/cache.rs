//! Stage 3, between builds: [`BuildCache`] keeps what an earlier [`build_cached`] loaded and
//! built, so that `scnc watch` redoes only what an edit changed.
//!
//! No syntax of its own; it memoises the work behind `mesh … = obj(…) | inline {…} | quad |
//! box | sphere` and behind the placement of `object`s and area lights:
//! - a loaded, validated mesh, keyed by its source ([`MeshKey`]: the OBJ path, or a hash of the
//!   inline arrays / built-in shape parameters) and, for files, the content hash of the bytes it
//!   was loaded from. The caller reports current content hashes through
//!   [`BuildCache::retain_current`]; an entry whose file changed is dropped, an unchanged file
//!   is not read again.
//! - the acceleration structure, keyed by its kind and the list of (mesh key, transform) of
//!   every instance: a camera, material, light-colour or render-setting edit reuses it. When
//!   an instance moved, the BVH's top level is built again beside the last one's trace, which
//!   copies the subtrees over unmoved instances (the same tree as a fresh build, bit for bit).
//! - the environment map (`light … = environment { image(…) }`), decoded, cleaned, scaled and
//!   with its sampling table, keyed by path, intensity and rotation and by the content hash of
//!   the file: an edit elsewhere neither re-reads the image nor rebuilds its table.
//! - image textures (`texture t = image(…)`), decoded and with their mip pyramid, keyed by
//!   path, encoding and whether the pyramid was built, and by the content hash of the file: a
//!   material edit does not reload them. They are shared (`Arc`), so the cache keeps its own
//!   handle and nothing needs recycling.
//!
//! Entries are moved into the new scene (no copy of a 1M-triangle mesh or its BVH); hand the
//! scene back with [`BuildCache::recycle`] when it is no longer rendered.
//!
//! [`build_cached`]: super::build_cached

use std::collections::HashMap;
use std::hash::Hash;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use super::env_load::load_env_map;
use super::load::load_mesh;
use super::mesh::TriMesh;
use super::texture_load::load_image_texture;
use super::{BuildError, Scene, SceneInstance};
use crate::assets::Loader;
use crate::bvh::{Accel, AccelKind, BuildTrace, Instance, MeshRef};
use crate::ir::{self, AssetPath, MeshSource, TextureEncoding};
use crate::shade::texture::image::ImageData;
use crate::shade::EnvMap;

/// A hash of file contents (64-bit foldhash with a fixed seed: stable within and across runs of
/// one build of scnc, which is all a cache needs).
pub fn content_hash(bytes: &[u8]) -> u64 {
    // A fixed seed: the same bytes give the same hash in every run (foldhash's quality
    // variant; it is compared only within one process, never stored).
    use std::hash::BuildHasher;
    foldhash::quality::FixedState::with_seed(0x5c4e_c0de_5eed_0001).hash_one(bytes)
}

/// What a mesh was made from, without its span (moving a declaration is not a change).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum MeshKey {
    /// The OBJ's path, and whether its MTL libraries were skipped (`mtl false`).
    Obj(PathBuf, bool),
    /// Hash of the serialised inline arrays or built-in shape parameters.
    Data(u64),
}

impl MeshKey {
    /// The key of a mesh declaration's source and OBJ options.
    pub fn of(source: &MeshSource, obj: &crate::ir::ObjOptions) -> MeshKey {
        let json = match source {
            MeshSource::Obj(path) => return MeshKey::Obj(path.path.clone(), obj.ignore_mtl),
            MeshSource::Inline(m) => serde_json::to_vec(m),
            MeshSource::Builtin(shape) => serde_json::to_vec(shape),
        };
        // Serialising plain numbers cannot fail; an empty key would only cost a reload.
        MeshKey::Data(content_hash(&json.unwrap_or_default()))
    }
}

/// What one [`build_cached`](super::build_cached) did, for the watch status line.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CacheReport {
    /// Meshes loaded (read, parsed, tessellated or validated) in this build.
    pub meshes_loaded: usize,
    /// Meshes taken from the cache.
    pub meshes_reused: usize,
    /// Whether the acceleration structure was built (false: reused or no triangles).
    pub accel_built: bool,
    /// Whether an environment map was read and decoded (false: reused or none).
    pub environment_loaded: bool,
    /// Image textures read and decoded in this build.
    pub textures_loaded: usize,
    /// Image textures taken from the cache.
    pub textures_reused: usize,
}

impl CacheReport {
    /// Names of what was rebuilt: `"meshes"`, `"bvh"`.
    pub fn rebuilt(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        if self.meshes_loaded > 0 {
            out.push("meshes");
        }
        if self.accel_built {
            out.push("bvh");
        }
        if self.environment_loaded {
            out.push("environment");
        }
        if self.textures_loaded > 0 {
            out.push("textures");
        }
        out
    }
}

#[derive(Debug)]
struct CachedMesh {
    mesh: TriMesh,
    /// Content hash of the OBJ file it came from (`None` for inline and built-in meshes).
    file_hash: Option<u64>,
    /// The other files its load read (an OBJ's MTL libraries and their texture maps) and
    /// their content hashes (`None`: could not be read): a change to any reloads the mesh.
    deps: Vec<(PathBuf, Option<u64>)>,
}

/// An environment map's file, intensity bits and rotation bits.
type EnvKey = (PathBuf, u32, u32);

#[derive(Debug)]
struct CachedEnvMap {
    map: EnvMap,
    file_hash: Option<u64>,
}

/// An image texture's file, whether it is sRGB-decoded, and whether it has its pyramid.
type TextureKey = (PathBuf, bool, bool);

/// Per instance: the mesh, the content hash of its file, and the transform's bits.
type AccelKey = (AccelKind, Vec<(MeshKey, Option<u64>, [u32; 12])>);

/// Meshes and acceleration structure kept between builds. See the module doc.
#[derive(Debug, Default)]
pub struct BuildCache {
    meshes: HashMap<MeshKey, CachedMesh>,
    accel: Option<(AccelKey, Accel)>,
    /// The trace of the last BVH built (its top level's input and nodes): the next build after
    /// an instance moved copies its subtrees over unmoved instances (`bvh::BuildTrace`).
    top_trace: Option<BuildTrace>,
    /// Keys (and file hashes) of the meshes of the scene built last, in its mesh order.
    current: Vec<(MeshKey, Option<u64>)>,
    /// Per entry of `current`: the other files its load read (see [`CachedMesh::deps`]).
    current_deps: Vec<Vec<(PathBuf, Option<u64>)>>,
    /// The key of the accel the current build made or reused (stored with it on give-back).
    last_accel_key: Option<AccelKey>,
    /// The environment map kept between builds (at most one image per scene).
    env_map: Option<(EnvKey, CachedEnvMap)>,
    /// The key and file hash of the environment map of the scene built last.
    current_env: Option<(EnvKey, Option<u64>)>,
    /// Decoded image textures and the content hash of their file.
    textures: HashMap<TextureKey, (Option<u64>, Arc<ImageData>)>,
    /// The textures (and file hashes) of the scene built last.
    current_textures: Vec<(PathBuf, Option<u64>)>,
    report: CacheReport,
}

impl BuildCache {
    /// An empty cache.
    pub fn new() -> BuildCache {
        BuildCache::default()
    }

    /// Drops every mesh whose file's current content hash (from `hash_of`; `None`: missing or
    /// unknown) differs from the one it was loaded from.
    pub fn retain_current(&mut self, hash_of: impl Fn(&Path) -> Option<u64>) {
        self.meshes.retain(|key, m| match key {
            MeshKey::Obj(path, _) => {
                m.file_hash.is_some()
                    && hash_of(path) == m.file_hash
                    && m.deps.iter().all(|(p, h)| hash_of(p) == *h)
            }
            MeshKey::Data(_) => true,
        });
        if let Some(((path, _, _), cached)) = &self.env_map {
            if cached.file_hash.is_none() || hash_of(path) != cached.file_hash {
                self.env_map = None;
            }
        }
        self.textures
            .retain(|(path, _, _), (h, _)| h.is_some() && hash_of(path) == *h);
    }

    /// The files (and their content hashes) of the meshes of the scene built last: the watch
    /// set must include them even when they were not read again.
    pub fn files_in_use(&self) -> Vec<(PathBuf, u64)> {
        self.current
            .iter()
            .filter_map(|(k, h)| match (k, h) {
                (MeshKey::Obj(p, _), Some(h)) => Some((p.clone(), *h)),
                _ => None,
            })
            .chain(
                self.current_deps
                    .iter()
                    .flatten()
                    .filter_map(|(p, h)| Some((p.clone(), (*h)?))),
            )
            .chain(
                self.current_env
                    .iter()
                    .filter_map(|((p, _, _), h)| Some((p.clone(), (*h)?))),
            )
            .chain(
                self.current_textures
                    .iter()
                    .filter_map(|(p, h)| Some((p.clone(), (*h)?))),
            )
            .collect()
    }

    /// What the last build loaded and built.
    pub fn report(&self) -> &CacheReport {
        &self.report
    }

    /// Takes a scene's meshes and accel back for the next build.
    pub fn recycle(&mut self, scene: Scene) {
        let env_map = scene.lights.environment.and_then(|e| e.map);
        if let (Some(map), Some((key, file_hash))) = (env_map, self.current_env.clone()) {
            self.env_map = Some((key, CachedEnvMap { map, file_hash }));
        }
        self.give_back(scene.meshes, scene.accel);
    }

    pub(super) fn begin(&mut self) {
        self.current.clear();
        self.current_deps.clear();
        self.current_env = None;
        self.current_textures.clear();
        self.last_accel_key = None;
        self.report = CacheReport::default();
    }

    /// Returns meshes (in the order they were loaded in the current build) and an accel.
    pub(super) fn give_back(&mut self, meshes: Vec<TriMesh>, accel: Option<Accel>) {
        let deps = std::mem::take(&mut self.current_deps);
        for (((key, file_hash), deps), mesh) in self.current.iter().cloned().zip(deps).zip(meshes) {
            self.meshes.insert(
                key,
                CachedMesh {
                    mesh,
                    file_hash,
                    deps,
                },
            );
        }
        if let (Some(accel), Some(key)) = (accel, self.last_accel_key.take()) {
            self.accel = Some((key, accel));
        }
    }

    /// [`load_mesh`] through the cache. The caller pushes the mesh (in order) into the scene.
    pub(super) fn load_mesh(
        &mut self,
        decl: &ir::Mesh,
        loader: &dyn Loader,
    ) -> Result<(TriMesh, Vec<BuildError>), BuildError> {
        let key = MeshKey::of(&decl.source, decl.obj_options());
        if let Some(hit) = self.meshes.remove(&key) {
            self.report.meshes_reused += 1;
            self.current.push((key, hit.file_hash));
            self.current_deps.push(hit.deps);
            return Ok((hit.mesh, Vec::new()));
        }
        let hashing = HashingLoader {
            inner: loader,
            last: Mutex::new(Vec::new()),
        };
        let loaded = load_mesh(decl, &hashing)?;
        self.report.meshes_loaded += 1;
        let (file_hash, deps) = hashing.first_and_rest();
        self.current.push((key, file_hash));
        self.current_deps.push(deps);
        Ok(loaded)
    }

    /// [`load_env_map`] through the cache: a map with the same file content, intensity and
    /// rotation as the one recycled last is reused (with its sampling table); its warnings were
    /// reported when it was loaded.
    pub(super) fn load_env_map(
        &mut self,
        file: &AssetPath,
        intensity: f32,
        rotation_y_rad: f32,
        loader: &dyn Loader,
    ) -> (Option<EnvMap>, Vec<BuildError>) {
        let key: EnvKey = (
            file.path.clone(),
            intensity.to_bits(),
            rotation_y_rad.to_bits(),
        );
        if let Some((cached_key, cached)) = self.env_map.take() {
            if cached_key == key {
                self.current_env = Some((key, cached.file_hash));
                return (Some(cached.map), Vec::new());
            }
        }
        let hashing = HashingLoader {
            inner: loader,
            last: Mutex::new(Vec::new()),
        };
        let loaded = load_env_map(file, intensity, rotation_y_rad, &hashing);
        self.report.environment_loaded = true;
        let file_hash = hashing.first_and_rest().0;
        self.current_env = Some((key, file_hash));
        loaded
    }

    /// [`load_image_texture`] through the cache: the same file content with the same encoding
    /// (and pyramid) as in an earlier build is not read again.
    pub(super) fn load_texture(
        &mut self,
        file: &AssetPath,
        encoding: TextureEncoding,
        mipmaps: bool,
        loader: &dyn Loader,
    ) -> Result<Arc<ImageData>, BuildError> {
        let key: TextureKey = (
            file.path.clone(),
            encoding == TextureEncoding::Srgb,
            mipmaps,
        );
        if let Some((hash, data)) = self.textures.get(&key) {
            self.report.textures_reused += 1;
            self.current_textures.push((key.0, *hash));
            return Ok(data.clone());
        }
        let hashing = HashingLoader {
            inner: loader,
            last: Mutex::new(Vec::new()),
        };
        let loaded = load_image_texture(file, encoding, mipmaps, &hashing);
        let file_hash = hashing.first_and_rest().0;
        self.report.textures_loaded += 1;
        self.current_textures.push((key.0.clone(), file_hash));
        let data = loaded?;
        self.textures.insert(key, (file_hash, data.clone()));
        Ok(data)
    }

    /// The acceleration structure for `instances` over `meshes` (loaded by this build), reused
    /// when the same meshes sit at the same places.
    pub(super) fn accel(
        &mut self,
        meshes: &[TriMesh],
        instances: &[SceneInstance],
        kind: AccelKind,
    ) -> Accel {
        let key: AccelKey = (
            kind,
            instances
                .iter()
                .map(|i| {
                    let (k, h) = self
                        .current
                        .get(i.mesh as usize)
                        .cloned()
                        .unwrap_or((MeshKey::Data(u64::MAX), None));
                    (k, h, i.world_from_object.to_cols_array().map(f32::to_bits))
                })
                .collect(),
        );
        self.last_accel_key = Some(key.clone());
        if let Some((old, accel)) = self.accel.take() {
            if old == key {
                return accel;
            }
        }
        self.report.accel_built = true;
        let refs: Vec<MeshRef<'_>> = meshes.iter().map(TriMesh::as_mesh_ref).collect();
        let accel_instances: Vec<Instance> = instances
            .iter()
            .map(|i| Instance::new(i.mesh, i.world_from_object))
            .collect();
        let (accel, trace) =
            Accel::build_reusing(&refs, &accel_instances, kind, self.top_trace.as_ref());
        self.top_trace = trace;
        accel
    }
}

/// Remembers the content hash of the first file read: the mesh's OBJ or the map (an OBJ's
/// material libraries are read after it and do not change its geometry).
struct HashingLoader<'a> {
    inner: &'a dyn Loader,
    /// Every read, in order, with its content hash (`None`: the read failed).
    last: Mutex<Vec<(PathBuf, Option<u64>)>>,
}

impl HashingLoader<'_> {
    /// The hash of the first file read (the asset itself), and every other file read.
    fn first_and_rest(&self) -> (Option<u64>, Vec<(PathBuf, Option<u64>)>) {
        let mut reads = self.last.lock().map(|r| r.clone()).unwrap_or_default();
        if reads.is_empty() {
            return (None, reads);
        }
        let first = reads.remove(0);
        (first.1, reads)
    }
}

impl Loader for HashingLoader<'_> {
    fn read(&self, path: &Path) -> std::io::Result<Arc<[u8]>> {
        let result = self.inner.read(path);
        if let Ok(mut reads) = self.last.lock() {
            let hash = result.as_ref().ok().map(|b| content_hash(b));
            reads.push((path.to_path_buf(), hash));
        }
        result
    }

    fn recorded(&self) -> Vec<PathBuf> {
        self.inner.recorded()
    }
}
