//! Ray-throughput benchmark of scnc's acceleration structure against Intel Embree's harness
//! (`bench/peers/embree/rays.c`): the same deterministic primary, shadow and incoherent ray sets
//! on the dense-L5…L8 benchmark scenes, the same checksums, Mrays per CPU-second.
//!
//! ```text
//! cargo bench --bench rays -- [SCENES_DIR] [--scenes dense-L5,dense-L6] [--reps 3]
//!                             [--embree a.csv:b.csv] [--tests both|watertight|mt]
//!                             [--stacks caller|thread]
//! ```
//! `SCENES_DIR` (or `$SCNC_BENCH_SCENES`) holds the directories made by `bench/scenes/gen.py`;
//! without it the benchmark says so and exits 0. `--embree` (or `$SCNC_BENCH_EMBREE`) names a CSV
//! of Embree figures: either the `CSV,` lines `rays` prints, or the merged `results.csv`; several
//! files joined like `PATH` (`a.csv:b.csv`) are merged, keeping Embree's best figure of each.
//!
//! Each ray set's hits are also summarised on stderr as a digest of their bits (hit or miss,
//! `t`, `u`, `v`, instance, triangle of every ray, in order): a kernel change that claims the same
//! bits shows the same digests, whatever the instruction set (`SCNC_SIMD`).
//!
//! Queries run on traversal stacks the benchmark holds (`Accel::closest_hit_with`, as Embree's
//! harness holds an intersect context per chunk of rays); `--stacks thread` makes them reach
//! the thread-local stacks on every query instead (`Accel::closest_hit`, as the renderer does).
//!
//! With `--features bvh-counters`, each ray set also reports the wide nodes tested, leaves
//! entered and packets of four triangles tested per ray (on stderr).
//!
//! Ray generation follows `rays.c` exactly (double precision, stored as f32); timing covers
//! tracing only, on one thread, as thread CPU time (`CLOCK_THREAD_CPUTIME_ID`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Affine3A, DVec3, Vec3};
use scnc::bvh::{Accel, AccelKind, Hit, Instance, MeshRef, Scratch, TriangleTest};
use scnc::geom::Ray;
use scnc::testing::SplitMix64;

struct Obj {
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
}

