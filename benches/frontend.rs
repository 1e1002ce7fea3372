//! Front-end benchmark (a program, not a test): `cargo bench --bench frontend`.
//!
//! Generates in memory the statement-dense scene of issue 22 (~10 MB, 100,000 top-level
//! statements: objects with a rotate and a translate, 20,000 materials, groups 4 deep, long transform chains;
//! `BENCH_DENSE_ONLY=1` stops after it, `BENCH_WRITE_DENSE=PATH` only writes it out for
//! `scnc check` runs), the 50,003-statement scene of issue 2 (every object uses a `let`, one box
//! mesh per object; `BENCH_STATEMENTS_ONLY=1` measures it alone), one inline mesh of 1,000,000
//! vertices (a 1000 × 1000 grid, ~2M triangles) and the last two in one file, compiles each with
//! `compile_source`, and reports throughput (MB of source per second) and peak heap use relative
//! to the source size, measured by a counting global allocator. Figures go to docs/frontend-bench.md by hand.

// A global allocator needs `unsafe impl`; it only forwards to the system allocator.
#![allow(unsafe_code)]

use std::fmt::Write;
use std::sync::atomic::Ordering;
use std::time::Instant;

use scnc::assets::MemLoader;
use scnc::compile::compile_source;

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{Counting, CURRENT, PEAK};

#[global_allocator]
static ALLOC: Counting = Counting;

const GRID: usize = 1000;

fn statements_scene(n: usize) -> String {
    let mut s =
        String::from("scnc 1\ncamera main { eye (0, 50, -200)  target (0, 0, 0)  fov 40deg }\n");
    let per = n / 5;
    for i in 0..per {
        let _ = writeln!(s, "let k{i} = {}.5 * 2 + {i}", i % 7);
        let _ = writeln!(
            s,
            "material m{i} = phong {{ diffuse rgb(0.{}, 0.5, 0.25)  specular 0.1 }}",
            i % 9
        );
        let _ = writeln!(s, "mesh b{i} = box {{ size ({}.5, 1, 1) }}", 1 + i % 3);
        let _ = writeln!(
            s,
            "object b{i} {{ material m{i}  transform {{ rotate y {}deg  translate (k{i}, 0, {i}) }} }}",
            i % 360
        );
        let _ = writeln!(s, "group g{i} {{ object b{i} {{ material m{i} }} }}");
    }
    s.push_str("light sun = point { position (0, 100, 0)  intensity 1000 }\n");
    s
}

/// The generated scene of issue 22: statement-dense text as exporters write it, about 10 MB.
/// Per unit of 10 statements: 2 materials, 6 objects of a few shared meshes (each with a rotate
/// and a translate), one object with a long transform chain and one group nested 4 deep.
fn dense_scene(units: usize) -> String {
    let mut s = String::with_capacity(units * 1100);
    s.push_str("scnc 1\ncamera main { eye (0, 50, -200)  target (0, 0, 0)  fov 40deg }\n");
    s.push_str("mesh tree = icosphere { radius 1  subdivisions 1 }\n");
    s.push_str("mesh rock = box { size (1, 0.5, 1) }\nmesh post = box { size (0.2, 2, 0.2) }\n");
    let meshes = ["tree", "rock", "post"];
    for u in 0..units {
        let _ = writeln!(
            s,
            "material bark{u} = phong {{ diffuse rgb(0.{}, 0.3, 0.2)  specular 0.05 }}",
            u % 10
        );
        let _ = writeln!(
            s,
            "material leaf{u} = phong {{ diffuse rgb(0.1, 0.{}, 0.1)  specular 0.2  shininess 20 }}",
            u % 10
        );
        for k in 0..6 {
            let i = u * 6 + k;
            let _ = writeln!(
                s,
                "object {} {{ material leaf{u}  transform {{ rotate y {}deg  translate ({}.25, 0, {}.5) }} }}",
                meshes[k % 3],
                i % 360,
                i % 1000,
                i / 1000
            );
        }
        let _ = writeln!(
            s,
            "object post {{ material bark{u}  transform {{ scale 0.5  rotate x 10deg  rotate y {}deg  \
             rotate z 5deg  translate (1, 2, 3)  scale (1, 1.5, 1)  translate ({}, 0, -{}) }} }}",
            u % 360,
            u % 100,
            u / 100
        );
        let _ = writeln!(
            s,
            "group block{u} {{\n  transform {{ translate ({u}, 0, 0) }}\n  group a{u} {{ group b{u} {{ group c{u} {{\n    \
             object rock {{ material bark{u}  transform {{ rotate y 30deg  translate (0, 1, 0) }} }}\n  }} }} }}\n}}"
        );
    }
    s.push_str("light sun = point { position (0, 100, 0)  intensity 1000 }\n");
    s
}

