//! Environment maps: an equirectangular (latitude-longitude) image of the radiance arriving from
//! every direction (`vkrt render --envmap FILE`), Radiance `.hdr` or OpenEXR.
//!
//! The convention is Mitsuba 3's `envmap` emitter with an identity transform, so that a scene
//! lit by the same file renders alike in both: a direction d (y up) looks up
//! u = atan2(d.x, -d.z) / 2 pi (wrapped into [0, 1)) and v = acos(d.y) / pi, with v = 0 the
//! image's top row. Within the image, like Mitsuba's `eval_spectrum`, the texels of a row sit at
//! u = (i + 0.5) / W and wrap around, while the rows sit at v = j / (H - 1), the first and last
//! on the poles; radiance is bilinear between them. `--envmap-rotate DEG` turns the map by DEG
//! about +y (Mitsuba's `to_world` rotation about y).

use crate::error::InputError;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

/// A decoded environment map: linear RGB radiance, row 0 the top row (v = 0, straight up).
#[derive(Debug, Clone, PartialEq)]
pub struct EnvMap {
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

impl EnvMap {
    /// Reads a Radiance `.hdr` or OpenEXR file. Errors name the file: one that cannot be read
    /// or decoded, an image smaller than 2 x 2 (a row on each pole is needed), negative or
    /// non-finite radiance.
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let err = |msg: String| InputError::new(path, None, msg);
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("hdr" | "exr")) {
            return Err(err("an environment map must be a Radiance .hdr or OpenEXR .exr file".into()).into());
        }
        // Not opened unless it is a regular file: a FIFO would block the open (input_file).
        super::input_file::regular_file(path).map_err(err)?;
        let img = image::ImageReader::open(path)
            .map_err(|e| err(format!("cannot read the environment map: {e}")))?
            .with_guessed_format()
            .map_err(|e| err(format!("cannot read the environment map: {e}")))?
            .decode()
            .map_err(|e| err(format!("cannot decode the environment map: {e}")))?
            .into_rgb32f();
        let (width, height) = img.dimensions();
        let texels: Vec<[f32; 3]> = img.pixels().map(|p| p.0).collect();
        Self::from_texels(path, width, height, texels)
    }

    /// A map from `width * height` texels, top row first (for generated maps and tests).
    pub fn from_texels(path: impl Into<PathBuf>, width: u32, height: u32, texels: Vec<[f32; 3]>) -> anyhow::Result<Self> {
        let path = path.into();
        let err = |msg: String| InputError::new(&path, None, msg);
        if width < 2 || height < 2 || texels.len() != width as usize * height as usize {
            return Err(err(format!("an environment map must be at least 2x2 texels; this one is {width}x{height}")).into());
        }
        if let Some(i) = texels.iter().position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0)) {
            let (x, y) = (i as u32 % width, i as u32 / width);
            return Err(err(format!("texel ({x}, {y}) is {:?}: radiance must be finite and not negative", texels[i])).into());
        }
        Ok(Self { path, width, height, texels })
    }

    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        Vec3::from(self.texels[(y * self.width + x) as usize])
    }

    /// The radiance the map gives along local direction `d` (unit; before any rotation), as
    /// the shaders look it up (`env_radiance` in shaders/include/environment.glsl).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (x, y) = grid_position(direction_to_uv(d), self.width, self.height);
        let (i, j) = ((x.floor() as u32).min(self.width - 1), (y.floor() as u32).min(self.height - 2));
        let (fx, fy) = (x - i as f32, y - j as f32);
        let i1 = (i + 1) % self.width;
        let top = self.texel(i, j).lerp(self.texel(i1, j), fx);
        let bottom = self.texel(i, j + 1).lerp(self.texel(i1, j + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// Mitsuba's latitude-longitude coordinates of unit direction `d`: u in [0, 1), v in [0, 1].
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) / (2.0 * PI);
    Vec2::new(u - u.floor(), d.y.clamp(-1.0, 1.0).acos() / PI)
}

