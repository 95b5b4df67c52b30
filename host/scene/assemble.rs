//! The steps both loaders (`obj`, `lab_yaml`) share: adding triangles (dropping degenerate
//! ones), finishing a scene (camera, textures) and the default light of an unlit scene.

use std::path::Path;

use glam::Vec3;

use super::{Camera, Light, Scene, Triangle};
use crate::error::InputError;

/// Adds triangles to the scene in order, dropping zero-area ones (counted in `stats`) and
/// shading normals that cannot be normalised (zero, NaN, inf) for that triangle.
pub fn push_triangles(scene: &mut Scene, triangles: impl IntoIterator<Item = Triangle>) {
    for mut t in triangles {
        let len = t.cross().length();
        // NaN fails both tests: a triangle with a non-finite vertex is unusable too.
        let has_area = len > 0.0 && len.is_finite();
        if !has_area {
            scene.stats.dropped_degenerate += 1;
            continue;
        }
        if let Some(n) = t.n {
            let n = n.map(|v| v.normalize_or_zero());
            t.n = if n.iter().all(|v| *v != Vec3::ZERO && v.is_finite()) { Some(n) } else { None };
        }
        scene.triangles.push(t);
    }
}

/// What both loaders do last: refuse an empty scene, frame a camera if the file has none, and
/// decode the materials' textures.
pub fn finish_scene(scene: &mut Scene, file: &Path, camera: Option<Camera>) -> anyhow::Result<()> {
    if scene.triangles.is_empty() {
        let dropped = scene.stats.dropped_degenerate;
        let msg = if dropped > 0 {
            format!("the scene has no triangles (all {dropped} were degenerate)")
        } else {
            "the scene has no triangles".to_string()
        };
        return Err(InputError::new(file, None, msg).into());
    }
    scene.camera = camera.unwrap_or_else(|| Camera::framing(&scene.bounds()));
    // Textures are decoded once per file, here, so that both loaders share the rule.
    super::material_textures::load_material_textures(scene, file, &mut super::texture::TextureCache::default())?;
    Ok(())
}

/// The light a scene without any gets: directional, from over the camera's shoulder (up and
/// behind the eye), so that what the camera sees is lit from the front.
pub fn default_light(camera: &Camera) -> Light {
    let back = (camera.eye - camera.target).normalize_or_zero();
    let direction = (camera.up.normalize_or_zero() + back).normalize_or_zero();
    let direction = if direction == Vec3::ZERO { Vec3::Y } else { direction };
    Light::Directional { direction, intensity: Vec3::ONE }
}
