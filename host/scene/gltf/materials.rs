//! glTF materials onto [`Material`], per the glTF 2.0 specification's Appendix B (BRDF
//! implementation) and section 3.9 (Materials).
//!
//! - `pbrMetallicRoughness`: `baseColorFactor` rgb -> `diffuse`, its alpha -> `dissolve`,
//!   `baseColorTexture` -> `diffuse_texture`; `metallicFactor`, `roughnessFactor` and
//!   `metallicRoughnessTexture` -> `metallic_roughness`.
//! - `emissiveFactor` times `KHR_materials_emissive_strength` -> `emission`, `emissiveTexture`
//!   -> `emission_texture`; `normalTexture` and its `scale` -> `normal_texture`, `normal_scale`.
//! - `occlusionTexture` is ignored: ambient occlusion is a rasteriser's stand-in for the
//!   indirect shadowing a path tracer computes.
//! - `alphaMode`: OPAQUE ignores alpha; MASK cuts out where alpha < `alphaCutoff` (default
//!   0.5); BLEND sets `alpha_blend`. Both take alpha from the base colour texture.
//! - `doubleSided` is recorded.
//!
//! Until the GPU reads `metallic_roughness`, the Kd/Ks/Ns fields say "Lambert with the base
//! colour" (Ks = 0, illum 2), which is what a metallic-roughness surface looks like under
//! diffuse light when it is not metallic; metals then render too dull, never wrong in hue.
//! A primitive without a material gets the spec's default material (section 3.9.6: base colour
//! white, metallic 1, roughness 1).
//!
//! Texture coordinates: only set 0 is read. A texture on another set is used with set 0 and
//! warned about. `KHR_texture_transform` is applied to the UVs at load (they are per triangle,
//! so one transform per material): the base colour texture's, or the first other texture's;
//! textures of one material that disagree get a warning.

use std::path::Path;

use glam::{Mat3, Vec2, Vec3};

use super::images::Images;
use crate::error::InputError;
use crate::scene::{Material, MetallicRoughness, Scene};

/// The loader's materials: `Scene::materials` index of each glTF material, its UV transform,
/// and the default material's index.
pub struct MaterialTable {
    /// UV transform (KHR_texture_transform, in glTF UV space) of `Scene::materials[i]`.
    pub uv_transform: Vec<Option<Mat3>>,
    /// The index used for primitives without a material (only valid if some have none).
    pub default: u32,
}

impl MaterialTable {
    /// The `Scene::materials` index of a primitive's material.
    pub fn index(&self, material: Option<usize>) -> u32 {
        material.map_or(self.default, |i| i as u32)
    }
}

/// Converts every material of the document into `scene.materials` (in order, so indices agree),
/// decoding their textures, and adds the default material if some primitive has none.
pub fn convert(document: &::gltf::Document, file: &Path, images: &mut Images, scene: &mut Scene) -> anyhow::Result<MaterialTable> {
    let mut uv_transform = Vec::new();
    for m in document.materials() {
        let (material, uv) = convert_one(&m, file, images, scene)?;
        scene.materials.push(material);
        uv_transform.push(uv);
    }
    let default = scene.materials.len() as u32;
    let untextured = document.meshes().flat_map(|m| m.primitives()).any(|p| p.material().index().is_none());
    if untextured {
        scene.materials.push(default_material());
        uv_transform.push(None);
    }
    Ok(MaterialTable { uv_transform, default })
}

/// glTF 2.0 section 3.9.6, "Default material".
fn default_material() -> Material {
    Material {
        name: "glTF default".to_string(),
        diffuse: Vec3::ONE,
        specular: Vec3::ZERO,
        illum: 2,
        metallic_roughness: Some(MetallicRoughness { metallic: 1.0, roughness: 1.0, texture: None }),
        alpha_cutoff: 0.5,
        double_sided: false,
        ..Material::default()
    }
}

/// One texture reference: the texture, its texCoord set and its KHR_texture_transform.
struct TexRef<'a> {
    texture: ::gltf::Texture<'a>,
    tex_coord: u32,
    transform: Option<Mat3>,
    loc: String,
}

impl<'a> TexRef<'a> {
    fn from_info(info: ::gltf::texture::Info<'a>, loc: String) -> Self {
        let t = info.texture_transform();
        let tex_coord = t.as_ref().and_then(|t| t.tex_coord()).unwrap_or(info.tex_coord());
        Self { texture: info.texture(), tex_coord, transform: t.map(|t| uv_matrix(t.offset(), t.rotation(), t.scale())), loc }
    }
}

/// The KHR_texture_transform matrix, translation * rotation * scale, as the extension's
/// README writes it in GLSL (column-major `mat3`s): uv' = (M * vec3(uv, 1)).xy.
pub fn uv_matrix(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Mat3 {
    let (s, c) = rotation.sin_cos();
    let translation = Mat3::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, offset[0], offset[1], 1.0]);
    let rotation = Mat3::from_cols_array(&[c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0]);
    let scale = Mat3::from_cols_array(&[scale[0], 0.0, 0.0, 0.0, scale[1], 0.0, 0.0, 0.0, 1.0]);
    translation * rotation * scale
}

/// Applies a UV transform to one coordinate (glTF UV space, v down).
pub fn transform_uv(m: &Mat3, uv: Vec2) -> Vec2 {
    m.transform_point2(uv)
}

