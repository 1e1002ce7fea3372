//! Stage 2, check: declaration tables, reference resolution with did-you-mean, and the final
//! pass that reports unused declarations, drops them and compacts the IR's indices.

use std::hash::BuildHasher;

use foldhash::fast::FixedState;

use hashbrown::HashTable;

use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::Expr;

/// The separate name spaces of declarations (a mesh and a material may share a name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Namespace {
    Texture = 0,
    Material = 1,
    Mesh = 2,
    Light = 3,
    Camera = 4,
    Group = 5,
}

impl Namespace {
    pub fn what(self) -> &'static str {
        match self {
            Namespace::Texture => "texture",
            Namespace::Material => "material",
            Namespace::Mesh => "mesh",
            Namespace::Light => "light",
            Namespace::Camera => "camera",
            Namespace::Group => "group",
        }
    }

    pub fn plural(self) -> &'static str {
        match self {
            Namespace::Texture => "textures",
            Namespace::Material => "materials",
            Namespace::Mesh => "meshes",
            Namespace::Light => "lights",
            Namespace::Camera => "cameras",
            Namespace::Group => "groups",
        }
    }

    /// Nothing refers to a light or a group by name yet, so an unknown one cannot be reported;
    /// when something does, that namespace gets its own code.
    pub(in crate::check) fn unknown_code(self) -> Code {
        match self {
            Namespace::Texture => Code::CheckUnknownTexture,
            Namespace::Material => Code::CheckUnknownMaterial,
            Namespace::Mesh => Code::CheckUnknownMesh,
            Namespace::Camera => Code::CheckUnknownCamera,
            Namespace::Light | Namespace::Group => Code::CheckUnknownName,
        }
    }
}

/// Names declared in one namespace, in declaration order. Each name is held once, in one
/// string, and the hash index holds only declaration numbers (a scene of 50,000 declarations
/// had tables as large as its IR's objects: docs/frontend-bench.md).
#[derive(Debug, Default)]
pub struct Table {
    /// Declaration indices, hashed by their names (4 bytes a bucket: the names lie in `names`).
    index: HashTable<u32>,
    /// Every name, one after the other, in declaration order.
    names: String,
    /// Where each name ends in `names`.
    ends: Vec<u32>,
    pub spans: Vec<Span>,
    /// foldhash with a fixed seed: a table is made for every statement the pre-check offers
    /// (std's `RandomState` read its thread-local keys each time, and SipHash was ≈ 4 % of a
    /// statement-dense compile; docs/frontend-bench.md, nineteenth session). Names only index
    /// the table, they never order anything the user sees.
    hasher: FixedState,
    /// The last unknown name looked up, what its kind is called and its help: the 1,000
    /// objects of a renamed material ask for the same did-you-mean over the same names (10 ms
    /// of edit distances per re-check; 2026-11-26, seventh session). Only [`Table::declare`]
    /// changes the names (the others make the table again), and it forgets this.
    /// Boxed: a table is made and dropped for every statement the pre-check offers, and this
    /// is rarely set.
    last_help: Option<Box<(String, &'static str, String)>>,
}

impl Table {
    /// Adds a name; returns the first declaration's span if it was already declared (the
    /// duplicate is not added).
    pub fn declare(&mut self, name: &str, span: Span) -> Option<Span> {
        if let Some(i) = self.get(name) {
            return Some(self.spans[i]);
        }
        self.last_help = None;
        let Table {
            index,
            names,
            ends,
            hasher,
            ..
        } = self;
        let hash = hasher.hash_one(name.as_bytes());
        index.insert_unique(hash, ends.len() as u32, |&i| {
            hasher.hash_one(name_at(names, ends, i as usize).as_bytes())
        });
        names.push_str(name);
        ends.push(names.len() as u32);
        self.spans.push(span);
        None
    }

    /// The declaration number of `name`, if it is declared.
    pub fn get(&self, name: &str) -> Option<usize> {
        self.get_bytes(name.as_bytes())
    }

    /// [`Table::get`] by the name's bytes (names are hashed as bytes: a `syntax::Name` is
    /// looked up without the UTF-8 check of its `as_str`).
    pub fn get_bytes(&self, name: &[u8]) -> Option<usize> {
        let hash = self.hasher.hash_one(name);
        self.index
            .find(hash, |&i| {
                name_at(&self.names, &self.ends, i as usize).as_bytes() == name
            })
            .map(|&i| i as usize)
    }

