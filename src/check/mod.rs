//! Stage 2, check: AST → `ir::SceneDesc` (names resolved, expressions folded, units normalised,
//! values validated). Reports every error and warning found, then returns the IR only if there
//! was no error.
//!
//! Order: `let` constants are folded in statement order (a constant may use earlier ones);
//! declarations are registered first (so a block may name a declaration written after it), then
//! lowered kind by kind (one file each: textures, materials, meshes, lights, objects and groups,
//! cameras, render settings). Finally declarations nothing uses are reported as warnings and
//! dropped, and the surviving indices are compacted (`names.rs`).

pub mod array;
mod camera;
mod constants;
mod define;
mod early;
mod eval;
mod icosphere;
mod inline_mesh;
mod light;
mod material;
mod mesh;
mod names;
mod object;
mod props;
mod recheck;
pub mod reference;
mod reference_table;
mod render;
mod texture;
pub mod transform;
mod typed;
pub mod value;
pub mod vocabulary;

pub use early::{Placed, PreCheck};
pub use eval::FUNCTIONS;
pub use recheck::{check_tracked, inert, CheckMemo, Dependents};

use std::collections::HashMap;

use crate::diag::{Code, Diagnostic, Staged};
use crate::ir;
use crate::source::{SourceMap, Span};
use crate::syntax::{Block, Decl, DeclKind, Ident, Stmt};
pub use constants::Constants;
use names::{Namespace, Table};

/// The checker's state for one compile.
pub struct Checker<'s> {
    /// Every source file, for snippets (arrays are read from the text).
    pub sources: &'s SourceMap,
    /// Every error and warning found so far.
    pub diags: Vec<Diagnostic>,
    /// The `let` constants evaluated so far, with where each was declared.
    pub lets: Constants,
    /// The value of the predefined constant `frame` (`--frame F`; 0 when not animating).
    pub frame: f64,
    /// `--define NAME=VALUE` overrides: name → (value expression, used by a `let`).
    pub defines: HashMap<String, (crate::syntax::Expr, bool)>,
    /// Constants whose value had an error: uses stay silent instead of cascading.
    pub poisoned: std::collections::HashSet<String>,
    tables: [Table; 6],
    /// Lowered declarations, indexed like their table (None when they had errors).
    textures: Vec<Option<ir::Texture>>,
    materials: Vec<Option<ir::Material>>,
    meshes: Vec<Option<ir::Mesh>>,
    lights: Vec<ir::Light>,
    objects: Vec<ir::Object>,
    cameras: Vec<ir::Camera>,
    /// The textures each material that refers to any refers to: (material table index,
    /// texture table indices), ascending.
    material_textures: Vec<(u32, Vec<usize>)>,
    /// The material overrides of each mesh `finish` kept that has any: (mesh table index,
    /// the overrides' material table indices, in order), ascending; `finish` remaps the IR's
    /// to IR indices, and the incremental re-compaction maps them back from this list.
    mesh_overrides: Vec<(u32, Vec<u32>)>,
    used_materials: Vec<bool>,
    used_meshes: Vec<bool>,
    /// How many objects name each material and mesh (table indices), for the incremental
    /// re-check: a change of one object keeps the IR's indices only if no count reaches or
    /// leaves zero.
    material_uses: Vec<u32>,
    mesh_uses: Vec<u32>,
    /// Table index → index in the IR (`None`: dropped), set by `finish`.
    material_map: Vec<Option<u32>>,
    texture_map: Vec<Option<u32>>,
    mesh_map: Vec<Option<u32>>,
    /// Index into `cameras` chosen by `render { camera NAME }`.
    active_camera: usize,
    /// The lowered declarations `finish` leaves out of the IR (unused), by table index: an
    /// incremental check's memo keeps them for an edit that makes one used.
    dropped: recheck::Dropped,
    /// How many diagnostics there were when `finish` began (those after are its own).
    finish_from: usize,
    /// Per light `finish` kept, the mesh table index of an area light (set by `finish`,
    /// which maps them to IR indices), for the incremental re-compaction to map again.
    light_meshes: Vec<Option<u32>>,
    /// Which of two spans the check reads first, across included files (set by the
    /// incremental re-check, which compares declarations' places; the full check reads in
    /// order and never asks).
    order: crate::source::ReadingOrder,
}

