//! `scnc watch` benchmark (a program, not a test): `cargo bench --bench watch [-- --edits N]`.
//!
//! 1. Save → first updated image: runs the real `scnc watch --events json --no-serve` on a copy
//!    of `examples/cornell.scn` (its full 512×512 resolution; the first pass is preview quality,
//!    1 spp), saves N camera edits, and times each from the write to the first `pass` event
//!    (the image is written before that event is printed). The compile share is the `ms` of the
//!    `compiled` event. Medians are reported.
//! 2. Camera-only edit vs full rebuild on a dense scene (a 1144-segment UV sphere, ~1.3M
//!    triangles): `scene::build` from scratch vs `scene::build_cached` after a camera edit.
//!
//! Figures go to docs/watch.md by hand.

use std::time::{Duration, Instant};

use scnc::assets::MemLoader;
use scnc::compile::compile_source;
use scnc::scene::{self, BuildCache, BuildOptions};

#[path = "support/watch_process.rs"]
mod watch_process;
use watch_process::WatchProcess;

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn save_to_image(edits: usize) {
    let dir = std::env::temp_dir().join(format!("scnc-watch-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let root = env!("CARGO_MANIFEST_DIR");
    let original =
        std::fs::read_to_string(format!("{root}/examples/cornell.scn")).expect("cornell.scn");
    let scn = dir.join("cornell.scn");
    std::fs::write(&scn, &original).expect("write scene");
    let watch = WatchProcess::start(&dir, "cornell.scn", Duration::from_secs(60));
    let wait = |name: &str, final_only: bool| watch.wait(name, final_only);
    wait("pass", true);
    let (mut latency, mut compile, mut pass) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..edits {
        let eye = format!("eye (278, {}, -800)", 273 + 1 + i % 2);
        let text = original.replace("eye (278, 273, -800)", &eye);
        let t0 = Instant::now();
        std::fs::write(&scn, text).expect("save");
        let (_, c) = wait("compiled", false);
        let (t1, p) = wait("pass", false);
        latency.push((t1 - t0).as_secs_f64() * 1e3);
        compile.push(c["ms"].as_f64().unwrap_or(0.0));
        pass.push(p["ms"].as_f64().unwrap_or(0.0));
        // Let the refining passes finish, as a person would between two saves.
        wait("pass", true);
    }
    drop(watch);
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "cornell 512x512, {edits} camera edits: save -> first image median {:.1} ms \
         (compile+build {:.2} ms, first pass at 1 spp {:.1} ms; the rest is event batching \
         and the write)",
        median(&mut latency),
        median(&mut compile),
        median(&mut pass)
    );
}

fn dense(eye_z: f32) -> String {
    format!(
        "scnc 1
camera main {{ eye (0, 1.6, {eye_z})  target (0, 0.9, 0)  up (0, 1, 0)  fov 40deg }}
material blob = phong {{ diffuse rgb(0.7, 0.7, 0.7) }}
mesh ball = sphere {{ radius 1  segments 1144 }}
mesh floor = quad {{ size (10, 10) }}
object ball {{ material blob  transform {{ translate (0, 1, 0) }} }}
object floor {{ material blob }}
light key = point {{ position (2, 4, -3)  intensity rgb(30, 30, 30) }}
render {{ resolution 64 x 64  samples 1 }}
"
    )
}

fn camera_edit_vs_rebuild() {
    let loader = MemLoader::new();
    let opts = BuildOptions::default();
    let mut cache = BuildCache::new();
    let (mut full, mut camera) = (Vec::new(), Vec::new());
    let mut triangles = 0;
    for i in 0..3 {
        let compiled = compile_source("dense.scn", &dense(-4.2), &loader);
        let desc = compiled.scene.expect("dense scene compiles");
        let t = Instant::now();
        let s = scene::build(&desc, &loader, &opts).value.expect("builds");
        full.push(t.elapsed().as_secs_f64() * 1e3);
        triangles = s.triangle_count();
        drop(s);

        if i == 0 {
            let s = scene::build_cached(&desc, &loader, &opts, &mut cache)
                .value
                .expect("builds");
            cache.recycle(s);
        }
        let t = Instant::now();
        let compiled = compile_source("dense.scn", &dense(-4.0 - i as f32 * 0.1), &loader);
        let desc = compiled.scene.expect("compiles");
        let s = scene::build_cached(&desc, &loader, &opts, &mut cache)
            .value
            .expect("builds");
        camera.push(t.elapsed().as_secs_f64() * 1e3);
        assert!(
            cache.report().rebuilt().is_empty(),
            "camera edit rebuilt something"
        );
        cache.recycle(s);
    }
    println!(
        "dense {triangles} triangles: full build median {:.1} ms; camera-only edit (compile + \
         cached build) median {:.2} ms",
        median(&mut full),
        median(&mut camera)
    );
}

fn main() {
    let mut edits = 15;
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--edits") {
        edits = args
            .get(i + 1)
            .and_then(|n| n.parse().ok())
            .unwrap_or(edits);
    }
    save_to_image(edits.max(1));
    camera_edit_vs_rebuild();
}
