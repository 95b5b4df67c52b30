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
}
