//! Images by extension: `.png` (sRGB, 8-bit; values are clipped to [0, 1], so callers pass a
//! display-referred image, `display::Display::apply`), `.exr` and `.pfm` (linear float32).
//! Row 0 is the top of every image. Files are written to a temporary name beside the target and
//! renamed into place, so an existing output is never replaced by a partial one.

use crate::files;
use crate::integrator::Image;
use anyhow::{anyhow, bail, Context as _, Result};
use std::io::Write as _;
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Exr,
    Pfm,
}

impl ImageFormat {
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path.extension().and_then(|e| e.to_str()).map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Self::Png),
            Some("exr") => Ok(Self::Exr),
            Some("pfm") => Ok(Self::Pfm),
            _ => bail!("{}: unknown image format; use .png, .exr or .pfm", path.display()),
        }
    }
}

/// Linear to sRGB-encoded, clamped to [0, 1] (IEC 61966-2-1).
pub fn linear_to_srgb(x: f32) -> f32 {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) };
    if x <= 0.0031308 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// Fails now, before any rendering, if `path` has an unknown extension or its folder cannot
/// be written.
pub fn check_writable(path: &Path) -> Result<()> {
    ImageFormat::from_path(path)?;
    let tmp = files::temp_beside(path);
    std::fs::File::create(&tmp).with_context(|| format!("{}: cannot write the output here", path.display()))?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Writes `image` to `path` in the format its extension names, atomically.
pub fn write_image(path: &Path, image: &Image) -> Result<()> {
    let format = ImageFormat::from_path(path)?;
    files::write_whole(path, |tmp| write_format(tmp, format, image))
}

fn write_format(path: &Path, format: ImageFormat, image: &Image) -> Result<()> {
    match format {
        ImageFormat::Png => {
            let bytes: Vec<u8> = image.pixels.iter().flat_map(|p| p.map(|c| (linear_to_srgb(c) * 255.0 + 0.5) as u8)).collect();
            let buf = image::RgbImage::from_raw(image.width, image.height, bytes).ok_or_else(|| anyhow!("image size mismatch"))?;
            buf.save_with_format(path, image::ImageFormat::Png)?;
        }
        ImageFormat::Exr => {
            let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
            let buf = image::Rgb32FImage::from_raw(image.width, image.height, data).ok_or_else(|| anyhow!("image size mismatch"))?;
            image::DynamicImage::ImageRgb32F(buf).save_with_format(path, image::ImageFormat::OpenExr)?;
        }
        ImageFormat::Pfm => {
            let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
            // Colour PFM, little-endian (negative scale). PFM stores the bottom row first.
            write!(f, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
            for y in (0..image.height).rev() {
                for x in 0..image.width {
                    for c in image.get(x, y) {
                        f.write_all(&c.to_le_bytes())?;
                    }
                }
            }
            f.flush()?;
        }
    }
    Ok(())
}

/// Reads a `.png` (decoded from sRGB to linear), `.exr` or `.pfm`.
pub fn read_image(path: &Path) -> Result<Image> {
    let format = ImageFormat::from_path(path)?;
    let ctx = || format!("reading {}", path.display());
    match format {
        ImageFormat::Pfm => read_pfm(path).with_context(ctx),
        ImageFormat::Png | ImageFormat::Exr => {
            let img = image::open(path).with_context(ctx)?;
            let linear = format == ImageFormat::Exr;
            let rgb = img.to_rgb32f();
            let (width, height) = rgb.dimensions();
            let pixels = rgb.pixels().map(|p| if linear { p.0 } else { p.0.map(srgb_to_linear) }).collect();
            Ok(Image { width, height, pixels })
        }
    }
}

/// sRGB-encoded to linear (IEC 61966-2-1).
pub fn srgb_to_linear(x: f32) -> f32 {
    if x <= 0.04045 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

fn read_pfm(path: &Path) -> Result<Image> {
    pfm_from_bytes(&std::fs::read(path)?)
}

/// A colour PFM's pixels (Row 0 the top, as every `Image`). The size comes from the file, so it
/// is checked against the bytes there before any pixel is read or allocated.
pub fn pfm_from_bytes(data: &[u8]) -> Result<Image> {
    // Header: three whitespace-separated tokens after the magic, then one whitespace byte.
    let mut fields = Vec::new();
    let mut pos = 0;
    while fields.len() < 4 {
        while pos < data.len() && data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < data.len() && !data[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            bail!("truncated PFM header");
        }
        fields.push(String::from_utf8_lossy(&data[start..pos]).into_owned());
    }
    pos += 1;
    if fields[0] != "PF" {
        bail!("not a colour PFM (magic {:?})", fields[0]);
    }
    let width: u32 = fields[1].parse().context("PFM width")?;
    let height: u32 = fields[2].parse().context("PFM height")?;
    let scale: f32 = fields[3].parse().context("PFM scale")?;
    if width == 0 || height == 0 {
        bail!("PFM size {width}x{height} holds no pixels");
    }
    let little = scale < 0.0;
    // Three float32 channels per pixel; a damaged size overflows here rather than in an index.
    let bytes = (width as usize).checked_mul(height as usize).and_then(|n| n.checked_mul(3 * 4));
    let body = bytes.and_then(|n| data.get(pos..pos.checked_add(n)?)).ok_or_else(|| {
        anyhow!(
            "truncated PFM data: {width}x{height} pixels need {} bytes after the header, the file has {}",
            width as u128 * height as u128 * 12,
            data.len().saturating_sub(pos)
        )
    })?;
    let floats: Vec<f32> = body
        .chunks_exact(4)
        .map(|b| {
            let a = [b[0], b[1], b[2], b[3]];
            if little {
                f32::from_le_bytes(a)
            } else {
                f32::from_be_bytes(a)
            }
        })
        .collect();
    let mut image = Image::new(width, height);
    for y in 0..height as usize {
        let src_row = height as usize - 1 - y;
        for x in 0..width as usize {
            let i = (src_row * width as usize + x) * 3;
            image.pixels[y * width as usize + x] = [floats[i], floats[i + 1], floats[i + 2]];
        }
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pfm(header: &str, floats: &[f32]) -> Vec<u8> {
        let mut out = header.as_bytes().to_vec();
        out.extend(floats.iter().flat_map(|f| f.to_le_bytes()));
        out
    }

    #[test]
    fn a_pfm_reads_bottom_row_last_and_its_damage_is_an_error() {
        // 1x2: the bottom row is stored first.
        let img = pfm_from_bytes(&pfm("PF\n1 2\n-1.0\n", &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0])).unwrap();
        assert_eq!(img.pixels, vec![[4.0, 5.0, 6.0], [1.0, 2.0, 3.0]]);
        let err = |bytes: &[u8]| format!("{:#}", pfm_from_bytes(bytes).unwrap_err());
        assert!(err(&pfm("PF\n1 2\n-1.0\n", &[1.0; 5])).contains("truncated PFM data"));
        // A size whose byte count overflows: an error, not an overflow or an allocation.
        let e = err(&pfm("PF\n4294967295 4294967295\n-1.0\n", &[1.0; 3]));
        assert!(e.contains("4294967295x4294967295") && e.contains("truncated"), "{e}");
        assert!(err(&pfm("PF\n0 4294967295\n-1.0\n", &[])).contains("no pixels"));
        assert!(err(b"PF\n1 1").contains("truncated PFM header"));
        assert!(err(&pfm("Pf\n1 1\n-1.0\n", &[1.0])).contains("not a colour PFM"));
    }
}
