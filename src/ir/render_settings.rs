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
    /// Every preset, in order of cost.
    pub const ALL: [Quality; 3] = [Quality::Draft, Quality::Preview, Quality::Final];

    /// The preset a name in [`Quality::NAMES`] stands for.
    pub fn from_name(name: &str) -> Option<Quality> {
        Quality::ALL.into_iter().find(|q| q.name() == name)
    }

    /// The preset's name in the language and on the command line.
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

/// The curve from exposed radiance to the [0, 1] range of an 8-bit image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ToneMap {
    /// Scale by exposure, clamp to [0, 1].
    Clamp,
    /// Reinhard: x / (1 + x).
    Reinhard,
    /// The ACES filmic fit (Narkowicz 2015).
    Filmic,
}

/// An image file format, chosen by the output's extension.
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

/// One `output "file"` of the render block.
#[derive(Debug, Clone, Serialize)]
pub struct Output {
    /// Where to write, as written in the scene (with its span).
    pub file: AssetPath,
    /// The format its extension names.
    pub format: OutputFormat,
}

/// The `render { }` block, resolved: every setting has its value.
#[derive(Debug, Clone, Serialize)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel: a perfect square N² (N per side of the pattern).
    pub samples_per_pixel: u32,
    /// How the samples are laid out in the pixel.
    pub pattern: SamplePattern,
    /// Multiplies each area light's own `samples` (default 1).
    pub light_samples: u32,
    /// Seeds every random number of the render (same seed, same image).
    pub seed: u64,
    /// Exposure in stops: radiance is scaled by 2^exposure before tone mapping.
    pub exposure: f32,
    /// How exposed radiance becomes 8-bit values (PNG only).
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

    /// A fixed count of `spp` samples per pixel, adaptive sampling off (`--spp N`, and each
    /// preview pass of `scnc watch`). The renderer rounds the count up to the next square N²
    /// (its patterns are N×N).
    pub fn fix_samples(&mut self, spp: u32) {
        self.samples_per_pixel = spp;
        self.noise = None;
    }

    /// The one place where command-line choices meet the scene's `render { }` block, before
    /// the render starts. The checker has already resolved the block itself (`samples` beats
    /// `quality`, which beats the default); here a flag beats the scene and, at the command
    /// line, an explicit count beats a preset: `--spp` > `--quality` > `samples` > `quality` >
    /// default, and `--quality` > `light_samples` > `quality` > default. `--noise` (or the
    /// scene's `noise`) samples adaptively up to `--max-samples` (or the scene's); `--spp`
    /// turns the scene's adaptive sampling off.
    pub fn resolve(&mut self, flags: &SettingFlags) {
        if let Some((width, height)) = flags.resolution {
            self.width = width;
            self.height = height;
        }
        if let Some(q) = flags.quality {
            self.apply_quality(q);
        }
        if let Some(spp) = flags.spp {
            self.fix_samples(spp);
        }
        if let Some(e) = flags.noise {
            self.noise = Some(e);
        }
        if let Some(n) = flags.max_samples {
            self.max_samples = Some(n);
        }
    }
}

/// The command line's render settings, each `None` when not given (see
/// [`RenderSettings::resolve`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SettingFlags {
    /// `--resolution WxH`.
    pub resolution: Option<(u32, u32)>,
    /// `--quality PRESET`.
    pub quality: Option<Quality>,
    /// `--spp N`.
    pub spp: Option<u32>,
    /// `--noise E`.
    pub noise: Option<f32>,
    /// `--max-samples N`.
    pub max_samples: Option<u32>,
}

#[cfg(test)]
mod tests {
    use super::{Quality, RenderSettings, SamplePattern, SettingFlags, ToneMap};

    fn scene(samples: u32, noise: Option<f32>) -> RenderSettings {
        RenderSettings {
            width: 8,
            height: 8,
            samples_per_pixel: samples,
            pattern: SamplePattern::RotatedGrid,
            light_samples: 2,
            seed: 0,
            exposure: 0.0,
            tonemap: ToneMap::Clamp,
            outputs: Vec::new(),
            quality: None,
            noise,
            max_samples: None,
        }
    }

    fn resolved(mut s: RenderSettings, flags: SettingFlags) -> RenderSettings {
        s.resolve(&flags);
        s
    }

    #[test]
    fn no_flags_keep_the_scene() {
        let s = resolved(scene(64, Some(0.1)), SettingFlags::default());
        assert_eq!(
            (s.samples_per_pixel, s.light_samples, s.noise),
            (64, 2, Some(0.1))
        );
    }

    #[test]
    fn spp_beats_quality_beats_the_scene() {
        let q = SettingFlags {
            quality: Some(Quality::Draft),
            ..SettingFlags::default()
        };
        let s = resolved(scene(64, None), q);
        assert_eq!((s.samples_per_pixel, s.light_samples), (1, 4));
        let both = SettingFlags { spp: Some(9), ..q };
        let s = resolved(scene(64, None), both);
        assert_eq!((s.samples_per_pixel, s.light_samples), (9, 4));
    }

    #[test]
    fn spp_turns_the_scenes_adaptive_sampling_off_and_noise_turns_it_on() {
        let spp = SettingFlags {
            spp: Some(4),
            ..SettingFlags::default()
        };
        assert_eq!(resolved(scene(64, Some(0.1)), spp).noise, None);
        let noise = SettingFlags {
            noise: Some(0.05),
            max_samples: Some(256),
            ..SettingFlags::default()
        };
        let s = resolved(scene(64, None), noise);
        assert_eq!((s.noise, s.max_samples), (Some(0.05), Some(256)));
    }

    #[test]
    fn resolution_replaces_the_scenes() {
        let flags = SettingFlags {
            resolution: Some((320, 240)),
            ..SettingFlags::default()
        };
        let s = resolved(scene(1, None), flags);
        assert_eq!((s.width, s.height), (320, 240));
    }
}
