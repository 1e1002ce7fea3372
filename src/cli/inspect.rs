//! `scnc inspect FILE.obj [--json] [--strict] [--no-mtl]`: what scnc makes of a mesh file,
//! without a scene: triangle count, surface area, bounding box, vertex/normal/UV counts, each
//! material and what it maps to, and every warning (as diagnostics on stderr, with the OBJ or
//! MTL line). `--json` prints one document on stdout with the keys `triangles`, `area`,
//! `bounds` (`min`, `max`), `vertices`, `materials`, `warnings`. Exit 0 when the file loads
//! (warnings allowed, unless `--strict`), 1 with a diagnostic on stderr when it cannot.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use glam::Vec3;
use serde_json::{json, Value};

use super::report::{print_diagnostic_list, DiagnosticFormat, JsonTo};
use crate::assets::obj::phong::{default_phong, phong_of, renders_map, ObjPhong};
use crate::assets::obj::report::{error_diagnostic, mtl_display_name, warning_diagnostics};
use crate::assets::obj::{load_obj, LoadedObj};
use crate::assets::{FsLoader, Loader};
use crate::diag::{Diagnostic, Staged};
use crate::source::SourceMap;

/// `scnc inspect`'s arguments.
#[derive(Debug, Clone, Args)]
pub struct InspectArgs {
    /// The OBJ file.
    #[arg(value_name = "FILE")]
    pub file: PathBuf,
    /// Print one JSON document on stdout.
    #[arg(long)]
    pub json: bool,
    /// Treat every warning as an error (exit 1).
    #[arg(long)]
    pub strict: bool,
    /// Do not read the material libraries (`mtllib`).
    #[arg(long)]
    pub no_mtl: bool,
}

/// `scnc inspect`: load the OBJ, print its summary, then report its diagnostics once.
pub fn run(args: &InspectArgs) -> ExitCode {
    let shown = args.file.display().to_string();
    let mut loaded = load(args, &shown);
    if args.strict {
        super::report::promote_warnings(&mut loaded.diagnostics);
    }
    if let Some(obj) = &loaded.value {
        let summary = summarise(obj, &shown, &loaded.diagnostics);
        if args.json {
            println!(
                "{}",
                serde_json::to_string_pretty(&summary).unwrap_or_default()
            );
        } else {
            print!("{}", human(&summary));
        }
    }
    // The OBJ and MTL lines are labelled inside each diagnostic: no `.scn` sources.
    let sources = SourceMap::new();
    print_diagnostic_list(
        &loaded.diagnostics,
        &sources,
        DiagnosticFormat::Human,
        JsonTo::Stderr,
    );
    if loaded.value.is_none() || loaded.has_errors() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// Reads and parses the OBJ (and, unless `--no-mtl`, its material libraries): the model with
/// its warnings, or the one error that stopped it.
fn load(args: &InspectArgs, shown: &str) -> Staged<LoadedObj> {
    let loader = FsLoader::new();
    let bytes = match loader.read(&args.file) {
        Ok(b) => b,
        Err(e) => {
            return Staged::failed(vec![Diagnostic::error(
                "scnc::inspect::read_failed",
                format!("cannot read `{shown}`: {e}"),
            )])
        }
    };
    match load_obj(&args.file, bytes.clone(), !args.no_mtl, &loader) {
        Ok(loaded) => {
            let warnings = warning_diagnostics(&loaded, shown, None);
            Staged::new(Some(loaded), warnings)
        }
        Err(e) => Staged::failed(vec![error_diagnostic(&e, shown, &bytes, None)]),
    }
}

fn v3(v: Vec3) -> Value {
    json!([v.x, v.y, v.z])
}

fn mapping(p: &ObjPhong) -> Value {
    json!({
        "kind": if p.is_emitter() { "area_light" } else { "phong" },
        "diffuse": v3(p.diffuse),
        "specular": v3(p.specular),
        "shininess": p.shininess,
        "emission": v3(p.emission),
        "adjusted": p.adjusted,
        "maps": p.maps.iter().map(|(k, t)| json!({"map": k, "file": t.file, "rendered": renders_map(k)})).collect::<Vec<_>>(),
    })
}

/// The JSON document (the human output is printed from it too).
pub fn summarise(o: &LoadedObj, shown: &str, warnings: &[Diagnostic]) -> Value {
    let m = &o.model;
    let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
    let mut area = 0.0f64;
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        lo = lo.min(a).min(b).min(c);
        hi = hi.max(a).max(b).max(c);
        area += 0.5 * f64::from((b - a).cross(c - a).length());
    }
    if m.triangles.is_empty() {
        (lo, hi) = (Vec3::ZERO, Vec3::ZERO);
    }
    // One entry per material name, in first-use order, with its triangle count.
    let mut mats: Vec<(Option<String>, usize)> = Vec::new();
    for (i, run) in m.runs.iter().enumerate() {
        let end = m.runs.get(i + 1).map_or(m.triangles.len(), |r| r.start);
        let n = end.saturating_sub(run.start);
        match mats.iter_mut().find(|(name, _)| *name == run.name) {
            Some((_, count)) => *count += n,
            None => mats.push((run.name.clone(), n)),
        }
    }
    let materials: Vec<Value> = mats
        .iter()
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| {
            let found = name.as_deref().and_then(|n| o.find_material(n));
            let (phong, from) = match found {
                Some((l, i)) => {
                    let src = &o.mtls[l];
                    let mat = &src.library.materials[i];
                    (
                        phong_of(mat),
                        json!({"file": mtl_display_name(shown, &src.written), "line": mat.at.line}),
                    )
                }
                None => (default_phong(), Value::Null),
            };
            json!({"name": name, "triangles": n, "defined_in": from, "maps_to": mapping(&phong)})
        })
        .collect();
    let warnings: Vec<Value> = warnings
        .iter()
        .map(|d| {
            let at = d.external.first();
            json!({
                "severity": d.severity,
                "code": d.code,
                "message": d.message,
                "file": at.map(|e| e.file.clone()),
                "line": at.map(|e| e.line),
                "help": d.help,
            })
        })
        .collect();
    json!({
        "file": shown,
        "triangles": m.triangles.len(),
        "area": area,
        "bounds": {"min": v3(lo), "max": v3(hi)},
        "vertices": {
            "positions": m.stats.positions,
            "normals": m.stats.normals,
            "uvs": m.stats.uvs,
            "single_indexed": m.positions.len(),
        },
        "faces": m.stats.faces,
        "degenerate_dropped": m.stats.degenerate_dropped,
        "lines_and_points_skipped": m.stats.lines_and_points,
        "materials": materials,
        "warnings": warnings,
    })
}

