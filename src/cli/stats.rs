//! `--stats`: the time of each phase, rays by kind, throughput, what the build made and its
//! memory (only the structures the scene uses), how often the per-sample loop took the paths of
//! optional features (and, for textured scenes, how often the anisotropic texture filter ran
//! and its mean taps), samples dropped as NaN or infinite, and peak memory.

use std::fmt::Write;
use std::time::Duration;

use crate::render::{PixelWindow, RenderStats};
use crate::scene::Scene;

/// Wall time of each pipeline phase of one `scnc render`.
#[derive(Debug, Clone, Copy, Default)]
pub struct PhaseStats {
    /// Parse and check (includes read through the loader).
    pub compile: Duration,
    pub asset_load: Duration,
    pub accel_build: Duration,
    pub render: Duration,
    pub write: Duration,
    /// `--tile K/N`: `(K, N)`, the tile's window, and the time of the pre-pass that cut it.
    pub tile: Option<(u32, u32, PixelWindow, Duration)>,
}

impl PhaseStats {
    /// The report printed after the render.
    pub fn report(&self, scene: &Scene, render: &RenderStats) -> String {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let accel = scene.accel_stats();
        let mut s = String::new();
        let _ = writeln!(s, "phase          time");
        for (name, d) in [
            ("parse+check", self.compile),
            ("asset load", self.asset_load),
            ("bvh build", self.accel_build),
            ("render", self.render),
            ("write", self.write),
        ] {
            let _ = writeln!(s, "  {name:<12} {:>9.2} ms", ms(d));
        }
        // The render's own CPU time (every thread's): what its ray rate is per CPU-second of,
        // comparable with `cargo bench --bench rays` on a loaded machine.
        if let Some(cpu) = render.cpu {
            let _ = writeln!(s, "  render cpu   {:>9.2} ms", ms(cpu));
        }
        let _ = writeln!(
            s,
            "image          {}x{}, {} spp, {} threads",
            scene.settings.width, scene.settings.height, render.samples_per_pixel, render.threads
        );
        if let (boosted @ 1.., spp) = render.emitter_pixels {
            let _ = writeln!(
                s,
                "light pixels   {boosted} pixels that may see an area light took {spp} spp"
            );
        }
        if let Some((k, n, w, split)) = self.tile {
            let _ = writeln!(
                s,
                "tile           {k}/{n}: columns {}..{}, rows {}..{} ({}x{} of the {}x{} image); \
                 cost pre-pass {:.2} ms",
                w.x0,
                w.x1,
                w.y0,
                w.y1,
                w.width(),
                w.height(),
                scene.settings.width,
                scene.settings.height,
                ms(split)
            );
        }
        let _ = writeln!(
            s,
            "rays           {} camera, {} shadow, {} BRDF, {} total, {:.2} Mrays/s{}; {} BRDF \
             directions not traced (they miss every light)",
            render.camera_rays,
            render.shadow_rays,
            render.brdf_rays,
            render.rays(),
            render.mrays_per_sec(),
            render
                .mrays_per_cpu_sec()
                .map(|r| format!(", {r:.2} Mrays/CPU-s"))
                .unwrap_or_default(),
            render.counts.brdf_skipped
        );
        let _ = writeln!(
            s,
            "geometry       {} triangles; bvh {} nodes, {} leaves, {:.1} MiB",
            scene.triangle_count(),
            accel.nodes,
            accel.leaves,
            accel.bytes as f64 / (1024.0 * 1024.0)
        );
        if let Some(per) = scene.bytes_per_instance() {
            let _ = writeln!(
                s,
                "instances      {} placements of {} meshes, {per:.0} bytes each (records + top-level bvh)",
                scene.instances.len(),
                scene.meshes.len(),
            );
        }
        let c = &render.counts;
        let _ = writeln!(
            s,
            "sample paths   {} textured, {} specular, {} environment; {} NaN/inf samples dropped",
            c.textured, c.specular, c.environment, c.nonfinite
        );
        if c.textured > 0 {
            let _ = writeln!(
                s,
                "texture filter {} anisotropic lookups, {:.1} taps each on average",
                c.filter.anisotropic,
                c.filter.mean_taps()
            );
        }
        let _ = writeln!(s, "{}", render.noise.summary());
        let _ = writeln!(s, "built");
        for b in scene.inventory() {
            let _ = writeln!(
                s,
                "  {:<18} {:>10}  {}",
                b.what,
                human_bytes(b.bytes),
                b.detail
            );
        }
        let _ = write!(
            s,
            "peak memory    {}",
            peak_memory_bytes()
                .map(|b| format!("{:.1} MiB", b as f64 / (1024.0 * 1024.0)))
                .unwrap_or_else(|| "unknown on this platform".into())
        );
        s
    }
}

/// `1234 B`, `12.1 KiB`, `3.4 MiB`.
fn human_bytes(bytes: usize) -> String {
    let b = bytes as f64;
    if b < 1024.0 {
        format!("{bytes} B")
    } else if b < 1024.0 * 1024.0 {
        format!("{:.1} KiB", b / 1024.0)
    } else {
        format!("{:.1} MiB", b / (1024.0 * 1024.0))
    }
}

/// The process's peak resident set size (Linux `VmHWM`), if the platform tells.
pub fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
