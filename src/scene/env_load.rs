//! Stage 3: an environment map declaration (`light sky = environment { image("sky.hdr")
//! intensity 2  rotate 90deg }`) → an [`EnvMap`], its bytes read through the [`Loader`].
//!
//! Invalid texels (a negative, NaN or infinite channel) are set to 0 channel by channel, with one
//! warning counting the pixels affected: a map with a few bad pixels still lights the scene,
//! and the user learns how many. A map that is black everywhere gives a warning and no map (it
//! would light nothing, and its sampling table would divide by zero). A missing, unreadable,
//! corrupt or oversized file is an error labelled at the path literal.

use glam::Vec3;

use super::BuildError;
use crate::assets::hdr_image::{decode_float_image, FloatImage, ImageError, MAX_HEIGHT, MAX_WIDTH};
use crate::assets::Loader;
use crate::ir::AssetPath;
use crate::shade::EnvMap;

/// The map scaled by `intensity` (`None` if it failed or is black), and the problems found.
pub fn load_env_map(
    file: &AssetPath,
    intensity: f32,
    rotation_y_rad: f32,
    loader: &dyn Loader,
) -> (Option<EnvMap>, Vec<BuildError>) {
    let image = match read_image(file, loader) {
        Ok(image) => image,
        Err(e) => return (None, vec![e]),
    };
    let (written, span) = (file.written.clone(), file.span);
    let scale = if intensity.is_finite() && intensity > 0.0 {
        intensity
    } else {
        0.0
    };
    let (width, height, total) = (image.width, image.height, image.pixels.len());
    let texels = clean_texels(image.pixels, scale);
    let mut problems = Vec::new();
    if texels.invalid > 0 {
        problems.push(BuildError::InvalidPixels {
            written: written.clone(),
            span,
            count: texels.invalid,
            total,
        });
    }
    if !texels.any_light {
        problems.push(BuildError::BlackEnvironment { written, span });
        return (None, problems);
    }
    let map = EnvMap::new(
        width as usize,
        height as usize,
        texels.texels,
        rotation_y_rad,
    );
    (map, problems)
}

/// Reads and decodes the file; an error labelled at the path literal if it cannot.
fn read_image(file: &AssetPath, loader: &dyn Loader) -> Result<FloatImage, BuildError> {
    let (written, span) = (file.written.clone(), file.span);
    let bytes = match loader.read(&file.path) {
        Ok(b) => b,
        Err(source) if source.kind() == std::io::ErrorKind::NotFound => {
            return Err(BuildError::Missing {
                written,
                span,
                source,
            })
        }
        Err(source) => {
            return Err(BuildError::Read {
                written,
                span,
                source,
            })
        }
    };
    decode_float_image(&bytes).map_err(|e| match e {
        ImageError::Corrupt(reason) => BuildError::CorruptImage {
            written,
            span,
            reason,
        },
        ImageError::TooLarge { width, height } => BuildError::ImageTooLarge {
            written,
            span,
            width,
            height,
            max_width: MAX_WIDTH,
            max_height: MAX_HEIGHT,
        },
    })
}

/// Scaled texels with every invalid channel set to 0, and what was found.
struct Cleaned {
    texels: Vec<Vec3>,
    /// Pixels with a negative, NaN or infinite channel.
    invalid: usize,
    /// Whether any texel is above 0.
    any_light: bool,
}

fn clean_texels(pixels: Vec<Vec3>, scale: f32) -> Cleaned {
    let mut invalid = 0usize;
    let mut any_light = false;
    let texels = pixels
        .into_iter()
        .map(|p| {
            let clean = |c: f32| if c.is_finite() && c > 0.0 { c } else { 0.0 };
            let bad = !(p.is_finite() && p.min_element() >= 0.0);
            invalid += bad as usize;
            let t = Vec3::new(clean(p.x), clean(p.y), clean(p.z)) * scale;
            // Scaling a huge finite value can overflow: that is black too, not infinite.
            let t = if t.is_finite() { t } else { Vec3::ZERO };
            any_light |= t.max_element() > 0.0;
            t
        })
        .collect();
    Cleaned {
        texels,
        invalid,
        any_light,
    }
}