fn human(s: &Value) -> String {
    let mut out = String::new();
    let f = |v: &Value| v.to_string();
    out += &format!("{}\n", s["file"].as_str().unwrap_or(""));
    out += &format!(
        "  triangles  {}  (from {} faces; {} degenerate dropped)\n",
        s["triangles"], s["faces"], s["degenerate_dropped"]
    );
    out += &format!("  area       {:.6}\n", s["area"].as_f64().unwrap_or(0.0));
    out += &format!(
        "  bounds     {} .. {}\n",
        f(&s["bounds"]["min"]),
        f(&s["bounds"]["max"])
    );
    let v = &s["vertices"];
    out += &format!(
        "  vertices   {} positions, {} normals, {} UVs ({} after single indexing)\n",
        v["positions"], v["normals"], v["uvs"], v["single_indexed"]
    );
    out += "  materials\n";
    for m in s["materials"].as_array().into_iter().flatten() {
        let name = m["name"].as_str().unwrap_or("(none)");
        let map = &m["maps_to"];
        let from = match &m["defined_in"] {
            Value::Null => "default material".to_string(),
            d => format!("{}:{}", d["file"].as_str().unwrap_or(""), d["line"]),
        };
        out += &format!(
            "    {name} ({} triangles, {from}): {} diffuse {} specular {} shininess {} emission {}\n",
            m["triangles"], map["kind"].as_str().unwrap_or(""), f(&map["diffuse"]), f(&map["specular"]), map["shininess"], f(&map["emission"])
        );
        for t in map["maps"].as_array().into_iter().flatten() {
            let how = if t["rendered"] == true {
                "rendered"
            } else {
                "not rendered: constant kept"
            };
            out += &format!(
                "      {} {} ({how})\n",
                t["map"].as_str().unwrap_or(""),
                t["file"].as_str().unwrap_or("")
            );
        }
    }
    out += &format!(
        "  warnings   {}\n",
        s["warnings"].as_array().map_or(0, Vec::len)
    );
    out
}
