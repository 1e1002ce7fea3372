//! Stage 2, check: `render { ... }` → `ir::RenderSettings`, and the active camera.
//!
//! Syntax: `render { resolution 512 x 512  samples rgss 4  light_samples 1  seed 0
//! camera main  output "cornell.png"  exposure 0  tonemap filmic }`. Defaults: 640 x 480,
//! `samples rgss 4`, light_samples 1, seed 0, exposure 0, tonemap filmic, no outputs (the CLI
//! decides), the first camera. Resolution 1..=16384 per side; samples a perfect square up to
//! 65536 with pattern `rgss` (rotated grid) or `grid`; light_samples 1..=1024; `output` may be
//! repeated, the format follows the extension (.png .exr .hdr .pfm).
//!
//! `quality draft|preview|final` picks a preset's samples and light_samples; an explicit
//! `samples` or `light_samples` in the same block wins whatever the order. `noise 0.01` turns on
//! adaptive sampling (relative standard error target, 0.0001..=1) with `max_samples N`
//! (16..=1048576, default 4096).

use super::names::Namespace;
use super::Checker;
use crate::diag::{suggest, Code, Diagnostic};
use crate::ir;
use crate::source::Span;
use crate::syntax::Block;

use super::vocabulary::RENDER_KEYS as KEYS;
const EXTENSIONS: &[&str] = &["png", "exr", "hdr", "pfm"];

/// The settings of a scene without a `render` block.
pub(super) fn default_settings() -> ir::RenderSettings {
    ir::RenderSettings {
        width: 640,
        height: 480,
        samples_per_pixel: 4,
        pattern: ir::SamplePattern::RotatedGrid,
        light_samples: 1,
        seed: 0,
        exposure: 0.0,
        tonemap: ir::ToneMap::Filmic,
        outputs: Vec::new(),
        quality: None,
        noise: None,
        max_samples: None,
    }
}

/// `samples` and `light_samples` as written: they win over a `quality` preset wherever it is.
#[derive(Default)]
struct Explicit {
    samples: Option<u32>,
    light_samples: Option<u32>,
}

