//! OBJ parse speed: scnc's parser against tobj (the parser it replaced) on the same file, in the
//! same run. Usage:
//!
//! ```text
//! python3 ../shared/bench/scenes/gen.py /tmp/bvh_scenes
//! cargo bench --bench obj -- /tmp/bvh_scenes/dense-L8/blob.obj [runs]
//! ```
//!
//! Prints, for each parser, the best of `runs` (default 5) wall times, MB/s, triangles/s and
//! ns per triangle, and scnc's peak heap bytes per triangle (counted by a wrapping allocator,
//! the file's own bytes excluded). Figures are recorded in docs/obj.md.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator unchanged and only counts bytes.
#[allow(unsafe_code)] // a counting allocator is the only way to measure the peak heap
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        System.alloc(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
        System.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        if new > l.size() {
            let now = LIVE.fetch_add(new - l.size(), Ordering::Relaxed) + new - l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        } else {
            LIVE.fetch_sub(l.size() - new, Ordering::Relaxed);
        }
        System.realloc(p, l, new)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn best(runs: usize, mut f: impl FnMut() -> usize) -> (Duration, usize) {
    let mut best = Duration::MAX;
    let mut tris = 0;
    for _ in 0..runs {
        let t = Instant::now();
        tris = f();
        best = best.min(t.elapsed());
    }
    (best, tris)
}

fn report(name: &str, bytes: usize, (t, tris): (Duration, usize)) {
    let s = t.as_secs_f64();
    println!(
        "{name:>5}: {:8.1} ms  {:7.1} MB/s  {:6.2} Mtri/s  {:6.1} ns/tri  ({tris} triangles)",
        s * 1e3,
        bytes as f64 / s / 1e6,
        tris as f64 / s / 1e6,
        s * 1e9 / tris.max(1) as f64
    );
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let Some(path) = args.first() else {
        eprintln!("usage: cargo bench --bench obj -- FILE.obj [runs]  (see the file's header)");
        return;
    };
    let runs: usize = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(5);
    let bytes = match std::fs::read(path) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("cannot read {path}: {e}");
            return;
        }
    };
    println!("{path}: {:.1} MB, best of {runs}", bytes.len() as f64 / 1e6);

    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let ours = best(runs, || match scnc::assets::obj::parse_obj(&bytes) {
        Ok((m, _)) => m.triangles.len(),
        Err(e) => panic!("scnc failed: {e:?}"),
    });
    let peak = PEAK.load(Ordering::Relaxed) - before;
    report("scnc", bytes.len(), ours);
    println!(
        "       peak heap {:.1} MiB = {:.1} B/triangle",
        peak as f64 / (1 << 20) as f64,
        peak as f64 / ours.1.max(1) as f64
    );

    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let theirs = best(runs, || {
        let mut reader = std::io::Cursor::new(&bytes);
        match tobj::load_obj_buf(&mut reader, &options, |_| Ok(Default::default())) {
            Ok((models, _)) => models.iter().map(|m| m.mesh.indices.len() / 3).sum(),
            Err(e) => panic!("tobj failed: {e}"),
        }
    });
    report("tobj", bytes.len(), theirs);
    println!(
        "scnc / tobj time: {:.2}",
        ours.0.as_secs_f64() / theirs.0.as_secs_f64()
    );
}