impl<'s> Checker<'s> {
    fn new(sources: &'s SourceMap) -> Checker<'s> {
        Checker {
            sources,
            diags: Vec::new(),
            lets: Constants::default(),
            frame: 0.0,
            defines: HashMap::new(),
            poisoned: Default::default(),
            tables: Default::default(),
            textures: Vec::new(),
            materials: Vec::new(),
            meshes: Vec::new(),
            lights: Vec::new(),
            objects: Vec::new(),
            cameras: Vec::new(),
            material_textures: Vec::new(),
            mesh_overrides: Vec::new(),
            used_materials: Vec::new(),
            used_meshes: Vec::new(),
            material_uses: Vec::new(),
            mesh_uses: Vec::new(),
            material_map: Vec::new(),
            texture_map: Vec::new(),
            mesh_map: Vec::new(),
            active_camera: 0,
            dropped: recheck::Dropped::default(),
            finish_from: 0,
            light_meshes: Vec::new(),
            order: Default::default(),
        }
    }

    /// Records a diagnostic (an error or a warning, despite the name).
    pub fn error(&mut self, d: Diagnostic) {
        self.diags.push(d);
    }

    fn table(&mut self, ns: Namespace) -> &mut Table {
        &mut self.tables[ns as usize]
    }

    /// Registers a declared name; reports a duplicate with the first declaration and returns
    /// false for it (a duplicate is not lowered, so tables and lowered vectors stay aligned).
    fn declare(&mut self, ns: Namespace, name: &str, span: Span) -> bool {
        let Some(first) = self.table(ns).declare(name, span) else {
            return true;
        };
        self.error(names::duplicate_name(ns.what(), name, span, first));
        false
    }

    fn let_stmt(&mut self, name: &crate::syntax::Ident, value: &crate::syntax::Expr) {
        if matches!(name.name.as_str(), "true" | "false" | "frame") {
            self.error(
                Diagnostic::error(
                    Code::CheckReservedName,
                    format!("`{}` is a reserved word", name.name),
                )
                .at(name.span, "cannot be a constant"),
            );
            return;
        }
        if let Some((_, first)) = self.lets.get(&name.name) {
            let first = *first;
            self.error(names::duplicate_name(
                "constant", &name.name, name.span, first,
            ));
            return;
        }
        match self.eval(value).and_then(|v| self.define_override(name, v)) {
            Some(v) => {
                self.lets.insert(&name.name, v, name.span);
            }
            None => {
                self.poisoned.insert(name.name.as_str().to_owned());
            }
        }
    }
}

/// Checks parsed statements (every file's, includes expanded in place, in order) and lowers
/// them into the IR. `sources` gives file paths for resolving relative asset paths.
pub fn check(statements: &[Stmt], sources: &SourceMap) -> Staged<ir::SceneDesc> {
    check_with(statements, sources, 0.0, Vec::new())
}

/// [`check`] with the predefined constant `frame` set to `frame` (`scnc render --frame F`)
/// and `let`s overridden by `defines` (`--define NAME=VALUE`: the name and the parsed value).
pub fn check_with(
    statements: &[Stmt],
    sources: &SourceMap,
    frame: f64,
    defines: Vec<(String, crate::syntax::Expr)>,
) -> Staged<ir::SceneDesc> {
    check_placed(statements, Placed::default(), sources, frame, defines)
}

/// [`check_with`] of the statements `statements` and `placed` together: `placed` holds the
/// top-level `object`s a [`PreCheck`] took while parsing (their places among all statements),
/// `statements` every other statement in order.
pub fn check_placed(
    statements: &[Stmt],
    placed: Placed,
    sources: &SourceMap,
    frame: f64,
    defines: Vec<(String, crate::syntax::Expr)>,
) -> Staged<ir::SceneDesc> {
    let mut cx = Checker::new(sources);
    cx.frame = frame;
    cx.defines = defines.into_iter().map(|(n, e)| (n, (e, false))).collect();
    let scene = cx.run(statements, placed, None);
    let failed = cx.diags.iter().any(Diagnostic::is_error);
    Staged::new(scene.filter(|_| !failed), cx.diags)
}

/// Whether `s` is a scene setting: a `camera`, a `light` or a `render` block.
pub fn is_setting(s: &Stmt) -> bool {
    matches!(s, Stmt::Camera { .. } | Stmt::Render { .. })
        || matches!(s, Stmt::Decl(d) if d.kind == DeclKind::Light)
}

/// What checking one top-level statement produced (the incremental re-check's bookkeeping).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StmtRecord {
    /// Whether it is a top-level `object` (the only statement the re-check redoes alone).
    pub object: bool,
    /// Whether it is a scene setting: a `camera`, a `light` or the `render` block (the
    /// re-check lowers them all again together: `recheck/settings.rs`).
    pub setting: bool,
    /// Diagnostics its placement check emitted (0 for statements checked in other phases).
    pub diags: u32,
    /// IR objects it placed.
    pub objects: u32,
    /// For an `object`: the mesh and the material (table indices) it named, if they resolved.
    pub mesh: Option<u32>,
    /// See `mesh`.
    pub material: Option<u32>,
}