impl Checker<'_> {
    pub(super) fn render(&mut self, block: Option<(&Block, Span)>) -> Option<ir::RenderSettings> {
        let mut s = default_settings();
        let Some((block, _)) = block else {
            return Some(s);
        };
        let props = self.split(block, "render settings", KEYS, &["output"], &[]);
        let mut ok = true;
        let mut explicit = Explicit::default();
        for p in &props.props {
            ok &= self.render_property(p, &mut s, &mut explicit);
        }
        if let Some(q) = s.quality {
            s.apply_quality(q);
        }
        if let Some(n) = explicit.samples {
            s.samples_per_pixel = n;
        }
        if let Some(n) = explicit.light_samples {
            s.light_samples = n;
        }
        ok.then_some(s)
    }

    /// Applies one property to `s`; false when it was wrong (and reported).
    fn render_property(
        &mut self,
        p: &super::props::Prop,
        s: &mut ir::RenderSettings,
        explicit: &mut Explicit,
    ) -> bool {
        match p.key {
            "resolution" => self.resolution(p, s).is_some(),
            "samples" => self
                .samples(p, s)
                .map(|()| explicit.samples = Some(s.samples_per_pixel))
                .is_some(),
            "quality" => self
                .one(p, "quality preview")
                .and_then(|e| self.word(e, super::vocabulary::QUALITY_WORDS, "quality preset"))
                .and_then(ir::Quality::from_name)
                .map(|q| s.quality = Some(q))
                .is_some(),
            "noise" => self
                .one(p, "noise 0.01")
                .and_then(|e| self.num_in(e, 1e-4, 1.0, "noise"))
                .map(|x| s.noise = Some(x as f32))
                .is_some(),
            "max_samples" => self
                .one(p, "max_samples 4096")
                .and_then(|e| self.int_in(e, 16, 1 << 20, "max_samples"))
                .map(|n| s.max_samples = Some(n as u32))
                .is_some(),
            "light_samples" => self
                .one(p, "light_samples 1")
                .and_then(|e| self.int_in(e, 1, 1024, "light_samples"))
                .map(|n| explicit.light_samples = Some(n as u32))
                .is_some(),
            "seed" => self
                .one(p, "seed 0")
                .and_then(|e| self.int_in(e, 0, 1 << 53, "seed"))
                .map(|n| s.seed = n)
                .is_some(),
            "camera" => self.select_camera(p).is_some(),
            "output" => self.output(p, s).is_some(),
            "exposure" => self
                .one(p, "exposure 0")
                .and_then(|e| self.num_in(e, -64.0, 64.0, "exposure"))
                .map(|x| s.exposure = x as f32)
                .is_some(),
            "tonemap" => self
                .one(p, "tonemap filmic")
                .and_then(|e| self.choice::<ir::ToneMap>(e, "tone mapping"))
                .map(|t| s.tonemap = t)
                .is_some(),
            other => {
                // split() yields only RENDER_KEYS, each handled above.
                debug_assert!(false, "render key `{other}` has no arm");
                true
            }
        }
    }

    /// `camera NAME`: the camera the render uses.
    fn select_camera(&mut self, p: &super::props::Prop) -> Option<()> {
        let e = self.one(p, "camera NAME")?;
        let i = self.resolve(Namespace::Camera, e)?;
        let name = self.tables[Namespace::Camera as usize].name(i).to_string();
        self.active_camera = self
            .cameras
            .iter()
            .position(|c| c.name == name)
            .unwrap_or(0);
        Some(())
    }

    fn resolution(&mut self, p: &super::props::Prop, s: &mut ir::RenderSettings) -> Option<()> {
        let form = "resolution 640 x 480";
        if let [one] = p.values.to_vec().as_slice() {
            // `640x480` reads as 640 with unit `x480`: evaluating it explains that.
            self.eval(one)?;
        }
        let v = self.arity::<3>(p, form)?;
        if v[1].as_name() != Some("x") {
            self.error(
                Diagnostic::error(
                    Code::CheckBadResolution,
                    "expected `x` between width and height",
                )
                .at(v[1].span, "expected `x`")
                .help(format!("write `{form}`")),
            );
            return None;
        }
        let w = self.int_in(v[0], 1, 16384, "width");
        let h = self.int_in(v[2], 1, 16384, "height");
        s.width = w? as u32;
        s.height = h? as u32;
        Some(())
    }

    fn samples(&mut self, p: &super::props::Prop, s: &mut ir::RenderSettings) -> Option<()> {
        let (pattern, count) = match p.values.to_vec().as_slice() {
            [n] => (ir::SamplePattern::RotatedGrid, *n),
            [pat, n] => (self.choice::<ir::SamplePattern>(pat, "sample pattern")?, *n),
            _ => {
                self.arity::<2>(p, "samples rgss 4")?;
                return None;
            }
        };
        let n = self.int_in(count, 1, 65536, "samples")?;
        let side = (n as f64).sqrt().round() as u64;
        if side * side != n {
            let (lo, hi) = ((side.saturating_sub(1)).max(1), side + 1);
            let near = [lo * lo, side * side, hi * hi];
            let below = near.iter().copied().filter(|&q| q < n).max().unwrap_or(1);
            let above = near.iter().copied().filter(|&q| q > n).min().unwrap_or(4);
            self.error(
                Diagnostic::error(
                    Code::CheckSamplesNotSquare,
                    format!("samples must be a perfect square (1, 4, 9, 16, ...), found {n}"),
                )
                .at(count.span, "not a square")
                .help(format!(
                    "the patterns are N x N grids: try {below} or {above}"
                )),
            );
            return None;
        }
        s.pattern = pattern;
        s.samples_per_pixel = n as u32;
        Some(())
    }

    fn output(&mut self, p: &super::props::Prop, s: &mut ir::RenderSettings) -> Option<()> {
        let e = self.one(p, "output \"image.png\"")?;
        let file = self.asset_path(e)?;
        let ext = file
            .path
            .extension()
            .and_then(|x| x.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        let format = match ext.as_str() {
            "png" => ir::OutputFormat::Png,
            "exr" => ir::OutputFormat::Exr,
            "hdr" => ir::OutputFormat::Hdr,
            "pfm" => ir::OutputFormat::Pfm,
            _ => {
                let help = match suggest::did_you_mean(&ext, EXTENSIONS.iter().copied()) {
                    Some(best) => format!("did you mean `.{best}`?"),
                    None => "use .png (8-bit sRGB) or .exr, .hdr, .pfm (linear float)".to_string(),
                };
                self.error(
                    Diagnostic::error(
                        Code::CheckUnknownOutputFormat,
                        if ext.is_empty() {
                            "the output file has no extension".to_string()
                        } else {
                            format!("unknown output format `.{ext}`")
                        },
                    )
                    .at(e.span, "format follows the extension")
                    .help(help),
                );
                return None;
            }
        };
        s.outputs.push(ir::Output { file, format });
        Some(())
    }
}
