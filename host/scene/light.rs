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
/// - `Cone`: as `Point`, times the cone falloff `f` (below): `intensity * f / d^2`.
///
/// How the path tracer reads them (physically based; a Lambert surface reflects Kd / pi of the
/// irradiance E, so its radiance is Kd E / pi: pi times darker than Whitted's Kd E for point
/// and directional lights, the same for emitters):
/// - `Point`: radiant intensity I = `intensity` (W/sr) in every direction; E = I cos / d^2.
/// - `Directional`: irradiance E = `intensity` on a surface facing `direction`; E cos otherwise.
/// - `Spot`: radiant intensity `intensity * 4 pi r^2 * max(0, cos)` (the lab estimator's
///   numerator, cos measured from `direction`); E = that cos_surface / d^2.
/// - `Cone`: radiant intensity `intensity * f(cos)` (W/sr), cos measured from `direction`, the
///   way the light shines; E = that cos_surface / d^2. `f` is KHR_lights_punctual's spot
///   falloff (the extension's README, "Inner and Outer Cone Angles"): 0 outside the outer cone,
///   1 inside the inner one, and between them ((cos - cos_outer) / (cos_inner - cos_outer))^2,
///   the square of a ramp linear in the cosine.
/// - Emissive triangles: radiance Ke from the front face, sampled by area.
///
/// All are picked for light sampling in proportion to their power (`prepare::light_table`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    Point {
        position: Vec3,
        intensity: Vec3,
    },
    Directional {
        direction: Vec3,
        intensity: Vec3,
    },
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        radius: f32,
    },
    /// A glTF spot light: a point light limited to a cone around `direction` (normalised, the
    /// way it shines), full inside the inner angle (cosine `cos_inner`), dark outside the outer
    /// one (`cos_outer` < `cos_inner`).
    Cone {
        position: Vec3,
        direction: Vec3,
        intensity: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
}

impl Light {
    /// The cone falloff `f` of [`Light::Cone`] at cosine `cos` from its axis (KHR_lights_punctual
    /// README: `saturate(cd * scale + offset)^2`, scale = 1 / max(0.001, cos_inner - cos_outer),
    /// offset = -cos_outer * scale). Mirrored in `shaders/include/lights.glsl` (`cone_falloff`).
    pub fn cone_falloff(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
        let scale = 1.0 / (cos_inner - cos_outer).max(0.001);
        let a = ((cos - cos_outer) * scale).clamp(0.0, 1.0);
        a * a
    }
}
