//! Which glTF extensions vkrt reads, and what it does with the others (glTF 2.0 spec, section
//! 3.12: an extension in `extensionsRequired` must be supported for the asset to load; one only
//! in `extensionsUsed` may be ignored).

use std::path::Path;

use crate::error::InputError;
use crate::scene::LoadStats;

/// The extensions the loader implements.
pub const SUPPORTED_EXTENSIONS: &[&str] = &["EXT_mesh_gpu_instancing", "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"];

/// Fails on a required extension vkrt does not implement; warns once for each optional one.
pub fn check(document: &::gltf::Document, file: &Path, stats: &mut LoadStats) -> anyhow::Result<()> {
    for (i, name) in document.extensions_required().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            let msg = format!("the file requires extension {name}, which vkrt does not support (supported: {})", SUPPORTED_EXTENSIONS.join(", "));
            return Err(super::at(file, format!("extensionsRequired[{i}]"), msg));
        }
    }
    for (i, name) in document.extensions_used().enumerate() {
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            let msg = format!("optional extension {name} is not supported; the file is rendered without it");
            stats.warn(InputError::new(file, Some(format!("extensionsUsed[{i}]")), msg).to_string());
        }
    }
    Ok(())
}
