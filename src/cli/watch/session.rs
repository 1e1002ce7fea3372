//! `scnc watch`: one compile of the loop. Reads the scene and its includes and assets through a
//! recording loader (every path asked for, with the content hash of the bytes it got, or
//! `None` if missing: that is the next watch set), builds through the [`BuildCache`], and says
//! what was rebuilt.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::status::CompileFigures;
use super::watcher::{absolute, FileSet};
use crate::assets::Loader;
use crate::bvh::AccelKind;
use crate::cli::targets::{camera_index, output_targets};
use crate::compile::compile_file;
use crate::diag::Diagnostic;
use crate::film::WriteSettings;
use crate::ir::SceneDesc;
use crate::scene::cache::content_hash;
use crate::scene::{build_cached, BuildCache, BuildOptions, Scene};
use crate::source::{SourceMap, Span};

/// Reads from disk and records path → content hash (`None`: could not be read).
#[derive(Debug, Default)]
pub struct RecordingLoader {
    read: Mutex<HashMap<PathBuf, Option<u64>>>,
}

impl Loader for RecordingLoader {
    fn read(&self, path: &Path) -> std::io::Result<Arc<[u8]>> {
        let result = std::fs::read(path).map(Arc::<[u8]>::from);
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
    pub scene: Scene,
    pub outputs: Vec<(PathBuf, Option<Span>)>,
    pub write: WriteSettings,
}

/// The result of one compile.
pub struct Outcome {
    pub sources: SourceMap,
    /// `Err`: every error and warning found (nothing to render).
    pub result: Result<Ready, Vec<Diagnostic>>,
    pub figures: CompileFigures,
    pub warnings: Vec<Diagnostic>,
    /// What this compile read: the next watch set (output files removed).
    pub files: FileSet,
}

pub struct Session {
    pub file: PathBuf,
    pub output: Option<PathBuf>,
    pub camera: Option<String>,
    pub cache: BuildCache,
}

impl Session {
    pub fn compile(&mut self) -> Outcome {
        let loader = RecordingLoader::default();
        let t = Instant::now();
        let compiled = compile_file(&self.file, &loader);
        let mut figures = CompileFigures {
            compile_ms: t.elapsed().as_secs_f64() * 1e3,
            ..CompileFigures::default()
        };
        let mut warnings: Vec<Diagnostic> = compiled.diagnostics.clone();
        let result = match compiled.scene {
            None => Err(compiled.diagnostics),
            Some(desc) => {
                let t = Instant::now();
                let r = self.build(&desc, &compiled.sources, &loader, &mut warnings);
                figures.build_ms = t.elapsed().as_secs_f64() * 1e3;
                let report = self.cache.report();
                figures.rebuilt = report.rebuilt();
                figures.meshes_loaded = report.meshes_loaded;
                figures.meshes_reused = report.meshes_reused;
                r
            }
        };
        figures.warnings = warnings.len();
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
        if let Ok(ready) = &result {
            for (out, _) in &ready.outputs {
                files.remove(&absolute(out));
            }
        }
        Outcome {
            sources: compiled.sources,
            result,
            figures,
            warnings,
            files,
        }
    }

    fn build(
        &mut self,
        desc: &SceneDesc,
        sources: &SourceMap,
        loader: &RecordingLoader,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Ready, Vec<Diagnostic>> {
        let camera = match self.camera.as_deref() {
            None => None,
            Some(name) => Some(camera_index(desc, name).map_err(|d| vec![*d])?),
        };
        let options = BuildOptions {
            accel: AccelKind::Bvh,
            camera,
        };
        let mut scene = build_cached(desc, sources, loader, &options, &mut self.cache)?;
        warnings.append(&mut scene.warnings);
        Ok(Ready {
            outputs: output_targets(self.output.as_deref(), &self.file, desc),
            write: WriteSettings::from_render(&scene.settings),
            scene,
        })
    }
}
