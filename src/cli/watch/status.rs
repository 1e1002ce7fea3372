//! `scnc watch`: what the user sees in the terminal, and the machine-readable event stream.
//!
//! Every happening is one JSON event (`{"event":"checked",…}` when the front end is done,
//! `"compiled"` after the build, `"pass"`, `"error"`,
//! `"watching"`, `"serving"`, `"stopped"`). With `--events json` each is printed as one line on
//! stdout (tests and tools read them); otherwise a short human status goes to stderr (clearing
//! the terminal before each compile unless `--no-clear`), and diagnostics print as in
//! `scnc check`. Events also go to the preview server, if one runs.

use std::io::{IsTerminal, Write};
use std::sync::{Arc, Mutex};

use serde_json::{json, Value};

use super::server::Preview;
use crate::cli::report::{print_diagnostic_list, DiagnosticFormat, JsonTo};
use crate::diag::{json_diagnostics, render_plain_all, Diagnostic};
use crate::source::SourceMap;

/// `--events`: how happenings are reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, Default)]
pub enum EventsFormat {
    /// A short status on stderr.
    #[default]
    Human,
    /// One JSON object per line on stdout.
    Json,
}

/// Compile-and-build figures for the `compiled` event.
#[derive(Debug, Clone, Default)]
pub struct CompileFigures {
    /// Wall time of the compile.
    pub compile_ms: f64,
    /// Whether the compile reused the last one (parsed and checked only what changed).
    pub incremental: bool,
    /// Wall time of the build.
    pub build_ms: f64,
    /// What the build cache had to rebuild.
    pub rebuilt: Vec<&'static str>,
    /// Meshes read from their files.
    pub meshes_loaded: usize,
    /// Meshes the cache kept.
    pub meshes_reused: usize,
    /// Diagnostics reported.
    pub warnings: usize,
}

/// Reports the loop's events: a human status on stderr, or JSON lines on stdout (and to the
/// preview page).
pub struct Status {
    format: EventsFormat,
    clear: bool,
    preview: Option<Arc<Preview>>,
    /// Serialises output from the loop and the render thread.
    lock: Mutex<()>,
}

fn ms(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

impl Status {
    /// A reporter in `format`; clears the terminal before each compile unless `no_clear`.
    pub fn new(format: EventsFormat, no_clear: bool, preview: Option<Arc<Preview>>) -> Status {
        Status {
            format,
            clear: !no_clear && std::io::stderr().is_terminal(),
            preview,
            lock: Mutex::new(()),
        }
    }

    /// Sends the event (made only when the preview or `--events json` takes it: an error
    /// event of 1,000 diagnostics costs milliseconds) or runs `human`.
    fn emit(&self, event: impl FnOnce() -> Value, human: impl FnOnce()) {
        let _guard = self.lock.lock();
        let json = self.format == EventsFormat::Json;
        let event = (json || self.preview.is_some()).then(event);
        if let (Some(p), Some(event)) = (&self.preview, &event) {
            p.event(event);
        }
        match (self.format, event) {
            (EventsFormat::Json, Some(event)) => {
                let mut out = std::io::stdout().lock();
                // A closed stdout (the reader went away) is no reason to stop watching.
                let _ = writeln!(out, "{event}");
                let _ = out.flush();
            }
            (EventsFormat::Json, None) => {}
            (EventsFormat::Human, _) => human(),
        }
    }

    /// Before a compile: clears the terminal (human mode, on a terminal, without --no-clear).
    pub fn begin(&self, changed: &[std::path::PathBuf]) {
        if self.format == EventsFormat::Human {
            if self.clear {
                eprint!("\x1b[2J\x1b[H");
            }
            for p in changed {
                eprintln!("changed: {}", p.display());
            }
        }
    }

    /// The front end succeeded (the build follows): its time and its warnings. The human
    /// status prints nothing here: the `compiled` line follows with every warning.
    pub fn checked(&self, f: &CompileFigures, warnings: &[Diagnostic], sources: &SourceMap) {
        let event = || {
            json!({
                "event": "checked",
                "compile_ms": ms(f.compile_ms),
                "incremental": f.incremental,
                "warnings": warnings.len(),
                "diagnostics": json_diagnostics(warnings, sources),
            })
        };
        self.emit(event, || {});
    }

    /// A compile and build succeeded, with these warnings.
    pub fn compiled(&self, f: &CompileFigures, warnings: &[Diagnostic], sources: &SourceMap) {
        let event = || {
            json!({
                "event": "compiled",
                "ms": ms(f.compile_ms + f.build_ms),
                "compile_ms": ms(f.compile_ms),
                "incremental": f.incremental,
                "build_ms": ms(f.build_ms),
                "rebuilt": f.rebuilt,
                "meshes_loaded": f.meshes_loaded,
                "meshes_reused": f.meshes_reused,
                "warnings": f.warnings,
            })
        };
        self.emit(event, || {
            print_diagnostic_list(warnings, sources, DiagnosticFormat::Human, JsonTo::Stderr);
            let rebuilt = if f.rebuilt.is_empty() {
                "nothing (meshes and BVH reused)".to_string()
            } else {
                f.rebuilt.join(", ")
            };
            eprintln!(
                "compiled in {:.1} ms (build {:.1} ms); rebuilt: {rebuilt}",
                f.compile_ms + f.build_ms,
                f.build_ms
            );
        });
    }

    /// A compile or build failed: the last good image stays.
    pub fn error(&self, diags: &[Diagnostic], sources: &SourceMap) {
        let event = || {
            json!({
                "event": "error",
                "diagnostics": json_diagnostics(diags, sources),
                "text": render_plain_all(diags, sources, 100),
            })
        };
        self.emit(event, || {
            print_diagnostic_list(diags, sources, DiagnosticFormat::Human, JsonTo::Stderr);
            eprintln!("keeping the last good image; waiting for the next edit");
        });
    }

    /// A render pass finished and was written.
    pub fn pass(&self, index: usize, spp: u32, wall_ms: f64, size: (u32, u32), last: bool) {
        let image = self.preview.as_ref().map_or(0, |p| p.image_version());
        let event = json!({
            "event": "pass", "pass": index, "spp": spp, "ms": ms(wall_ms),
            "width": size.0, "height": size.1, "final": last, "image": image,
        });
        self.emit(
            || event,
            || {
                eprintln!(
                    "pass {index}: {spp} spp, {}x{} in {wall_ms:.1} ms{}",
                    size.0,
                    size.1,
                    if last { " (final)" } else { "" }
                );
            },
        );
    }

    /// An output could not be written.
    pub fn write_failed(&self, d: &Diagnostic, sources: &SourceMap) {
        self.error(std::slice::from_ref(d), sources);
    }

    /// Waiting for a change of any of `files`.
    pub fn watching(&self, files: usize) {
        self.emit(
            || json!({"event": "watching", "files": files}),
            || {
                eprintln!("watching {files} files (Ctrl-C to stop)");
            },
        );
    }

    /// The preview server listens at `url`.
    pub fn serving(&self, url: &str) {
        self.emit(
            || json!({"event": "serving", "url": url}),
            || {
                eprintln!("preview at {url}");
            },
        );
    }

    /// The loop ended.
    pub fn stopped(&self) {
        self.emit(|| json!({"event": "stopped"}), || eprintln!("stopped"));
    }
}