/// `v` and `f` lines only; polygons are fanned like `rays.c` does.
fn load_obj(path: &Path) -> Result<Obj, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut obj = Obj {
        positions: Vec::new(),
        triangles: Vec::new(),
    };
    for line in text.lines() {
        let mut it = line.split_ascii_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f32> = it.take(3).filter_map(|s| s.parse().ok()).collect();
                let [x, y, z] = c[..] else {
                    return Err(format!("{}: bad v line {line:?}", path.display()));
                };
                obj.positions.push(Vec3::new(x, y, z));
            }
            Some("f") => {
                let n = obj.positions.len() as i64;
                let idx: Vec<u32> = it
                    .filter_map(|s| s.split('/').next()?.parse::<i64>().ok())
                    .map(|k| if k < 0 { n + k } else { k - 1 } as u32)
                    .collect();
                for t in 1..idx.len().saturating_sub(1) {
                    obj.triangles.push([idx[0], idx[t], idx[t + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok(obj)
}

fn rnd(ray: u64, dim: u64) -> f64 {
    (SplitMix64(ray * 4 + dim).next_u64() >> 40) as f64 * (1.0 / 16_777_216.0)
}

/// CPU seconds of the calling thread (wall seconds if the clock is unavailable): the thread
/// CPU clock, as Embree's harness reads it (`/proc/thread-self/schedstat` advances in
/// scheduler ticks on some kernels, 4 ms here: 6% of a pass).
fn thread_cpu_s(wall_start: Instant) -> f64 {
    cpu_time::ThreadTime::try_now().map_or_else(
        |_| wall_start.elapsed().as_secs_f64(),
        |t| t.as_duration().as_secs_f64(),
    )
}

struct Scene {
    name: String,
    meshes: Vec<Obj>,
    primary: Vec<Ray>,
    light: [DVec3; 3],
    eps: f64,
}

fn v3(j: &serde_json::Value) -> Result<DVec3, String> {
    let a = j.as_array().ok_or("expected [x, y, z]")?;
    let c = |k: usize| a.get(k).and_then(|v| v.as_f64()).ok_or("expected a number");
    Ok(DVec3::new(c(0)?, c(1)?, c(2)?))
}

fn load_scene(dir: &Path) -> Result<Scene, String> {
    let json = std::fs::read_to_string(dir.join("scene.json")).map_err(|e| e.to_string())?;
    let s: serde_json::Value = serde_json::from_str(&json).map_err(|e| e.to_string())?;
    let obj_of = |v: &serde_json::Value| -> Result<Obj, String> {
        load_obj(&dir.join(v["obj"].as_str().ok_or("mesh without obj")?))
    };
    let mut meshes = Vec::new();
    for m in s["meshes"].as_array().ok_or("no meshes")? {
        meshes.push(obj_of(m)?);
    }
    meshes.push(obj_of(&s["area_lights"][0])?);
    let l = &meshes[meshes.len() - 1].positions;
    if l.len() < 4 {
        return Err("light OBJ must be a quad".into());
    }
    let light = [l[0].as_dvec3(), l[1].as_dvec3(), l[3].as_dvec3()];
    let (mut lo, mut hi) = (DVec3::splat(1e30), DVec3::splat(-1e30));
    for p in meshes.iter().flat_map(|m| &m.positions) {
        lo = lo.min(p.as_dvec3());
        hi = hi.max(p.as_dvec3());
    }
    let eps = 1e-4 * (hi - lo).max_element();
    let cam = &s["camera"];
    let (eye, target, up) = (v3(&cam["eye"])?, v3(&cam["target"])?, v3(&cam["up"])?);
    let vfov = cam["vfov_deg"].as_f64().ok_or("no vfov")?;
    let res = &s["resolution"];
    let (w, h) = (
        res[0].as_u64().unwrap_or(512),
        res[1].as_u64().unwrap_or(512),
    );
    let f = (target - eye).normalize();
    let r = f.cross(up).normalize();
    let u = r.cross(f);
    let th = (0.5 * vfov * std::f64::consts::PI / 180.0).tan();
    let aspect = w as f64 / h as f64;
    const OFF: [[f64; 2]; 4] = [
        [0.125, 0.375],
        [0.375, -0.125],
        [-0.125, -0.375],
        [-0.375, 0.125],
    ];
    let mut primary = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            for o in OFF {
                let px = (2.0 * (x as f64 + 0.5 + o[0]) / w as f64 - 1.0) * th * aspect;
                let py = (1.0 - 2.0 * (y as f64 + 0.5 + o[1]) / h as f64) * th;
                let d = (f + px * r + py * u).normalize();
                primary.push(Ray::new(eye.as_vec3(), d.as_vec3()));
            }
        }
    }
    let name = dir
        .file_name()
        .map_or("?".into(), |n| n.to_string_lossy().into_owned());
    Ok(Scene {
        name,
        meshes,
        primary,
        light,
        eps,
    })
}

/// The shadow and incoherent rays of `rays.c`, one each per hitting primary ray.
fn secondary(scene: &Scene, hits: &[Option<Hit>]) -> (Vec<Ray>, Vec<Ray>) {
    let (mut shadow, mut incoherent) = (Vec::new(), Vec::new());
    let [l0, l1, l3] = scene.light;
    for (i, (ray, hit)) in scene.primary.iter().zip(hits).enumerate() {
        let Some(h) = hit else { continue };
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let p = o + d * h.t as f64;
        let m = &scene.meshes[h.instance as usize];
        let t = m.triangles[h.prim as usize];
        let v = |k: usize| m.positions[t[k] as usize].as_dvec3();
        let mut n = (v(1) - v(0)).cross(v(2) - v(0)).normalize();
        if n.dot(d) > 0.0 {
            n = -n;
        }
        let so = p + n * scene.eps;
        let i = i as u64;
        let lp = l0 + (l1 - l0) * rnd(i, 0) + (l3 - l0) * rnd(i, 1);
        let ld = lp - so;
        let dist = ld.length();
        shadow.push(Ray::segment(
            so.as_vec3(),
            (ld / dist).as_vec3(),
            (dist * (1.0 - 1e-4)) as f32,
        ));
        let sg = 1.0f64.copysign(n.z);
        let a = -1.0 / (sg + n.z);
        let b = n.x * n.y * a;
        let t1 = DVec3::new(1.0 + sg * n.x * n.x * a, sg * b, -sg * n.x);
        let t2 = DVec3::new(b, sg + n.y * n.y * a, -n.y);
        let (u1, u2) = (rnd(i, 2), rnd(i, 3));
        let (rr, ph) = (u1.sqrt(), 2.0 * std::f64::consts::PI * u2);
        let dir = (t1 * (rr * ph.cos()) + t2 * (rr * ph.sin()) + n * (1.0 - u1).max(0.0).sqrt())
            .normalize();
        incoherent.push(Ray::new(so.as_vec3(), dir.as_vec3()));
    }
    (shadow, incoherent)
}

#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Check {
    hits: u64,
    sum_t: f64,
    sum_prim: u64,
    /// [`digest`] of the hits.
    digest: u64,
}

/// Best-of-`reps` Mrays per CPU-second of closest-hit (or any-hit) tracing, and the checksums.
fn trace(
    accel: &Accel,
    rays: &[Ray],
    any: bool,
    reps: usize,
    thread_stacks: bool,
    out: &mut Vec<Option<Hit>>,
) -> (f64, Check) {
    let mut best = f64::INFINITY;
    // The traversal stacks held across the run, as Embree's harness holds one intersect
    // context per chunk of rays.
    let mut scratch = Scratch::new();
    #[cfg(feature = "bvh-counters")]
    let before = scnc::bvh::tally::counters::read();
    for _ in 0..reps {
        out.clear();
        let wall = Instant::now();
        let c0 = thread_cpu_s(wall);
        if any {
            out.extend(rays.iter().map(|r| {
                let blocked = if thread_stacks {
                    accel.any_hit(r)
                } else {
                    accel.any_hit_with(r, &mut scratch)
                };
                blocked.then_some(Hit {
                    t: 0.0,
                    u: 0.0,
                    v: 0.0,
                    instance: 0,
                    prim: 0,
                })
            }));
        } else {
            out.extend(rays.iter().map(|r| {
                if thread_stacks {
                    accel.closest_hit(r)
                } else {
                    accel.closest_hit_with(r, &mut scratch)
                }
            }));
        }
        best = best.min(thread_cpu_s(wall) - c0);
    }
    #[cfg(feature = "bvh-counters")]
    {
        let after = scnc::bvh::tally::counters::read();
        let per = |k: usize| (after[k] - before[k]) as f64 / (reps * rays.len()) as f64;
        eprintln!(
            "  {} rays, any={any}: per ray {:.2} nodes, {:.2} leaves, {:.2} packets",
            rays.len(),
            per(0),
            per(1),
            per(2)
        );
    }
    let mut c = Check::default();
    for h in out.iter().flatten() {
        c.hits += 1;
        c.sum_t += h.t as f64;
        c.sum_prim += h.prim as u64;
    }
    c.digest = digest(out);
    (rays.len() as f64 / best / 1e6, c)
}

/// A digest of every hit's bits, ray by ray (FNV-1a over 32-bit words, each word scrambled by
/// SplitMix64 so that nearby values do not cancel): equal for equal hit lists, and in practice
/// different for any changed bit.
fn digest(hits: &[Option<Hit>]) -> u64 {
    let mut d = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |w: u32| {
        d = (d ^ SplitMix64(u64::from(w)).next_u64()).wrapping_mul(0x0000_0100_0000_01b3);
    };
    for h in hits {
        match h {
            None => eat(u32::MAX),
            Some(h) => {
                for w in [
                    h.t.to_bits(),
                    h.u.to_bits(),
                    h.v.to_bits(),
                    h.instance,
                    h.prim,
                ] {
                    eat(w);
                }
            }
        }
    }
    d
}

/// Embree figures keyed by (scene, kind): (Mrays per CPU-s, x1 single thread, HIGH; hits).
/// Builds are keyed by (scene, "build1"/"build2") with the seconds in the first field.
fn load_embree(path: &Path) -> HashMap<(String, String), (f64, u64)> {
    let mut out = HashMap::new();
    let Ok(text) = std::fs::read_to_string(path) else {
        eprintln!("(cannot read Embree figures at {})", path.display());
        return out;
    };
    for line in text.lines() {
        let f: Vec<&str> = line.split(',').collect();
        // rays.c prints CSV,name,tris,kind,quality,api,threads,rays,best,mrays,hits,sum_t,sum_prim,per_cpu,load
        // results.csv has scene,tris,kind,quality,api,threads,rays,best,mrays,per_cpu,hits,...
        let (f, per_cpu, hits) = if f.first() == Some(&"CSV") {
            (&f[1..], 12, 9)
        } else {
            (&f[..], 9, 10)
        };
        if f.len() <= per_cpu.max(hits) || f[3] != "high" {
            continue;
        }
        let (scene, kind, api, threads) = (f[0].to_string(), f[2], f[4], f[5]);
        if kind == "build" {
            out.insert(
                (scene, format!("build{threads}")),
                (f[7].parse().unwrap_or(f64::NAN), 0),
            );
        } else if threads == "1" && api.ends_with('1') {
            let v = (
                f[per_cpu].parse().unwrap_or(f64::NAN),
                f[hits].parse().unwrap_or(0),
            );
            out.insert((scene, kind.to_string()), v);
        }
    }
    out
}

struct Args {
    dir: Option<PathBuf>,
    scenes: Vec<String>,
    reps: usize,
    embree: Option<PathBuf>,
    tests: Vec<TriangleTest>,
    /// `--stacks thread`: every query reaches the thread-local stacks.
    thread_stacks: bool,
    /// `--primary-only`: the primary set alone (a profile of primary rays without the
    /// secondary sets mixed in).
    primary_only: bool,
}

fn parse_args() -> Args {
    let mut a = Args {
        dir: std::env::var_os("SCNC_BENCH_SCENES").map(PathBuf::from),
        scenes: ["dense-L5", "dense-L6", "dense-L7", "dense-L8"]
            .map(String::from)
            .to_vec(),
        reps: 3,
        embree: std::env::var_os("SCNC_BENCH_EMBREE").map(PathBuf::from),
        tests: vec![TriangleTest::Watertight, TriangleTest::MollerTrumbore],
        thread_stacks: false,
        primary_only: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(s) = it.next() {
        match s.as_str() {
            "--scenes" => {
                a.scenes = it
                    .next()
                    .unwrap_or_default()
                    .split(',')
                    .map(String::from)
                    .collect()
            }
            "--reps" => a.reps = it.next().and_then(|r| r.parse().ok()).unwrap_or(3).max(1),
            "--embree" => a.embree = it.next().map(PathBuf::from),
            "--stacks" => a.thread_stacks = it.next().as_deref() == Some("thread"),
            "--primary-only" => a.primary_only = true,
            "--tests" => {
                a.tests = match it.next().as_deref() {
                    Some("mt") => vec![TriangleTest::MollerTrumbore],
                    Some("watertight") => vec![TriangleTest::Watertight],
                    _ => a.tests,
                }
            }
            s if s.starts_with("--") => {} // `cargo bench` passes `--bench`
            s => a.dir = Some(PathBuf::from(s)),
        }
    }
    a
}

fn main() {
    let args = parse_args();
    let Some(dir) = args.dir.filter(|d| d.is_dir()) else {
        println!("rays: no benchmark scenes (give a directory made by bench/scenes/gen.py as an argument or in SCNC_BENCH_SCENES); skipping.");
        return;
    };
    // `--embree a.csv,b.csv`: several runs, merged.
    let mut embree = HashMap::new();
    for path in args
        .embree
        .iter()
        .flat_map(|p| std::env::split_paths(p).collect::<Vec<_>>())
    {
        for (k, v) in load_embree(&path) {
            let e = embree.entry(k.clone()).or_insert(v);
            *e = if k.1.starts_with("build") {
                (e.0.min(v.0), v.1)
            } else {
                (e.0.max(v.0), v.1)
            };
        }
    }
    let simd = Accel::build(&[], &[], AccelKind::Bvh).simd();
    println!(
        "instruction set: {simd:?} (chosen at run time; SCNC_SIMD=portable forces the fallback)\n"
    );
    println!("| scene | test | ray kind | rays | hits (Embree) | scnc Mrays/CPU-s | Embree Mrays/CPU-s | ratio |");
    println!("|---|---|---|---:|---:|---:|---:|---:|");
    let mut builds = Vec::new();
    for name in &args.scenes {
        let scene = match load_scene(&dir.join(name)) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{name}: {e}; skipped");
                continue;
            }
        };
        let refs: Vec<MeshRef<'_>> = scene
            .meshes
            .iter()
            .map(|m| MeshRef {
                positions: &m.positions,
                triangles: &m.triangles,
            })
            .collect();
        let instances: Vec<Instance> = (0..refs.len() as u32)
            .map(|i| Instance::new(i, Affine3A::IDENTITY))
            .collect();
        let tris: usize = refs.iter().map(|m| m.triangles.len()).sum();
        for &test in &args.tests {
            // Build: best of reps on the global pool (all cores) and on one thread.
            let mut best = [f64::INFINITY; 2];
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .expect("a 1-thread pool");
            let mut accel = None;
            for _ in 0..args.reps {
                for (k, slot) in best.iter_mut().enumerate() {
                    let t0 = Instant::now();
                    let a = if k == 0 {
                        Accel::build_with(&refs, &instances, AccelKind::Bvh, test)
                    } else {
                        one.install(|| Accel::build_with(&refs, &instances, AccelKind::Bvh, test))
                    };
                    *slot = slot.min(t0.elapsed().as_secs_f64());
                    accel = Some(a);
                }
            }
            let accel = accel.expect("at least one build ran");
            let st = accel.stats();
            let eb = |k: &str| embree.get(&(scene.name.clone(), k.to_string())).copied();
            builds.push(format!(
                "| {} | {:?} | {tris} | {:.3} | {:.3} | {} | {} | {} | {} | {:.1} |",
                scene.name,
                test,
                best[1],
                best[0],
                eb("build1").map_or("-".into(), |v| format!("{:.3}", v.0)),
                eb("build2").map_or("-".into(), |v| format!("{:.3}", v.0)),
                st.nodes,
                st.leaves,
                st.bytes as f64 / tris as f64
            ));
            let mut hits = Vec::new();
            let (mp, cp) = trace(
                &accel,
                &scene.primary,
                false,
                args.reps,
                args.thread_stacks,
                &mut hits,
            );
            if args.primary_only {
                let e = eb("primary");
                println!(
                    "| {} | {:?} | primary | {} | {} | {mp:.2} | {} | - |",
                    scene.name,
                    test,
                    scene.primary.len(),
                    cp.hits,
                    e.map_or("-".into(), |e| format!("{:.2}", e.0)),
                );
                continue;
            }
            let (shadow, incoherent) = secondary(&scene, &hits);
            let (ms, cs) = trace(
                &accel,
                &shadow,
                true,
                args.reps,
                args.thread_stacks,
                &mut hits,
            );
            let (mi, ci) = trace(
                &accel,
                &incoherent,
                false,
                args.reps,
                args.thread_stacks,
                &mut hits,
            );
            for (kind, n, m, c) in [
                ("primary", scene.primary.len(), mp, cp),
                ("shadow", shadow.len(), ms, cs),
                ("incoherent", incoherent.len(), mi, ci),
            ] {
                let e = eb(kind);
                eprintln!(
                    "{} {:?} {kind}: hit digest {:016x}",
                    scene.name, test, c.digest
                );
                println!(
                    "| {} | {:?} | {kind} | {n} | {} ({}) | {m:.2} | {} | {} |",
                    scene.name,
                    test,
                    c.hits,
                    e.map_or("-".into(), |e| e.1.to_string()),
                    e.map_or("-".into(), |e| format!("{:.2}", e.0)),
                    e.map_or("-".into(), |e| format!("{:.2}", m / e.0)),
                );
            }
        }
    }
    println!("\n| scene | test | triangles | build 1T s | build all-cores s | Embree HIGH 1T s | Embree HIGH 2T s | nodes | leaves | bytes/tri |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for b in builds {
        println!("{b}");
    }
}