fn convert_one(m: &::gltf::Material, file: &Path, images: &mut Images, scene: &mut Scene) -> anyhow::Result<(Material, Option<Mat3>)> {
    let index = m.index().unwrap_or(0);
    let loc = format!("materials[{index}]");
    let pbr = m.pbr_metallic_roughness();
    let base = pbr.base_color_factor();
    let mut refs: Vec<(&str, TexRef)> = Vec::new();
    if let Some(t) = pbr.base_color_texture() {
        refs.push(("base", TexRef::from_info(t, format!("{loc}.pbrMetallicRoughness.baseColorTexture"))));
    }
    if let Some(t) = pbr.metallic_roughness_texture() {
        refs.push(("mr", TexRef::from_info(t, format!("{loc}.pbrMetallicRoughness.metallicRoughnessTexture"))));
    }
    if let Some(t) = m.emissive_texture() {
        refs.push(("emission", TexRef::from_info(t, format!("{loc}.emissiveTexture"))));
    }
    if let Some(n) = m.normal_texture() {
        // NormalTextureInfo is no textureInfo in the crate; its transform is read from JSON.
        let transform = n.extension_value("KHR_texture_transform").map(json_uv_matrix);
        let tex_coord = n.extension_value("KHR_texture_transform").and_then(|v| v.get("texCoord")).and_then(|v| v.as_u64()).map_or(n.tex_coord(), |c| c as u32);
        refs.push(("normal", TexRef { texture: n.texture(), tex_coord, transform, loc: format!("{loc}.normalTexture") }));
    }

    let mut uv: Option<Mat3> = None;
    let mut uv_from: Option<String> = None;
    let mut out = Material {
        name: m.name().map_or_else(|| loc.clone(), str::to_string),
        diffuse: Vec3::new(base[0], base[1], base[2]),
        dissolve: base[3],
        specular: Vec3::ZERO,
        shininess: 1.0,
        illum: 2,
        emission: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        metallic_roughness: Some(MetallicRoughness { metallic: pbr.metallic_factor(), roughness: pbr.roughness_factor(), texture: None }),
        alpha_cutoff: m.alpha_cutoff().unwrap_or(0.5),
        double_sided: m.double_sided(),
        ..Material::default()
    };
    for (slot, r) in &refs {
        if r.tex_coord != 0 {
            let msg = format!("texture on texCoord set {}; vkrt reads set 0 only, which is used instead", r.tex_coord);
            scene.stats.warn(InputError::new(file, Some(r.loc.clone()), msg).to_string());
        }
        let transform = r.transform.unwrap_or(Mat3::IDENTITY);
        match (&uv, &uv_from) {
            (None, None) if r.transform.is_some() => {
                uv = r.transform;
                uv_from = Some(r.loc.clone());
            }
            (None, None) => uv_from = Some(r.loc.clone()),
            _ if uv.unwrap_or(Mat3::IDENTITY).abs_diff_eq(transform, 1e-6) => {}
            (_, from) => {
                let from = from.clone().unwrap_or_default();
                let msg = format!("KHR_texture_transform differs from that of {from}; vkrt keeps one UV transform per material, {from}'s");
                scene.stats.warn(InputError::new(file, Some(r.loc.clone()), msg).to_string());
            }
        }
        let t = images.texture(scene, &r.texture, &r.loc)?;
        match *slot {
            "base" => out.diffuse_texture = Some(t),
            "mr" => {
                if let Some(mr) = &mut out.metallic_roughness {
                    mr.texture = Some(t);
                }
            }
            "emission" => out.emission_texture = Some(t),
            _ => out.normal_texture = Some(t),
        }
    }
    if let Some(n) = m.normal_texture() {
        out.normal_scale = n.scale();
    }
    match m.alpha_mode() {
        ::gltf::material::AlphaMode::Opaque => {
            // Section 3.9.4: "The rendered output is fully opaque and any alpha value is ignored."
            out.dissolve = 1.0;
        }
        ::gltf::material::AlphaMode::Mask => out.alpha_texture = out.diffuse_texture,
        ::gltf::material::AlphaMode::Blend => {
            out.alpha_blend = true;
            out.alpha_texture = out.diffuse_texture;
        }
    }
    Ok((out, uv))
}

/// A KHR_texture_transform object read from raw JSON (for `normalTexture`).
fn json_uv_matrix(v: &::gltf::json::Value) -> Mat3 {
    let pair = |key: &str, default: [f32; 2]| -> [f32; 2] {
        v.get(key).and_then(|a| a.as_array()).and_then(|a| Some([a.first()?.as_f64()? as f32, a.get(1)?.as_f64()? as f32])).unwrap_or(default)
    };
    let rotation = v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0) as f32;
    uv_matrix(pair("offset", [0.0, 0.0]), rotation, pair("scale", [1.0, 1.0]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_transform_offsets_scales_then_rotates() {
        let m = uv_matrix([0.5, 0.25], 0.0, [2.0, 3.0]);
        assert!(transform_uv(&m, Vec2::new(1.0, 1.0)).abs_diff_eq(Vec2::new(2.5, 3.25), 1e-6));
        // A quarter turn maps u to v: column 0 of the README's rotation is (cos, sin).
        let r = uv_matrix([0.0, 0.0], std::f32::consts::FRAC_PI_2, [1.0, 1.0]);
        assert!(transform_uv(&r, Vec2::new(1.0, 0.0)).abs_diff_eq(Vec2::new(0.0, 1.0), 1e-6));
    }
}