/// Where the placement phase began, for the incremental re-check: the diagnostics emitted
/// before it and which declarations something other than an object had used by then.
pub(crate) struct PlacementStart {
    pub diags: usize,
    pub used_meshes: Vec<bool>,
    pub used_materials: Vec<bool>,
}

impl Checker<'_> {
    /// Checks `statements`; the scene even when there were errors (`None` only when the render
    /// settings failed). With `track`, one record per statement and where placements began.
    fn run(
        &mut self,
        statements: &[Stmt],
        placed: Placed,
        mut track: Option<(&mut Vec<StmtRecord>, &mut Option<PlacementStart>)>,
    ) -> Option<ir::SceneDesc> {
        let cx = self;
        // `None`: the next declaration of its kind lowered while parsing (`lowered`).
        let mut decls: [Vec<Option<&Decl>>; 4] = Default::default();
        let mut renders = Vec::new();
        let mut cameras = Vec::new();
        let mut placements = Vec::new();
        let total = statements.len() + placed.len();
        let indices = early::kept_indices(&placed, total);
        let (mut lowered, placed) = placed.take_decls();
        cx.take_constants(&mut lowered);
        let declared = |kind| {
            let decl = |s: &&Stmt| matches!(s, Stmt::Decl(d) if d.kind == kind);
            statements.iter().filter(decl).count()
        };
        let materials = lowered.materials.len() + declared(DeclKind::Material);
        cx.table(Namespace::Material).reserve(materials);
        let meshes = lowered.meshes.len() + declared(DeclKind::Mesh);
        cx.table(Namespace::Mesh).reserve(meshes);
        let mut undeclared = early::Undeclared::default();
        let mut settings = Vec::new();
        for (i, stmt) in indices.into_iter().zip(statements) {
            if is_setting(stmt) {
                settings.push(i);
            }
            cx.declare_lowered(&lowered, &mut undeclared, i, &mut decls);
            match stmt {
                Stmt::Version { .. } | Stmt::Include { .. } => {}
                Stmt::Let { name, value, .. } => cx.let_stmt(name, value),
                Stmt::Camera { name, body, span } => {
                    if cx.declare(Namespace::Camera, &name.name, name.span) {
                        cameras.push((name, body, *span));
                    }
                }
                Stmt::Decl(d) => {
                    let ns = match d.kind {
                        DeclKind::Material => Namespace::Material,
                        DeclKind::Texture => Namespace::Texture,
                        DeclKind::Mesh => Namespace::Mesh,
                        DeclKind::Light => Namespace::Light,
                    };
                    if cx.declare(ns, &d.name.name, d.name.span) {
                        decls[ns as usize].push(Some(d));
                    }
                }
                Stmt::Object(_) | Stmt::Group(_) => placements.push((i, stmt)),
                Stmt::Render { body, span } => renders.push((body, *span)),
            }
        }
        cx.declare_lowered(&lowered, &mut undeclared, usize::MAX, &mut decls);
        for d in decls[Namespace::Texture as usize].iter().flatten() {
            let t = cx.texture(d);
            cx.textures.push(t);
        }
        let materials = &decls[Namespace::Material as usize];
        let mut textures = Vec::new();
        let lowered_materials = std::mem::take(&mut lowered.materials);
        cx.materials = early::merge_lowered(lowered_materials, materials, |i, d| {
            let (m, texs) = cx.material(d);
            if !texs.is_empty() {
                textures.push((i as u32, texs));
            }
            m
        });
        cx.material_textures = textures;
        let lowered_meshes = std::mem::take(&mut lowered.meshes);
        let meshes = &decls[Namespace::Mesh as usize];
        cx.meshes = early::merge_lowered(lowered_meshes, meshes, |_, d| cx.mesh(d));
        cx.used_materials = vec![false; cx.materials.len()];
        cx.used_meshes = vec![false; cx.meshes.len()];
        cx.material_uses = vec![0; cx.materials.len()];
        cx.mesh_uses = vec![0; cx.meshes.len()];
        for d in decls[Namespace::Light as usize].iter().flatten() {
            cx.light(d);
        }
        if let Some((records, start)) = &mut track {
            records.clear();
            records.resize(total, StmtRecord::default());
            for i in settings {
                if let Some(r) = records.get_mut(i) {
                    r.setting = true;
                }
            }
            **start = Some(PlacementStart {
                diags: cx.diags.len(),
                used_meshes: cx.used_meshes.clone(),
                used_materials: cx.used_materials.clone(),
            });
        }
        let records = track.as_mut().map(|(r, _)| &mut **r);
        cx.placements(placements, placed, records);
        cx.lower_cameras(cameras);
        let mut settings = cx.render_blocks(&renders);
        if track.is_none() {
            // Nothing reads them any more (an incremental check's memo keeps them): their
            // room goes to the IR's final lists.
            cx.lets = Constants::default();
            cx.tables[Namespace::Group as usize] = Table::default();
        } else if settings.is_none() && cx.diags.iter().any(Diagnostic::is_error) {
            // An incremental check's memo keeps the scene for the edit that mends the render
            // block (its result is filtered by the error; a failing value is reported, or names
            // a constant that failed, which was).
            settings = Some(render::default_settings());
        }
        cx.finish(settings)
    }
}

