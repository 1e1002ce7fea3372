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
use crate::diag::{
    json_diagnostics, maps_sort_keys, render_plain_all, write_json_diagnostics, Diagnostic,
};
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

/// One event as sent: its name (its `"event"`) and its JSON text, one line.
struct EventLine {
    name: &'static str,
    json: String,
}

impl EventLine {
    /// The event `value` printed.
    fn of(value: Value) -> EventLine {
        let name = match value.get("event").and_then(Value::as_str) {
            Some("checked") => "checked",
            Some("compiled") => "compiled",
            Some("pass") => "pass",
            Some("error") => "error",
            Some("watching") => "watching",
            Some("serving") => "serving",
            Some("stopped") => "stopped",
            _ => "",
        };
        EventLine {
            name,
            json: value.to_string(),
        }
    }
}

/// The `error` event of `diags`: `{"diagnostics":[…],"event":"error","text":"…"}`, the same
/// bytes as that value printed (tested; keys sorted, as serde_json's map prints them), written straight from the diagnostics (the value of
/// 1,002 diagnostics cost 6.9 ms to make and 6.8 ms to print at load 9; docs/watch.md).
fn error_event(diags: &[Diagnostic], sources: &SourceMap) -> EventLine {
    let text = render_plain_all(diags, sources, 100);
    let mut line = Vec::with_capacity(2 * text.len() + 64);
    // The keys in the order the value prints them.
    let sorted = maps_sort_keys();
    line.extend_from_slice(match sorted {
        true => br#"{"diagnostics":"#,
        false => br#"{"event":"error","diagnostics":"#,
    });
    write_json_diagnostics(&mut line, diags, sources);
    if sorted {
        line.extend_from_slice(br#","event":"error""#);
    }
    line.extend_from_slice(br#","text":"#);
    // A string always serialises; its escaping is serde_json's, as the value's printing.
    if serde_json::to_writer(&mut line, &text).is_err() {
        line.extend_from_slice(br#""""#);
    }
    line.push(b'}');
    EventLine {
        name: "error",
        // Only serde_json's UTF-8 output and ASCII went in.
        json: String::from_utf8(line).unwrap_or_default(),
    }
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
        self.emit_line(|| EventLine::of(event()), human);
    }

    /// [`Status::emit`] of an event made as its printed line.
    fn emit_line(&self, event: impl FnOnce() -> EventLine, human: impl FnOnce()) {
        let _guard = self.lock.lock();
        let json = self.format == EventsFormat::Json;
        let event = (json || self.preview.is_some()).then(event);
        // The page first, then stdout (a reader of the line may ask the page next).
        if let (Some(p), Some(event)) = (&self.preview, &event) {
            p.event_line(event.name, event.json.clone());
        }
        match (self.format, event) {
            (EventsFormat::Json, Some(event)) => {
                let mut out = std::io::stdout().lock();
                // A closed stdout (the reader went away) is no reason to stop watching.
                let _ = out.write_all(event.json.as_bytes());
                let _ = out.write_all(b"\n");
                let _ = out.flush();
            }
            (EventsFormat::Human, _) => human(),
            (EventsFormat::Json, None) => {}
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
        self.emit_line(
            || error_event(diags, sources),
            || {
                print_diagnostic_list(diags, sources, DiagnosticFormat::Human, JsonTo::Stderr);
                eprintln!("keeping the last good image; waiting for the next edit");
            },
        );
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diag::Code;
    use crate::source::Span;

    #[test]
    fn the_error_event_line_is_the_printed_value() {
        let mut sources = SourceMap::new();
        let text = "scnc 1\nobject ball { material \"r\u{e9}d\\\" }\n\tlet x = 1\n";
        let file = sources.add("a b.scn", "a b.scn", std::sync::Arc::<str>::from(text));
        let diags = [
            Diagnostic::warning(Code::CheckUnused, "material `red` is never used"),
            Diagnostic::error(Code::CheckUnknownMaterial, "unknown material `r\u{e9}d`")
                .at(Span::new(file, 23, 30), "not \"declared\"")
                .also(Span::new(file, 33, 38), "here\ttoo")
                .help("did you mean `red`?"),
        ];
        let value = json!({
            "event": "error",
            "diagnostics": json_diagnostics(&diags, &sources),
            "text": render_plain_all(&diags, &sources, 100),
        });
        let line = error_event(&diags, &sources);
        assert_eq!(line.json, value.to_string());
        assert_eq!(line.name, "error");
        let none = error_event(&[], &sources);
        assert_eq!(
            none.json,
            json!({"event": "error", "diagnostics": [], "text": render_plain_all(&[], &sources, 100)})
                .to_string()
        );
    }
}
