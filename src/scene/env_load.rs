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
use crate::assets::hdr_image::{decode_float_image, ImageError, MAX_HEIGHT, MAX_WIDTH};
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
    let (written, span) = (file.written.clone(), file.span);
    let bytes = match loader.read(&file.path) {
        Ok(b) => b,
        Err(source) if source.kind() == std::io::ErrorKind::NotFound => {
            let e = BuildError::Missing {
                written,
                span,
                source,
            };
            return (None, vec![e]);
        }
        Err(source) => {
            let e = BuildError::Read {
                written,
                span,
                source,
            };
            return (None, vec![e]);
        }
    };
    let image = match decode_float_image(&bytes) {
        Ok(image) => image,
        Err(ImageError::Corrupt(reason)) => {
            let e = BuildError::CorruptImage {
                written,
                span,
                reason,
            };
            return (None, vec![e]);
        }
        Err(ImageError::TooLarge { width, height }) => {
            let e = BuildError::ImageTooLarge {
                written,
                span,
                width,
                height,
                max_width: MAX_WIDTH,
                max_height: MAX_HEIGHT,
            };
            return (None, vec![e]);
        }
    };
    let scale = if intensity.is_finite() && intensity > 0.0 {
        intensity
    } else {
        0.0
    };
    let mut problems = Vec::new();
    let mut invalid = 0usize;
    let mut any_light = false;
    let total = image.pixels.len();
    let texels: Vec<Vec3> = image
        .pixels
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
    if invalid > 0 {
        problems.push(BuildError::InvalidPixels {
            written: written.clone(),
            span,
            count: invalid,
            total,
        });
    }
    if !any_light {
        problems.push(BuildError::BlackEnvironment { written, span });
        return (None, problems);
    }
    let map = EnvMap::new(
        image.width as usize,
        image.height as usize,
        texels,
        rotation_y_rad,
    );
    (map, problems)
}
