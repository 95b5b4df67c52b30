//! Decodes the textures a scene's materials name, and decides which materials are cut out.
//! Both loaders call this last (`assemble::finish_scene`), so OBJ and lab scenes follow one rule.

use super::texture::TextureCache;
use super::Scene;
use crate::error::InputError;
use anyhow::{Context as _, Result};
use std::path::Path;

/// Loads every `diffuse_map`, `alpha_map` and `normal_map` into `scene.textures` and sets the materials'
/// texture indices. A missing or undecodable diffuse map is an error naming the file and the
/// material (a silently untextured render is worse than a clear message). A missing `map_d` is
/// only a warning: White Oak's MTL names `*_A.png` files that were never shipped, and the
/// diffuse texture's own alpha channel holds the same mask, so that is used instead.
pub fn load_material_textures(scene: &mut Scene, file: &Path, cache: &mut TextureCache) -> Result<()> {
    for i in 0..scene.materials.len() {
        let m = &scene.materials[i];
        let name = m.name.clone();
        let (diffuse_map, alpha_map) = (m.diffuse_map.clone(), m.alpha_map.clone());
        if diffuse_map.is_none() && alpha_map.is_none() && m.normal_map.is_none() {
            // Nothing to load; a loader that decodes its own textures (glTF) has set the
            // indices already, and they stay.
            continue;
        }
        let diffuse = match &diffuse_map {
            Some(p) => {
                let d = cache.get(&mut scene.textures, p, false).with_context(|| format!("{}: texture of material '{name}'", file.display()))?;
                scene.stats.read_input(p);
                Some(d)
            }
            None => None,
        };
        let mut alpha = None;
        if let Some(p) = &alpha_map {
            if p.is_file() {
                let a = cache.get(&mut scene.textures, p, true).with_context(|| format!("{}: alpha map of material '{name}'", file.display()))?;
                scene.stats.read_input(p);
                alpha = Some(a);
            } else {
                let msg = format!(
                    "material '{name}': alpha map {} not found; {}",
                    p.display(),
                    if diffuse.is_some() { "using the diffuse texture's alpha" } else { "the surface is opaque" }
                );
                scene.stats.warn(InputError::new(file, None, msg).to_string());
            }
        }
        let alpha = alpha.or(diffuse).filter(|&a| scene.textures[a as usize].has_cutout());
        let normal = match scene.materials[i].normal_map.clone() {
            // Linear, not sRGB: texture.glsl decodes nothing when asked for linear texels.
            Some(p) => {
                let n = cache.get(&mut scene.textures, &p, false).with_context(|| format!("{}: normal map of material '{name}'", file.display()))?;
                scene.stats.read_input(&p);
                Some(n)
            }
            None => None,
        };
        let m = &mut scene.materials[i];
        m.diffuse_texture = diffuse;
        m.alpha_texture = alpha;
        // A loader that sets the index itself (glTF) keeps it.
        if normal.is_some() {
            m.normal_texture = normal;
        }
    }
    Ok(())
}
