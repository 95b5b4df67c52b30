//! Images and data out of (and into) files: PNG, EXR and PFM images ([`image`]) and how an
//! image becomes an 8-bit picture ([`display`]), the path tracer's checkpoint files
//! ([`checkpoint`]), the `.npy` ray
//! and hit files of `vkrt trace` ([`npy`]), image comparison ([`compare`]) and traversal heat
//! maps ([`heatmap`]). Every file is written to a temporary beside the target and renamed into
//! place.

pub mod checkpoint;
pub mod compare;
pub mod display;
pub mod heatmap;
pub mod image;
pub mod npy;

pub use self::image::{check_writable, read_image, write_image, ImageFormat};

use crate::integrator::Image;
use anyhow::Result;
use display::Display;
use std::path::Path;

/// Writes a rendered `image` to exactly `path`, in the format its extension names: float
/// formats hold the radiance as it is, 8-bit ones go through `display` first. The one place a
/// render's outputs are written.
pub fn write_render(path: &Path, image: &Image, display: &Display) -> Result<()> {
    if ImageFormat::from_path(path)? == ImageFormat::Png {
        write_image(path, &display.apply(image))
    } else {
        write_image(path, image)
    }
}
