//! Load a scene file, choosing the loader by extension.

use std::path::Path;

use super::{gltf, lab_yaml, obj, Scene};
use crate::error::InputError;

/// Loads `.obj` (Wavefront OBJ + MTL), `.yaml`/`.yml` (the lab scene format) or `.gltf`/`.glb`
/// (glTF 2.0).
pub fn load_scene(path: &Path) -> anyhow::Result<Scene> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("obj") => obj::load_obj(path),
        Some("yaml" | "yml") => lab_yaml::load_lab_yaml(path),
        Some("gltf" | "glb") => gltf::load_gltf(path),
        other => {
            let found = other.map_or("no extension".to_string(), |e| format!("extension .{e}"));
            let msg = format!("unsupported scene file ({found}); supported: .obj, .yaml, .yml, .gltf, .glb");
            Err(InputError::new(path, None, msg).into())
        }
    }
}
