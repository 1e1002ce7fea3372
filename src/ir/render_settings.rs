//! Render settings in the IR: image size, sampling, output files and tone mapping.
//!
//! Syntax:
//! ```text
//! render { resolution 512 x 512  samples rgss 4  light_samples 1  seed 0
//!          camera main  output "cornell.png"  exposure 0  tonemap filmic }
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
}
