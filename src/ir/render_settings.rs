//! Render settings in the IR: image size, sampling, output files and tone mapping.
//!
//! Syntax:
//! ```text
//! render { resolution 512 x 512  samples rgss 4  light_samples 1  seed 0
//!          camera main  output "cornell.png"  exposure 0  tonemap filmic
//!          quality preview  noise 0.01  max_samples 4096 }
//! ```

use serde::Serialize;

use super::AssetPath;

/// How the sub-pixel sample positions are laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum SamplePattern {
    /// N×N points on a grid rotated so that every row and every column of the N²×N² sub-grid
    /// holds exactly one sample (N = 2 is the classic 4-sample RGSS).
    RotatedGrid,
    /// N×N points at the centres of an axis-aligned grid.
    Grid,
}

/// A named point on the speed/accuracy curve: `render { quality draft }` or `--quality draft`.
/// Each preset is a sample count and a light-sample count (measured in docs/quality.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Quality {
    /// 1 sample per pixel, 4 light samples: a noisy but complete picture in milliseconds.
    Draft,
    /// 16 samples per pixel, 1 light sample.
    Preview,
    /// 256 samples per pixel, 1 light sample.
    Final,
}

impl Quality {
    /// The preset names in the language and on the command line, in order of cost.
    pub const NAMES: &'static [&'static str] = &["draft", "preview", "final"];
    pub const ALL: [Quality; 3] = [Quality::Draft, Quality::Preview, Quality::Final];

    pub fn from_name(name: &str) -> Option<Quality> {
        Quality::ALL.into_iter().find(|q| q.name() == name)
    }

    pub fn name(self) -> &'static str {
        match self {
            Quality::Draft => "draft",
            Quality::Preview => "preview",
            Quality::Final => "final",
        }
    }

    /// Samples per pixel (a perfect square).
    pub fn samples_per_pixel(self) -> u32 {
        match self {
            Quality::Draft => 1,
            Quality::Preview => 16,
            Quality::Final => 256,
        }
    }

    /// The scene's `light_samples`.
    pub fn light_samples(self) -> u32 {
        match self {
            Quality::Draft => 4,
            Quality::Preview | Quality::Final => 1,
        }
    }
}

/// Default `max_samples` of adaptive sampling.
pub const DEFAULT_MAX_SAMPLES: u32 = 4096;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ToneMap {
    /// Scale by exposure, clamp to [0, 1].
    Clamp,
    /// Reinhard: x / (1 + x).
    Reinhard,
    /// The ACES filmic fit (Narkowicz 2015).
    Filmic,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum OutputFormat {
    /// 8-bit sRGB PNG after exposure and tone mapping.
    Png,
    /// Linear radiance, OpenEXR (float).
    Exr,
    /// Linear radiance, Radiance RGBE.
    Hdr,
    /// Linear radiance, portable float map.
    Pfm,
}

#[derive(Debug, Clone, Serialize)]
pub struct Output {
    pub file: AssetPath,
    pub format: OutputFormat,
}

#[derive(Debug, Clone, Serialize)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel: a perfect square N² (N per side of the pattern).
    pub samples_per_pixel: u32,
    pub pattern: SamplePattern,
    /// Multiplies each area light's own `samples` (default 1).
    pub light_samples: u32,
    pub seed: u64,
    /// Exposure in stops: radiance is scaled by 2^exposure before tone mapping.
    pub exposure: f32,
    pub tonemap: ToneMap,
    /// Output files; empty means the CLI decides (`-o`, or the scene's name with `.png`).
    pub outputs: Vec<Output>,
    /// The preset that chose `samples_per_pixel` and `light_samples` (an explicit `samples` or
    /// `light_samples` beside it wins over the preset's value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quality: Option<Quality>,
    /// Adaptive sampling: keep sampling each pixel until the relative standard error of its
    /// mean is below this (e.g. 0.01), up to `max_samples`. `None`: a fixed sample count.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub noise: Option<f32>,
    /// The cap of adaptive sampling; `None` is [`DEFAULT_MAX_SAMPLES`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_samples: Option<u32>,
}

impl RenderSettings {
    /// Applies a preset: its sample and light-sample counts.
    pub fn apply_quality(&mut self, q: Quality) {
        self.quality = Some(q);
        self.samples_per_pixel = q.samples_per_pixel();
        self.light_samples = q.light_samples();
    }
}