/// The direction of latitude-longitude coordinates (u, v): the inverse of [`direction_to_uv`].
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (theta, phi) = (uv.y * PI, uv.x * 2.0 * PI);
    Vec3::new(phi.sin() * theta.sin(), theta.cos(), -phi.cos() * theta.sin())
}

/// Where (u, v) falls among the texels, in texel units: x in [0, W) measured from column 0's
/// centre (wrapping), y in [0, H - 1] from row 0 (the top pole).
pub fn grid_position(uv: Vec2, width: u32, height: u32) -> (f32, f32) {
    let x = uv.x * width as f32 - 0.5;
    let x = x - (x / width as f32).floor() * width as f32;
    (x.min(width as f32 - f32::EPSILON * width as f32), uv.y * (height - 1) as f32)
}

/// Rotation of the map about +y by `degrees`: the world direction of local direction `d`.
pub fn rotate_y(d: Vec3, degrees: f32) -> Vec3 {
    let (s, c) = degrees.to_radians().sin_cos();
    Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uv_and_direction_are_inverses_and_follow_mitsuba() {
        // Straight up is the top row, -z the middle of the image's width (u = 0 at -z... wrapped
        // to 0), +x a quarter of the way along.
        assert!(direction_to_uv(Vec3::Y).y.abs() < 1e-6);
        assert!((direction_to_uv(Vec3::NEG_Y).y - 1.0).abs() < 1e-6);
        assert!(direction_to_uv(Vec3::NEG_Z).x.abs() < 1e-6);
        assert!((direction_to_uv(Vec3::X).x - 0.25).abs() < 1e-6);
        assert!((direction_to_uv(Vec3::Z).x - 0.5).abs() < 1e-6);
        for k in 0..50 {
            let uv = Vec2::new((k as f32 * 0.137).fract(), 0.01 + 0.98 * (k as f32 * 0.291).fract());
            let back = direction_to_uv(uv_to_direction(uv));
            assert!((back - uv).abs().max_element() < 1e-4, "{uv} -> {back}");
        }
        let d = Vec3::new(0.3, 0.4, -0.866).normalize();
        assert!((rotate_y(rotate_y(d, 30.0), -30.0) - d).length() < 1e-6);
        assert!((rotate_y(Vec3::NEG_Z, 90.0) - Vec3::NEG_X).length() < 1e-6);
    }

    #[test]
    fn lookups_hit_texel_centres_and_rows_on_the_poles() {
        let (w, h) = (8, 5);
        let texels = (0..w * h).map(|i| [i as f32, 0.0, 0.0]).collect();
        let map = EnvMap::from_texels("t.exr", w, h, texels).unwrap();
        // Column 3's centre, row 2 (the equator).
        let d = uv_to_direction(Vec2::new(3.5 / w as f32, 2.0 / (h - 1) as f32));
        assert!((map.radiance(d).x - (2 * w + 3) as f32).abs() < 1e-3, "{}", map.radiance(d));
        // The top pole is row 0.
        assert!(map.radiance(Vec3::Y).x < w as f32);
        // Between the last column and the first: the lookup wraps.
        let d = uv_to_direction(Vec2::new(0.0, 0.5));
        let want = 0.5 * ((2 * w) as f32 + (2 * w + w - 1) as f32);
        assert!((map.radiance(d).x - want).abs() < 1e-3, "{} vs {want}", map.radiance(d));
    }

    #[test]
    fn bad_maps_are_errors_naming_the_file() {
        let e = EnvMap::from_texels("sky.exr", 1, 1, vec![[1.0; 3]]).unwrap_err();
        assert!(format!("{e:#}").contains("sky.exr") && format!("{e:#}").contains("2x2"), "{e:#}");
        let e = EnvMap::from_texels("sky.exr", 2, 2, vec![[1.0; 3], [f32::NAN, 0.0, 0.0], [1.0; 3], [1.0; 3]]).unwrap_err();
        assert!(format!("{e:#}").contains("(1, 0)"), "{e:#}");
        let e = EnvMap::load(Path::new("/nonexistent/sky.png")).unwrap_err();
        assert!(format!("{e:#}").contains(".hdr"), "{e:#}");
    }
}
