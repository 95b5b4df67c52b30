//! Images and data out of (and into) files: PNG, EXR and PFM images ([`image`]), the `.npy` ray
//! and hit files of `vkrt trace` ([`npy`]), image comparison ([`compare`]) and traversal heat
//! maps ([`heatmap`]). Every file is written to a temporary beside the target and renamed into
//! place.

pub mod compare;
pub mod heatmap;
pub mod image;
pub mod npy;

pub use self::image::{check_writable, read_image, write_image, ImageFormat};

use crate::integrator::Image;
use anyhow::Result;
use std::path::Path;

/// Writes a rendered `image`, and with `preview` beside a float image also a PNG preview (same
/// name, `.png`): the one place a render's output is written.
pub fn write_render(path: &Path, image: &Image, preview: bool) -> Result<()> {
    write_image(path, image)?;
    if preview && ImageFormat::from_path(path)? != ImageFormat::Png {
        write_image(&path.with_extension("png"), image)?;
    }
    Ok(())
}
