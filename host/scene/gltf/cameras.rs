//! glTF cameras (spec section 3.10): a perspective camera looks down its node's local -Z with
//! +Y up, from the node's origin.

use std::path::Path;

use glam::{Mat4, Vec3};

use crate::error::InputError;
use crate::scene::{Camera, LoadStats};

/// The camera a node places, or `None` (with a warning) for an orthographic one, which vkrt's
/// pinhole camera cannot show. `yfov` (radians) becomes `fov_y_deg`; `aspectRatio` is ignored,
/// since the image size comes from the command line (`--width`, `--height`), and so are
/// `znear`/`zfar` (a ray tracer needs no clip planes).
/// Fails, naming the JSON location, on a field of view outside (0, pi) radians (the spec asks
/// for yfov > 0; 180 degrees and more cannot be a pinhole's) and on a node whose transform
/// leaves the camera no view direction or no up direction (a zero scale, say).
pub fn camera(camera: &::gltf::Camera, node: usize, world: Mat4, file: &Path, stats: &mut LoadStats) -> anyhow::Result<Option<Camera>> {
    match camera.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            let yfov = p.yfov();
            if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                let loc = format!("cameras[{}].perspective.yfov", camera.index());
                return Err(InputError::new(file, Some(loc), format!("{yfov} radians is outside (0, pi)")).into());
            }
            let eye = world.transform_point3(Vec3::ZERO);
            let forward = world.transform_vector3(-Vec3::Z).normalize_or_zero();
            let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
            if forward == Vec3::ZERO || up == Vec3::ZERO || forward.cross(up).length_squared() < 1e-12 {
                let msg = format!("the node's transform leaves camera {} no view or up direction", camera.index());
                return Err(InputError::new(file, Some(format!("nodes[{node}]")), msg).into());
            }
            Ok(Some(Camera { eye, target: eye + forward, up, fov_y_deg: yfov.to_degrees(), ..Camera::default() }))
        }
        ::gltf::camera::Projection::Orthographic(_) => {
            let msg = format!("orthographic camera {} skipped: vkrt renders perspective cameras only", camera.index());
            stats.warn(InputError::new(file, Some(format!("nodes[{node}]")), msg).to_string());
            Ok(None)
        }
    }
}
