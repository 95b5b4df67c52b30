//! `KHR_lights_punctual` lights (the extension's README, "Light Types" and "Units"), placed by
//! their node: a light sits at the node's origin and shines down the node's local -Z.
//!
//! Units: point and spot `intensity` is luminous intensity in candela, directional `intensity`
//! illuminance in lux. vkrt renders radiometric RGB without a luminous-efficacy factor, so
//! candela are read as W/sr (the path tracer's radiant intensity of `Light::Point` and
//! `Light::Cone`) and lux as W/m² (the irradiance of `Light::Directional`), each times the
//! light's linear `color`: a file's relative light levels are kept, and the exposure is the
//! viewer's. `range` is ignored: the spec lets a renderer treat it as a hint, and inverse-square
//! falloff holds within it.

use glam::{Mat4, Vec3};

use crate::scene::Light;

/// The light of a node with world transform `world`.
pub fn light(light: &::gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    let intensity = Vec3::from(light.color()) * light.intensity();
    let position = world.transform_point3(Vec3::ZERO);
    let shines = world.transform_vector3(-Vec3::Z).normalize_or_zero();
    match light.kind() {
        ::gltf::khr_lights_punctual::Kind::Point => Light::Point { position, intensity },
        // `Light::Directional::direction` points toward the light: the node's +Z.
        ::gltf::khr_lights_punctual::Kind::Directional => Light::Directional { direction: -shines, intensity },
        ::gltf::khr_lights_punctual::Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            Light::Cone { position, direction: shines, intensity, cos_inner: inner_cone_angle.cos(), cos_outer: outer_cone_angle.cos() }
        }
    }
}