impl Checker<'_> {
    /// Lowers the cameras declared (the first of each name), in statement order.
    fn lower_cameras(&mut self, cameras: Vec<(&Ident, &Block, Span)>) {
        for (name, body, span) in cameras {
            if let Some(c) = self.camera(name, body, span) {
                self.cameras.push(c);
            }
        }
    }

    /// The `render` blocks, after the cameras: a second one is an error, then each `--define`
    /// no `let` used, then the first block's settings (`None` when they failed).
    fn render_blocks(&mut self, renders: &[(&Block, Span)]) -> Option<ir::RenderSettings> {
        if let [(_, first), (_, second), ..] = renders {
            self.error(
                Diagnostic::error(Code::CheckDuplicateRender, "more than one `render` block")
                    .at(*second, "second `render` block")
                    .also(*first, "first here")
                    .help("merge them into one"),
            );
        }
        self.unused_defines();
        self.render(renders.first().map(|(b, s)| (*b, *s)))
    }

    /// A string literal naming a file, resolved relative to the directory of the `.scn` file
    /// that contains it.
    pub fn asset_path(&mut self, e: &crate::syntax::Expr) -> Option<ir::AssetPath> {
        let written = self.string(e)?;
        if written.is_empty() {
            self.error(
                Diagnostic::error(Code::CheckEmptyPath, "empty file name")
                    .at(e.span, "empty string"),
            );
            return None;
        }
        let file = &self.sources.get(e.span.file).path;
        let dir = file.parent().unwrap_or_else(|| std::path::Path::new(""));
        Some(ir::AssetPath {
            path: dir.join(&written),
            written,
            span: e.span,
        })
    }
}
