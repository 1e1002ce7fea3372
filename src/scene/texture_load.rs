//! Stage 3: an image texture declaration (`texture wood = image("wood.png") { encoding srgb }`)
//! → shared [`ImageData`], its bytes read through the [`Loader`].
//!
//! A missing, unreadable, corrupt, truncated, empty (0 × n) or oversized file (beyond
//! `assets::texture_image::MAX_TEXTURE_SIDE` on a side) is an error labelled at the path
//! literal in the `.scn`. The mip pyramid is built here, once per file and encoding, when any
//! texture naming the file is mip-filtered (`trilinear` or `anisotropic`).

use std::sync::Arc;

use super::BuildError;
use crate::assets::texture_image::{decode_texture, ImageError, MAX_TEXTURE_SIDE};
use crate::assets::Loader;
use crate::ir::{AssetPath, TextureEncoding};
use crate::shade::texture::image::ImageData;

/// Reads and decodes `file`; builds its pyramid if `mipmaps`.
pub fn load_image_texture(
    file: &AssetPath,
    encoding: TextureEncoding,
    mipmaps: bool,
    loader: &dyn Loader,
) -> Result<Arc<ImageData>, BuildError> {
    let (written, span) = (file.written.clone(), file.span);
    let bytes = loader.read(&file.path).map_err(|source| {
        if source.kind() == std::io::ErrorKind::NotFound {
            BuildError::Missing {
                written: written.clone(),
                span,
                source,
            }
        } else {
            BuildError::Read {
                written: written.clone(),
                span,
                source,
            }
        }
    })?;
    let image = decode_texture(&bytes, encoding == TextureEncoding::Srgb).map_err(|e| match e {
        ImageError::Corrupt(reason) => BuildError::CorruptImage {
            written: written.clone(),
            span,
            reason,
        },
        ImageError::TooLarge { width, height } => BuildError::ImageTooLarge {
            written: written.clone(),
            span,
            width,
            height,
            max_width: MAX_TEXTURE_SIDE,
            max_height: MAX_TEXTURE_SIDE,
        },
    })?;
    Ok(Arc::new(ImageData::new(
        image.width,
        image.height,
        image.texels,
        mipmaps,
    )))
}
