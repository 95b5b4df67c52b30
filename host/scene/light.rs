//! Lights that are not triangles. Emissive triangles (MTL Ke, lab Emission, lab Area) are
//! geometry with an emitting material instead.

use glam::Vec3;

/// A light, in the lab format's terms.
///
/// How strong each is, as the Whitted integrator reads it (the lab renderer's convention for
/// point and directional lights, and the physically based one divided by pi for the others, so
/// that a Lambert surface lit by an emitter matches physically based direct lighting):
/// - `Point`: `intensity / d^2`.
/// - `Directional`: `intensity`, from `direction` (which points toward the light).
/// - `Spot`: a sphere of radius `radius` at `position` whose emission faces `direction`:
///   the lab renderer's estimator, `intensity * 4 pi r^2 * max(0, cos) / d^2`, divided by pi.
///
/// How the path tracer reads them (physically based; a Lambert surface reflects Kd / pi of the
/// irradiance E, so its radiance is Kd E / pi: pi times darker than Whitted's Kd E for point
/// and directional lights, the same for emitters):
/// - `Point`: radiant intensity I = `intensity` (W/sr) in every direction; E = I cos / d^2.
/// - `Directional`: irradiance E = `intensity` on a surface facing `direction`; E cos otherwise.
/// - `Spot`: radiant intensity `intensity * 4 pi r^2 * max(0, cos)` (the lab estimator's
///   numerator, cos measured from `direction`); E = that cos_surface / d^2.
/// - Emissive triangles: radiance Ke from the front face, sampled by area.
/// All are picked for light sampling in proportion to their power (`prepare::light_table`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    Point { position: Vec3, intensity: Vec3 },
    Directional { direction: Vec3, intensity: Vec3 },
    Spot { position: Vec3, direction: Vec3, intensity: Vec3, radius: f32 },
}
