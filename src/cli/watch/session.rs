//! `scnc watch`: one compile of the loop. Reads the scene and its includes and assets through a
//! recording loader (every path asked for, with the content hash of the bytes it got, or
//! `None` if missing: that is the next watch set), builds through the [`BuildCache`], and says
//! what was rebuilt. The front end is incremental: an edit of some `object`s, or of the values
//! of `let`s, materials, meshes or textures, re-parses and re-checks those alone (with what
//! names a changed constant; `compile::Incremental`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::settled;
use super::status::CompileFigures;
use super::watcher::{absolute, FileSet, Fresh};
use crate::assets::Loader;
use crate::bvh::AccelKind;
use crate::cli::targets::{camera_index, output_targets};
use crate::compile::{Incremental, Reuse};
use crate::diag::{Diagnostic, Staged};
use crate::film::WriteSettings;
use crate::ir::SceneDesc;
use crate::scene::cache::content_hash;
use crate::scene::{build_cached, BuildCache, BuildOptions, Scene};
use crate::source::{SourceMap, Span};

/// Reads from disk (again while a writer is seen writing: [`settled::read`]) and records path
/// → content hash (`None`: could not be read). A file the watcher has just read to confirm
/// its change is taken from those bytes, once, not read again.
#[derive(Debug, Default)]
pub struct RecordingLoader {
    read: Mutex<HashMap<PathBuf, Option<u64>>>,
    fresh: Mutex<Fresh>,
}

impl RecordingLoader {
    /// A loader that serves `fresh` (absolute paths) once each before reading from disk.
    pub fn with_fresh(fresh: Fresh) -> RecordingLoader {
        RecordingLoader {
            read: Mutex::default(),
            fresh: Mutex::new(fresh),
        }
    }

    fn take_fresh(&self, path: &Path) -> Option<(Arc<[u8]>, u64)> {
        let mut fresh = self.fresh.lock().ok()?;
        if fresh.is_empty() {
            return None;
        }
        fresh.remove(&absolute(path))
    }
}

impl Loader for RecordingLoader {
    fn read(&self, path: &Path) -> std::io::Result<Arc<[u8]>> {
        if let Some((bytes, hash)) = self.take_fresh(path) {
            if let Ok(mut read) = self.read.lock() {
                read.insert(path.to_path_buf(), Some(hash));
            }
            return Ok(bytes);
        }
        let result = settled::read(path);
        if let Ok(mut read) = self.read.lock() {
            read.insert(
                path.to_path_buf(),
                result.as_ref().ok().map(|b| content_hash(b)),
            );
        }
        result
    }

    fn recorded(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self
            .read
            .lock()
            .map(|r| r.keys().cloned().collect())
            .unwrap_or_default();
        v.sort();
        v
    }
}

/// A scene ready to render, and where its passes go.
pub struct Ready {
    /// The built scene.
    pub scene: Scene,
    /// Every output file, with the span of its `output "…"` literal when the scene named it.
    pub outputs: Vec<(PathBuf, Option<Span>)>,
    /// Exposure and tone mapping of the PNG outputs.
    pub write: WriteSettings,
}

/// The result of one compile.
pub struct Outcome {
    /// The scene file and its includes, as read by this compile.
    pub sources: SourceMap,
    /// The scene ready to render, with every error and warning of compile and build (no
    /// value: nothing to render).
    pub built: Staged<Ready>,
    /// Times and cache figures for the status line.
    pub figures: CompileFigures,
    /// What this compile read: the next watch set (output files removed).
    pub files: FileSet,
}

/// The watch loop's state between compiles: what to compile and the build cache.
pub struct Session {
    /// The scene file.
    pub file: PathBuf,
    /// `-o FILE`.
    pub output: Option<PathBuf>,
    /// `--camera NAME`.
    pub camera: Option<String>,
    /// What earlier builds made, for reuse.
    pub cache: BuildCache,
    /// The front end, with `--frame F` and `--define NAME=VALUE`: after an edit of the scene
    /// file it parses and checks only what changed when it can (`compile::Incremental`).
    pub front: Incremental,
}

impl Session {
    /// Compiles and builds the scene through one recording loader (serving `fresh`, the
    /// files the watcher just read, without reading them again). `checked` is called as
    /// soon as the front end has succeeded (before the build), with its figures and
    /// diagnostics, so that they reach the user without waiting for the build.
    pub fn compile(
        &mut self,
        fresh: Fresh,
        checked: &dyn Fn(&CompileFigures, &[Diagnostic], &SourceMap),
    ) -> Outcome {
        let loader = RecordingLoader::with_fresh(fresh);
        let mut sources = SourceMap::new();
        let t = Instant::now();
        let compiled = self.front.compile(&self.file, &loader, &mut sources);
        let mut figures = CompileFigures {
            compile_ms: t.elapsed().as_secs_f64() * 1e3,
            incremental: self.front.reuse != Reuse::Full,
            ..CompileFigures::default()
        };
        if compiled.value.is_some() {
            checked(&figures, &compiled.diagnostics, &sources);
        }
        let built = compiled.and_then(|desc| {
            let t = Instant::now();
            let built = self.build(&desc, &loader);
            figures.build_ms = t.elapsed().as_secs_f64() * 1e3;
            let report = self.cache.report();
            figures.rebuilt = report.rebuilt();
            figures.meshes_loaded = report.meshes_loaded;
            figures.meshes_reused = report.meshes_reused;
            built
        });
        figures.warnings = built.diagnostics.len();
        let files = self.watch_set(loader, built.value.as_ref());
        Outcome {
            sources,
            built,
            figures,
            files,
        }
    }

    /// Every file the compile and build read (and the cached files still in use), without
    /// scnc's own outputs.
    fn watch_set(&self, loader: RecordingLoader, ready: Option<&Ready>) -> FileSet {
        let mut files: FileSet = loader
            .read
            .into_inner()
            .unwrap_or_default()
            .into_iter()
            .map(|(p, h)| (absolute(&p), h))
            .collect();
        for (p, h) in self.cache.files_in_use() {
            files.entry(absolute(&p)).or_insert(Some(h));
        }
        // scnc's own output files are never inputs.
        if let Some(ready) = ready {
            for (out, _) in &ready.outputs {
                files.remove(&absolute(out));
            }
        }
        files
    }

    fn build(&mut self, desc: &SceneDesc, loader: &RecordingLoader) -> Staged<Ready> {
        let camera = match self.camera.as_deref() {
            None => None,
            Some(name) => match camera_index(desc, name) {
                Ok(i) => Some(i),
                Err(d) => return Staged::failed(vec![*d]),
            },
        };
        let options = BuildOptions {
            accel: AccelKind::Bvh,
            camera,
        };
        build_cached(desc, loader, &options, &mut self.cache).map(|scene| Ready {
            outputs: output_targets(self.output.as_deref(), &self.file, desc),
            write: WriteSettings::from_render(&scene.settings),
            scene,
        })
    }
}