    /// Room for `n` more names (declared one by one, the index would otherwise be rebuilt at
    /// each doubling, the old beside the new).
    pub fn reserve(&mut self, n: usize) {
        let Table {
            index,
            names,
            ends,
            hasher,
            ..
        } = self;
        index.reserve(n, |&i| {
            hasher.hash_one(name_at(names, ends, i as usize).as_bytes())
        });
        self.ends.reserve_exact(n);
        self.spans.reserve_exact(n);
    }

    /// Declares `name` as the `at`-th (the later ones move up by one): the table made again.
    pub fn insert_at(&mut self, at: usize, name: &str, span: Span) {
        let old = std::mem::take(self);
        self.reserve(old.len() + 1);
        for i in 0..old.len() {
            if i == at {
                self.declare(name, span);
            }
            self.declare(old.name(i), old.spans[i]);
        }
        if at >= old.len() {
            self.declare(name, span);
        }
    }

    /// Takes out the `at`-th name (the later ones move down by one): the table made again.
    pub fn remove_at(&mut self, at: usize) {
        let old = std::mem::take(self);
        self.reserve(old.len());
        for i in (0..old.len()).filter(|&i| i != at) {
            self.declare(old.name(i), old.spans[i]);
        }
    }

    /// How many names are declared.
    pub fn len(&self) -> usize {
        self.spans.len()
    }

    /// Whether none is.
    pub fn is_empty(&self) -> bool {
        self.spans.is_empty()
    }

    /// [`suggest::help_for`] `name` among the names (`what` they are), from the last
    /// look-up when it was the same.
    fn help_for_unknown(&mut self, name: &str, what: &'static str) -> String {
        if let Some((last, last_what, help)) = self.last_help.as_deref() {
            if last == name && *last_what == what {
                return help.clone();
            }
        }
        let help = suggest::help_for(name, &self.names(), what);
        self.last_help = Some(Box::new((name.to_string(), what, help.clone())));
        help
    }

    /// Every name, in declaration order.
    pub fn names(&self) -> Vec<&str> {
        (0..self.ends.len()).map(|i| self.name(i)).collect()
    }

    /// The name declared `i`-th.
    pub fn name(&self, i: usize) -> &str {
        if i < self.ends.len() {
            name_at(&self.names, &self.ends, i)
        } else {
            ""
        }
    }
}

/// The error for a name declared again at `again` (`what` it is: "constant", "material", ...),
/// first declared at `first`: the full check's, and the incremental re-check's when it adds
/// such a declaration (`recheck/redeclared.rs`).
pub(in crate::check) fn duplicate_name(
    what: &str,
    name: &str,
    again: Span,
    first: Span,
) -> Diagnostic {
    Diagnostic::error(
        Code::CheckDuplicateName,
        format!("{what} `{name}` is declared twice"),
    )
    .at(again, "declared again here")
    .also(first, "first declared here")
    .help("rename one of them")
}

/// The `i`-th name of a table's `names`, which end at `ends`.
fn name_at<'a>(names: &'a str, ends: &[u32], i: usize) -> &'a str {
    let start = if i == 0 { 0 } else { ends[i - 1] as usize };
    &names[start..ends[i] as usize]
}

