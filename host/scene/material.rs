//! Surface materials, in the terms of Wavefront MTL (which the lab YAML maps onto).

use glam::Vec3;

/// A material. Field names follow MTL; defaults are MTL's (a plain white Lambert surface).
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// Kd: diffuse albedo, linear RGB.
    pub diffuse: Vec3,
    /// Ks: specular colour; weights the Blinn-Phong highlight and, for mirrors, the reflection.
    pub specular: Vec3,
    /// Ns: Blinn-Phong exponent.
    pub shininess: f32,
    /// Ke: emitted radiance, linear RGB (front face only).
    pub emission: Vec3,
    /// Ni: index of refraction, used by dielectrics.
    pub ior: f32,
    /// d: dissolve (1 = opaque). Recorded; cut-outs come with textures.
    pub dissolve: f32,
    /// illum: the MTL illumination model; decides mirror and dielectric behaviour.
    pub illum: u32,
    /// map_Kd / lab DiffuseMap, resolved to a path.
    pub diffuse_map: Option<std::path::PathBuf>,
    /// map_d, resolved to a path.
    pub alpha_map: Option<std::path::PathBuf>,
    /// Index into `Scene::textures` of the decoded `diffuse_map`, whose sRGB colour replaces
    /// `diffuse` (the lab renderer's rule: albedo = texel^2.2, Kd ignored). Set by
    /// `material_textures::load_material_textures`.
    pub diffuse_texture: Option<u32>,
    /// Index into `Scene::textures` of the texture whose alpha cuts the surface out: `alpha_map`,
    /// or the diffuse texture's own alpha channel. Only set when some texel is see-through.
    pub alpha_texture: Option<u32>,
    /// Alpha below this is see-through where `alpha_texture` is set (the lab renderer's 0.2 for
    /// MTL and lab materials; glTF `alphaCutoff` for `MASK`).
    pub alpha_cutoff: f32,
    /// glTF `alphaMode: BLEND`: alpha is a coverage probability (stochastic transparency in the
    /// path tracer) instead of a cut-out.
    pub alpha_blend: bool,
    /// glTF 2.0 metallic-roughness parameters (specification, Appendix B); `None` for MTL and
    /// lab materials, which keep the Kd/Ks/Ns model. With them, `diffuse` is the base colour
    /// factor (linear) and `diffuse_texture` the base colour texture it multiplies.
    pub metallic_roughness: Option<MetallicRoughness>,
    /// Tangent-space normal map (glTF `normalTexture`, MTL `norm`), index into `Scene::textures`
    /// (linear, not sRGB), and its scale (glTF `normalTexture.scale`).
    pub normal_texture: Option<u32>,
    pub normal_scale: f32,
    /// MTL `norm` / glTF `normalTexture` resolved to a path, loaded with the other textures.
    pub normal_map: Option<std::path::PathBuf>,
    /// glTF `emissiveTexture` (sRGB), multiplying `emission`.
    pub emission_texture: Option<u32>,
    /// glTF `doubleSided`. Informational: vkrt shades both sides of every surface.
    pub double_sided: bool,
}

/// The glTF 2.0 metallic-roughness material parameters besides the base colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MetallicRoughness {
    /// `metallicFactor`, in [0, 1].
    pub metallic: f32,
    /// `roughnessFactor` (perceptual roughness; GGX alpha = roughness^2), in [0, 1].
    pub roughness: f32,
    /// `metallicRoughnessTexture` (linear; blue = metallic, green = roughness), multiplying the
    /// factors; index into `Scene::textures`.
    pub texture: Option<u32>,
}

impl Default for MetallicRoughness {
    fn default() -> Self {
        Self { metallic: 1.0, roughness: 1.0, texture: None }
    }
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: String::from("default"),
            diffuse: Vec3::splat(0.8),
            specular: Vec3::ZERO,
            shininess: 1.0,
            emission: Vec3::ZERO,
            ior: 1.5,
            dissolve: 1.0,
            illum: 2,
            diffuse_map: None,
            alpha_map: None,
            diffuse_texture: None,
            alpha_texture: None,
            alpha_cutoff: 0.2,
            alpha_blend: false,
            metallic_roughness: None,
            normal_texture: None,
            normal_scale: 1.0,
            normal_map: None,
            emission_texture: None,
            double_sided: true,
        }
    }
}

impl Material {
    /// MTL illum 3 (reflection, ray traced) and 5 (Fresnel reflection): a mirror weighted by Ks.
    pub fn is_mirror(&self) -> bool {
        matches!(self.illum, 3 | 5) && self.specular.max_element() > 0.0
    }
    /// MTL illum 4, 6, 7, 9: glass-like, refracting with index Ni.
    pub fn is_dielectric(&self) -> bool {
        matches!(self.illum, 4 | 6 | 7 | 9)
    }
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
    /// Whether shading reads any texture of this material (and so texture coordinates).
    pub fn has_textures(&self) -> bool {
        self.diffuse_texture.is_some()
            || self.alpha_texture.is_some()
            || self.emission_texture.is_some()
            || self.normal_texture.is_some()
            || self.metallic_roughness.is_some_and(|mr| mr.texture.is_some())
    }
}
