//! Decoded textures: 8-bit RGBA texels, row 0 the top row of the image file.
//!
//! The shaders read them from one texel buffer (`prepare::texture_atlas`), filter bilinearly with
//! repeat wrapping and decode sRGB there (shaders/include/texture.glsl), so the host keeps the
//! file's bytes untouched: decoding before filtering is what the lab renderer does.

use anyhow::{Context as _, Result};
use std::path::{Path, PathBuf};

/// Alpha below this (as a byte: below 0.2 * 255) is see-through: the lab renderer's rule.
pub const CUTOUT_ALPHA_BYTE: u8 = 51;

/// One decoded texture.
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    /// The file it came from (for messages), or a made-up name for generated textures.
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    /// Packed RGBA8, red in the low byte (GLSL `unpackUnorm4x8`), row-major from the top row.
    pub texels: Vec<u32>,
}

impl Texture {
    /// A texture from `width * height` RGBA byte quadruples, top row first.
    pub fn from_rgba(path: impl Into<PathBuf>, width: u32, height: u32, rgba: &[[u8; 4]]) -> Result<Self> {
        let path = path.into();
        if width == 0 || height == 0 || rgba.len() != width as usize * height as usize {
            anyhow::bail!("texture {}: {} texels do not make a {width}x{height} image", path.display(), rgba.len());
        }
        let texels = rgba.iter().map(|p| u32::from_le_bytes(*p)).collect();
        Ok(Self { path, width, height, texels })
    }

    /// Decodes a PNG, JPEG or TGA file (anything the `image` crate reads). A file without an
    /// alpha channel gets alpha 255.
    pub fn load(path: &Path) -> Result<Self> {
        let img = image::ImageReader::open(path)
            .with_context(|| format!("opening texture {}", path.display()))?
            .with_guessed_format()
            .with_context(|| format!("reading texture {}", path.display()))?
            .decode()
            .with_context(|| format!("decoding texture {}", path.display()))?
            .into_rgba8();
        let (width, height) = img.dimensions();
        let rgba: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
        Self::from_rgba(path, width, height, &rgba)
    }

    /// Decodes an image held in memory (a glTF image in a buffer view or a `data:` URI);
    /// `name` says where it came from, for messages and `Texture::path`.
    pub fn from_bytes(name: impl Into<PathBuf>, bytes: &[u8]) -> Result<Self> {
        let name = name.into();
        let img = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .with_context(|| format!("reading image {}", name.display()))?
            .decode()
            .with_context(|| format!("decoding image {}", name.display()))?
            .into_rgba8();
        let (width, height) = img.dimensions();
        let rgba: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
        Self::from_rgba(name, width, height, &rgba)
    }

    /// Loads an alpha map (MTL `map_d`): its alpha channel if it has see-through texels, else
    /// its red channel (grey-scale masks have no alpha channel).
    pub fn load_alpha_map(path: &Path) -> Result<Self> {
        let mut t = Self::load(path)?;
        if !t.has_cutout() {
            for p in &mut t.texels {
                let r = *p & 0xFF;
                *p = (*p & 0x00FF_FFFF) | (r << 24);
            }
        }
        Ok(t)
    }

    /// True if some texel is see-through. Bilinear filtering only blends texels, so a texture
    /// with none can never filter below the cut-off: its material needs no alpha test.
    pub fn has_cutout(&self) -> bool {
        self.texels.iter().any(|&t| ((t >> 24) as u8) < CUTOUT_ALPHA_BYTE)
    }

    pub fn bytes(&self) -> usize {
        self.texels.len() * 4
    }

    /// Half the size in each dimension (odd sizes round up), each texel the mean of the up to
    /// 2x2 texels it covers. Used only when the textures do not fit the device.
    pub fn downsampled(&self) -> Self {
        let (w, h) = (self.width.div_ceil(2), self.height.div_ceil(2));
        let mut texels = Vec::with_capacity(w as usize * h as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 4];
                let mut n = 0;
                for (sx, sy) in [(2 * x, 2 * y), (2 * x + 1, 2 * y), (2 * x, 2 * y + 1), (2 * x + 1, 2 * y + 1)] {
                    if sx < self.width && sy < self.height {
                        let b = self.texels[(sy * self.width + sx) as usize].to_le_bytes();
                        for c in 0..4 {
                            sum[c] += b[c] as u32;
                        }
                        n += 1;
                    }
                }
                let avg = sum.map(|s| ((s + n / 2) / n) as u8);
                texels.push(u32::from_le_bytes(avg));
            }
        }
        Self { path: self.path.clone(), width: w, height: h, texels }
    }
}

/// The scene's textures, each file decoded once however many materials use it.
#[derive(Debug, Default)]
pub struct TextureCache {
    by_path: std::collections::HashMap<(PathBuf, bool), u32>,
}

impl TextureCache {
    /// Index of `path` in `textures`, loading it on first use (as an alpha map if `alpha`).
    pub fn get(&mut self, textures: &mut Vec<Texture>, path: &Path, alpha: bool) -> Result<u32> {
        if let Some(&i) = self.by_path.get(&(path.to_path_buf(), alpha)) {
            return Ok(i);
        }
        let t = if alpha { Texture::load_alpha_map(path)? } else { Texture::load(path)? };
        let i = textures.len() as u32;
        textures.push(t);
        self.by_path.insert((path.to_path_buf(), alpha), i);
        Ok(i)
    }
}
