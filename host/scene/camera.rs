//! The pinhole camera, with the convention the reference images use.

use glam::Vec3;

/// A pinhole camera.
///
/// Convention (shared with `../shared/refs`): vertical field of view in degrees;
/// right = normalize(fwd x up), up' = right x fwd; pixel (i, j) has its centre at
/// ndc = ((i+0.5)/W*2-1) * tan(fov/2) * W/H, (1-(j+0.5)/H*2) * tan(fov/2); row 0 is the top.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self { eye: Vec3::new(0.0, 0.0, 3.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 45.0 }
    }
}

/// The orthonormal frame a camera renders with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraFrame {
    pub origin: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    /// tan(fov_y / 2).
    pub tan_half_fov_y: f32,
}

impl Camera {
    /// The camera's frame; fails for a degenerate camera (eye == target, up parallel to view).
    pub fn frame(&self) -> anyhow::Result<CameraFrame> {
        let forward = (self.target - self.eye).normalize_or_zero();
        let right = forward.cross(self.up).normalize_or_zero();
        if forward == Vec3::ZERO || right == Vec3::ZERO || !right.is_finite() {
            anyhow::bail!("degenerate camera: eye {} target {} up {}", self.eye, self.target, self.up);
        }
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            anyhow::bail!("camera field of view {} is outside (0, 180) degrees", self.fov_y_deg);
        }
        let up = right.cross(forward);
        Ok(CameraFrame {
            origin: self.eye,
            forward,
            right,
            up,
            tan_half_fov_y: (self.fov_y_deg.to_radians() * 0.5).tan(),
        })
    }

    /// A camera looking at `bounds` from the front (+z), far enough back to see all of it.
    pub fn framing(bounds: &crate::geom::Aabb) -> Self {
        let fov_y_deg: f32 = 45.0;
        if bounds.is_empty() {
            return Self::default();
        }
        let center = bounds.center();
        let radius = (0.5 * bounds.extent().length()).max(f32::MIN_POSITIVE.sqrt());
        let distance = radius / (fov_y_deg.to_radians() * 0.5).sin();
        Self { eye: center + Vec3::Z * distance, target: center, up: Vec3::Y, fov_y_deg }
    }
}

impl CameraFrame {
    /// The primary ray direction (normalised) through image position (x, y) in pixels, where
    /// (i + 0.5, j + 0.5) is the centre of pixel (i, j). Mirrored in `shaders/include/camera.glsl`.
    pub fn ray_direction(&self, x: f32, y: f32, width: u32, height: u32) -> Vec3 {
        let aspect = width as f32 / height as f32;
        let ndc_x = (x / width as f32 * 2.0 - 1.0) * self.tan_half_fov_y * aspect;
        let ndc_y = (1.0 - y / height as f32 * 2.0) * self.tan_half_fov_y;
        (self.forward + ndc_x * self.right + ndc_y * self.up).normalize()
    }
}