impl Checker<'_> {
    /// Resolves a reference written as a bare name.
    pub fn resolve(&mut self, ns: Namespace, e: &Expr) -> Option<usize> {
        if let crate::syntax::ExprKind::Name(name) = &e.kind {
            // The common case, a known name, by its bytes (no UTF-8 check).
            if let Some(i) = self.table(ns).get_bytes(name.as_bytes()) {
                return Some(i);
            }
        }
        let Some(name) = e.as_name() else {
            self.error(
                Diagnostic::error(
                    Code::CheckWrongType,
                    format!("expected the name of a {}", ns.what()),
                )
                .at(e.span, "not a name"),
            );
            return None;
        };
        self.resolve_name(ns, name, e.span)
    }

    /// [`Checker::resolve_name`] for a declared name as written (by its bytes first: no UTF-8
    /// check when it is known).
    pub fn resolve_ident(&mut self, ns: Namespace, name: &crate::syntax::Ident) -> Option<usize> {
        if let Some(i) = self.table(ns).get_bytes(name.name.as_bytes()) {
            return Some(i);
        }
        self.resolve_name(ns, &name.name, name.span)
    }

    /// Resolves `name` in `ns`, or reports it as unknown with a did-you-mean.
    pub fn resolve_name(&mut self, ns: Namespace, name: &str, span: Span) -> Option<usize> {
        let table = self.table(ns);
        if let Some(i) = table.get(name) {
            return Some(i);
        }
        let help = table.help_for_unknown(name, ns.plural());
        self.error(
            Diagnostic::error(ns.unknown_code(), format!("unknown {} `{name}`", ns.what()))
                .at(span, format!("no {} of this name", ns.what()))
                .help(help),
        );
        None
    }

    /// Whether `name` is declared in `ns` (no diagnostic).
    pub fn has(&mut self, ns: Namespace, name: &str) -> bool {
        self.table(ns).get(name).is_some()
    }

    /// Warns that the `i`-th name of `ns` (`name`) is never used.
    fn warn_unused(&mut self, ns: Namespace, i: usize, name: &str) {
        let span = self.table(ns).spans[i];
        self.error(
            Diagnostic::warning(
                Code::CheckUnused,
                format!("{} `{name}` is never used", ns.what()),
            )
            .at(span, "declared here, used nowhere")
            .help("it is left out of the scene; remove it or use it"),
        );
    }

    /// Drops unused declarations (with a warning each), remaps indices, builds the IR.
    pub(super) fn finish(&mut self, render: Option<ir::RenderSettings>) -> Option<ir::SceneDesc> {
        self.finish_from = self.diags.len();
        self.mark_override_materials_used();
        let (textures, texture_map) = self.keep_used_textures();
        let (materials, material_map) = self.keep_used_materials(&texture_map);
        self.texture_map = texture_map;
        let (meshes, mesh_map) = self.keep_used_meshes(&material_map);
        let mut objects = std::mem::take(&mut self.objects);
        for o in &mut objects {
            let (mesh, material) = (mesh_map[o.mesh as usize], material_map[o.material as usize]);
            if mesh.is_none() || material.is_none() {
                // A declaration that failed to lower (an error): 0 stands in for it.
                let names = (o.span, o.mesh, o.material);
                self.dropped.unresolved.push(names);
            }
            o.mesh = mesh.unwrap_or(0);
            o.material = material.unwrap_or(0);
        }
        let mut lights = std::mem::take(&mut self.lights);
        self.light_meshes = (lights.iter())
            .map(|l| match l {
                ir::Light::Area(a) => Some(a.mesh),
                _ => None,
            })
            .collect();
        for l in &mut lights {
            if let ir::Light::Area(a) = l {
                a.mesh = mesh_map[a.mesh as usize].unwrap_or(0);
            }
        }
        if self.cameras.is_empty() && self.table(Namespace::Camera).is_empty() {
            self.error(
                Diagnostic::error(Code::CheckNoCamera, "the scene has no camera").help(
                    "add one, e.g. `camera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }`",
                ),
            );
        }
        self.material_map = material_map;
        self.mesh_map = mesh_map;
        let render = render?;
        let active_camera = self.active_camera;
        Some(ir::SceneDesc {
            cameras: std::mem::take(&mut self.cameras),
            active_camera,
            meshes,
            textures,
            materials,
            objects,
            lights,
            render,
        })
    }

    /// A material is used if an object uses it, or a used OBJ mesh replaces one of its own.
    fn mark_override_materials_used(&mut self) {
        for (i, m) in self.meshes.iter().enumerate() {
            if !self.used_meshes.get(i).copied().unwrap_or(true) {
                continue;
            }
            for o in m.iter().flat_map(|m| &m.obj_options().materials) {
                if let Some(u) = self.used_materials.get_mut(o.material as usize) {
                    *u = true;
                }
            }
        }
    }

    /// Warns about unused materials, then keeps the textures used materials refer to: the
    /// kept textures and the old → new texture index map.
    fn keep_used_textures(&mut self) -> (Vec<ir::Texture>, Vec<Option<u32>>) {
        let mut used_textures = vec![false; self.textures.len()];
        for (i, textures) in &self.material_textures {
            if self.used_materials[*i as usize] {
                for &t in textures {
                    used_textures[t] = true;
                }
            }
        }
        let mut names = Names::default();
        for i in 0..self.materials.len() {
            if !self.used_materials[i] {
                let name = names.get(self, Namespace::Material, i);
                self.warn_unused(Namespace::Material, i, &name);
            }
        }
        let mut texture_map = vec![None; self.textures.len()];
        let mut textures = Vec::new();
        let mut names = Names::default();
        for (i, used) in used_textures.iter().enumerate() {
            if !used {
                let name = names.get(self, Namespace::Texture, i);
                self.warn_unused(Namespace::Texture, i, &name);
            } else if let Some(t) = self.textures[i].take() {
                texture_map[i] = Some(textures.len() as u32);
                textures.push(t);
            }
        }
        let unused = self.textures.iter_mut().enumerate();
        self.dropped.textures = unused
            .filter_map(|(i, t)| Some((i as u32, t.take()?)))
            .collect();
        (textures, texture_map)
    }

    /// The used materials with their texture indices remapped, and the material index map.
    /// The list is compacted where it lies (no second list of every material at once).
    fn keep_used_materials(
        &mut self,
        texture_map: &[Option<u32>],
    ) -> (Vec<ir::Material>, Vec<Option<u32>>) {
        let all = std::mem::take(&mut self.materials);
        let mut material_map = vec![None; all.len()];
        let mut kept = 0;
        let used = &self.used_materials;
        let mut dropped = Vec::new();
        let materials = (all.into_iter().enumerate())
            .filter_map(|(i, m)| {
                let mut m = m?;
                if !used[i] {
                    dropped.push((i as u32, m));
                    return None;
                }
                remap_textures(&mut m, texture_map);
                material_map[i] = Some(kept);
                kept += 1;
                Some(m)
            })
            .collect();
        self.dropped.materials = dropped;
        (materials, material_map)
    }

    /// The used meshes (with a warning for each unused one the user declared) with their
    /// material overrides remapped, and the mesh index map. Compacted where it lies.
    fn keep_used_meshes(
        &mut self,
        material_map: &[Option<u32>],
    ) -> (Vec<ir::Mesh>, Vec<Option<u32>>) {
        let user_meshes = self.table(Namespace::Mesh).len();
        let all = std::mem::take(&mut self.meshes);
        let mut mesh_map = vec![None; all.len()];
        let mut kept = 0;
        let mut names = Names::default();
        let mut dropped = Vec::new();
        let mut overrides = Vec::new();
        let meshes = (all.into_iter().enumerate())
            .filter_map(|(i, m)| {
                let used = self.used_meshes.get(i).copied().unwrap_or(true);
                if !used && i < user_meshes {
                    let name = names.get(self, Namespace::Mesh, i);
                    self.warn_unused(Namespace::Mesh, i, &name);
                    dropped.extend(m.map(|m| (i as u32, m)));
                    return None;
                }
                let mut m = m?;
                let listed: Vec<u32> = m
                    .obj_options()
                    .materials
                    .iter()
                    .map(|o| o.material)
                    .collect();
                if !listed.is_empty() {
                    overrides.push((i as u32, listed));
                }
                for o in m.obj.iter_mut().flat_map(|o| &mut o.materials) {
                    o.material = material_map[o.material as usize].unwrap_or(0);
                }
                mesh_map[i] = Some(kept);
                kept += 1;
                Some(m)
            })
            .collect();
        self.dropped.meshes = dropped;
        self.mesh_overrides = overrides;
        (meshes, mesh_map)
    }
}