fn mesh_scene() -> String {
    let mut s = String::with_capacity(80 * GRID * GRID);
    s.push_str("scnc 1\ncamera main { eye (0, 50, -200)  target (0, 0, 0)  fov 40deg }\n");
    s.push_str("material grey = phong { diffuse 0.5 }\nmesh terrain = inline {\n  positions [");
    for j in 0..GRID {
        for i in 0..GRID {
            let h = ((i * 7 + j * 13) % 100) as f32 * 0.013;
            let _ = write!(
                s,
                "({:.3}, {:.3}, {:.3}) ",
                i as f32 * 0.1,
                h,
                j as f32 * 0.1
            );
        }
        s.push('\n');
    }
    s.push_str("]\n  indices [");
    for j in 0..GRID - 1 {
        for i in 0..GRID - 1 {
            let a = j * GRID + i;
            let _ = write!(
                s,
                "{} {} {} {} {} {} ",
                a,
                a + GRID,
                a + 1,
                a + 1,
                a + GRID,
                a + GRID + 1
            );
        }
        s.push('\n');
    }
    s.push_str("]\n}\nobject terrain { material grey }\nlight sun = point { position (0, 100, 0)  intensity 1000 }\n");
    s
}

fn measure(label: &str, text: &str) {
    let loader = MemLoader::new();
    // Best of three runs for time (wall, and this thread's CPU time, which a machine loaded by
    // other jobs inflates far less); peak heap from the first, relative to the heap before it.
    let mut best = f64::MAX;
    let mut best_cpu = f64::MAX;
    let mut peak_extra = 0;
    for run in 0..3 {
        let base = CURRENT.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let t = Instant::now();
        let cpu = cpu_time::ThreadTime::now();
        let compiled = compile_source("bench.scn", text, &loader);
        let secs = t.elapsed().as_secs_f64();
        best_cpu = best_cpu.min(cpu.elapsed().as_secs_f64());
        assert!(
            compiled.scene.is_some(),
            "{:#?}",
            &compiled.diagnostics[..compiled.diagnostics.len().min(3)]
        );
        if run == 0 {
            peak_extra = PEAK.load(Ordering::Relaxed) - base;
        }
        drop(compiled);
        best = best.min(secs);
    }
    // What the AST alone holds, and the parse's own time (the syntax stage's share).
    let base = CURRENT.load(Ordering::Relaxed);
    let cpu = cpu_time::ThreadTime::now();
    let parsed = scnc::syntax::parse(scnc::source::FileId(0), text);
    let parse_cpu = cpu.elapsed().as_secs_f64();
    let ast = CURRENT.load(Ordering::Relaxed) - base;
    drop(parsed);
    let mb = text.len() as f64 / 1e6;
    println!(
        "  parse alone: cpu {:7.1} ms  {:7.1} MB/s  AST {:7.1} MB = {:4.2} x source",
        parse_cpu * 1e3,
        mb / parse_cpu,
        ast as f64 / 1e6,
        ast as f64 / text.len() as f64
    );
    println!(
        "{label:<34} {mb:8.1} MB  {:7.1} ms  {:7.1} MB/s  cpu {:7.1} ms  {:7.1} MB/s  \
         peak heap {:7.1} MB = {:4.2} x source",
        best * 1e3,
        mb / best,
        best_cpu * 1e3,
        mb / best_cpu,
        peak_extra as f64 / 1e6,
        peak_extra as f64 / text.len() as f64
    );
}

fn main() {
    if std::env::var_os("BENCH_STATEMENTS_ONLY").is_some() {
        let statements = statements_scene(50_000);
        let lines = statements.lines().count();
        measure(&format!("{lines} statements (issue 2)"), &statements);
        return;
    }
    let dense = dense_scene(10_000);
    if let Some(path) = std::env::var_os("BENCH_WRITE_DENSE") {
        // For `scnc check` / `scnc watch` timings and `/usr/bin/time -v` peaks on the same text.
        std::fs::write(path, &dense).expect("write the dense scene");
        return;
    }
    let statements_count = dense.matches('\n').count();
    measure(
        &format!("dense, {statements_count} lines (issue 22)"),
        &dense,
    );
    if std::env::var_os("BENCH_DENSE_ONLY").is_some() {
        return;
    }
    drop(dense);
    let statements = statements_scene(50_000);
    let lines = statements.lines().count();
    measure(&format!("{lines} statements (issue 2)"), &statements);
    let mesh = mesh_scene();
    measure("1,000,000-vertex inline mesh", &mesh);
    let mut both = statements;
    both.push_str(
        &mesh
            .split_once('\n')
            .map_or("", |(_, rest)| rest)
            .replace("camera main", "camera main2")
            .replace("light sun", "light sun2"),
    );
    measure("both in one file", &both);
}
