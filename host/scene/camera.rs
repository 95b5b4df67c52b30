//! The camera: a pinhole, or a thin lens for depth of field, with the convention the reference
//! images use.

use glam::{Vec2, Vec3};

/// A thin lens (Pharr, Jakob & Humphreys, PBRT 4th ed., section 5.2.3): rays start on a disc of
/// `aperture_radius` around the eye, in the plane of the camera's right and up axes, and pass
/// through the point where the pixel's pinhole ray meets the plane of focus, `focus_distance`
/// in front of the eye (perpendicular to the view direction), so that plane stays sharp.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Lens {
    /// Radius of the aperture, in scene units; 0 is a pinhole (`--aperture`).
    pub aperture_radius: f32,
    /// Distance from the eye to the plane in focus; 0 means the distance to the target
    /// (`--focus-distance`).
    pub focus_distance: f32,
}

impl Lens {
    /// The pinhole: every ray starts at the eye.
    pub const PINHOLE: Lens = Lens { aperture_radius: 0.0, focus_distance: 0.0 };
}

/// A camera: a pinhole unless `lens` has an aperture.
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
    pub lens: Lens,
}

impl Default for Camera {
    fn default() -> Self {
        Self { eye: Vec3::new(0.0, 0.0, 3.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 45.0, lens: Lens::PINHOLE }
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
    /// The thin lens's aperture radius (0: a pinhole) and the distance to the plane in focus
    /// (resolved: never 0 when the aperture is not).
    pub aperture_radius: f32,
    pub focus_distance: f32,
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
        let Lens { aperture_radius, focus_distance } = self.lens;
        if !(aperture_radius >= 0.0 && aperture_radius.is_finite()) {
            anyhow::bail!("aperture radius {aperture_radius} is not a finite number >= 0");
        }
        if !(focus_distance >= 0.0 && focus_distance.is_finite()) {
            anyhow::bail!("focus distance {focus_distance} is not a finite number >= 0");
        }
        let focus_distance = if focus_distance > 0.0 { focus_distance } else { (self.target - self.eye).length() };
        Ok(CameraFrame { origin: self.eye, forward, right, up, tan_half_fov_y: (self.fov_y_deg.to_radians() * 0.5).tan(), aperture_radius, focus_distance })
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
        Self { eye: center + Vec3::Z * distance, target: center, up: Vec3::Y, fov_y_deg, lens: Lens::PINHOLE }
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

    /// The primary ray (origin, unit direction) through image position (x, y), starting at lens
    /// sample `u` in [0, 1)^2 (mapped onto the aperture by `concentric_disk`). With no
    /// aperture it is the pinhole ray, whatever `u`. Mirrored in `shaders/include/camera.glsl`.
    pub fn ray(&self, x: f32, y: f32, width: u32, height: u32, u: Vec2) -> (Vec3, Vec3) {
        let dir = self.ray_direction(x, y, width, height);
        if self.aperture_radius <= 0.0 {
            return (self.origin, dir);
        }
        let focus = self.origin + dir * (self.focus_distance / dir.dot(self.forward));
        let d = concentric_disk(u) * self.aperture_radius;
        let origin = self.origin + d.x * self.right + d.y * self.up;
        (origin, (focus - origin).normalize())
    }
}

/// Maps the unit square onto the unit disc keeping areas and strata (Shirley & Chiu 1997, "A
/// low distortion map between disk and square"). Mirrored in `shaders/include/sampling.glsl`.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let quarter_pi = std::f32::consts::FRAC_PI_4;
    let (r, theta) = if o.x.abs() > o.y.abs() { (o.x, quarter_pi * (o.y / o.x)) } else { (o.y, 2.0 * quarter_pi - quarter_pi * (o.x / o.y)) };
    r * Vec2::new(theta.cos(), theta.sin())
}