/// A namespace's names in declaration order, rebuilt at the first one asked for (only
/// warnings need them).
#[derive(Default)]
struct Names(Option<Vec<String>>);

impl Names {
    /// The `i`-th name of `ns`.
    fn get(&mut self, cx: &mut Checker, ns: Namespace, i: usize) -> String {
        let names = self.0.get_or_insert_with(|| {
            let names = cx.table(ns).names();
            names.into_iter().map(str::to_string).collect()
        });
        names.get(i).cloned().unwrap_or_default()
    }
}

/// A material's texture inputs from table indices to the IR's (`map`: table → IR index).
pub(super) fn remap_textures(m: &mut ir::Material, map: &[Option<u32>]) {
    let at = |t: u32| map.get(t as usize).copied().flatten().unwrap_or(0);
    texture_inputs(m, |t| *t = at(*t));
}

/// Each texture input of a material, in the order `material.rs` resolves them (diffuse,
/// specular, shininess, normal map: the order of its list of textures).
pub(super) fn texture_inputs(m: &mut ir::Material, mut f: impl FnMut(&mut u32)) {
    for c in [&mut m.diffuse, &mut m.specular] {
        if let ir::ColorInput::Texture(t) = c {
            f(t);
        }
    }
    if let ir::ScalarInput::Texture(t) = &mut m.shininess {
        f(t);
    }
    if let Some(n) = &mut m.normal_map {
        f(&mut n.texture);
    }
}
