//! The per-scene arrays besides the BVH: shading data, materials, lights and emitters.

use super::texture_atlas::gpu_index;
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuEmitter, GpuLight, GpuMaterial, GpuShading, GpuTangents, GpuUv};
use crate::scene::{Light, Material, Scene, Triangle};

/// Everything the shaders read about a scene except its BVH.
#[derive(Debug, Clone, Default)]
pub struct SceneBuffers {
    pub shading: Vec<GpuShading>,
    pub materials: Vec<GpuMaterial>,
    pub lights: Vec<GpuLight>,
    pub emitters: Vec<GpuEmitter>,
    /// Texture coordinates by primitive id; empty when no material has a texture (the shaders
    /// then never read them, and big untextured scenes save 32 bytes a triangle).
    pub uvs: Vec<GpuUv>,
    /// Vertex tangents by primitive id (`Scene::tangents`); empty when no material has a
    /// normal map, for the same reason.
    pub tangents: Vec<GpuTangents>,
}

pub fn gpu_material(m: &Material) -> GpuMaterial {
    let mut flags = 0;
    if m.is_mirror() {
        flags |= MATERIAL_MIRROR;
    }
    if m.is_dielectric() {
        flags |= MATERIAL_DIELECTRIC;
    }
    if m.is_emissive() {
        flags |= MATERIAL_EMISSIVE;
    }
    if m.alpha_texture.is_some() {
        flags |= MATERIAL_ALPHA;
        if m.alpha_blend {
            flags |= MATERIAL_BLEND;
        }
    }
    if m.metallic_roughness.is_some() {
        flags |= MATERIAL_METALLIC_ROUGHNESS;
    }
    if m.normal_texture.is_some() {
        flags |= MATERIAL_NORMAL_MAP;
    }
    let mr = m.metallic_roughness.unwrap_or_default();
    GpuMaterial {
        diffuse: m.diffuse.to_array(),
        flags,
        specular: m.specular.to_array(),
        shininess: m.shininess,
        emission: m.emission.to_array(),
        ior: m.ior,
        diffuse_texture: gpu_index(m.diffuse_texture),
        alpha_texture: gpu_index(m.alpha_texture),
        emission_texture: gpu_index(m.emission_texture),
        alpha_cutoff: m.alpha_cutoff,
        metallic: mr.metallic.clamp(0.0, 1.0),
        roughness: mr.roughness.clamp(0.0, 1.0),
        metallic_roughness_texture: gpu_index(mr.texture),
        normal_scale: m.normal_scale,
        normal_texture: gpu_index(m.normal_texture),
        _pad0: 0,
        _pad1: 0,
        _pad2: 0,
    }
}

pub fn gpu_light(l: &Light) -> GpuLight {
    let (kind, position, direction, intensity, radius, cos_outer) = match *l {
        Light::Point { position, intensity } => (LIGHT_POINT, position, glam::Vec3::ZERO, intensity, 0.0, 0.0),
        Light::Directional { direction, intensity } => (LIGHT_DIRECTIONAL, glam::Vec3::ZERO, direction.normalize_or_zero(), intensity, 0.0, 0.0),
        Light::Spot { position, direction, intensity, radius } => (LIGHT_SPOT, position, direction.normalize_or_zero(), intensity, radius, 0.0),
        Light::Cone { position, direction, intensity, cos_inner, cos_outer } => {
            (LIGHT_CONE, position, direction.normalize_or_zero(), intensity, cos_inner, cos_outer)
        }
    };
    GpuLight { position: position.to_array(), kind, direction: direction.to_array(), radius, intensity: intensity.to_array(), cos_outer }
}

impl SceneBuffers {
    /// The arrays of a scene whose BVH is one level: an entry per primitive of `scene`, which
    /// has no instances (`Scene::expanded`; a two-level BVH's are `mesh_shading::per_mesh`).
    pub fn new(scene: &Scene) -> Self {
        let mut b = Self::without_triangles(scene);
        b.add_block(scene, &scene.triangles, &scene.tangents);
        b.add_own_emitters(scene, 0);
        b
    }

    /// The materials and lights, and no triangle's entries.
    pub fn without_triangles(scene: &Scene) -> Self {
        Self { materials: scene.materials.iter().map(gpu_material).collect(), lights: scene.lights.iter().map(gpu_light).collect(), ..Self::default() }
    }

    /// Adds a block of entries for `triangles` (shading; texture coordinates and tangents
    /// where some material of `scene` needs them) and returns where it starts.
    pub fn add_block(&mut self, scene: &Scene, triangles: &[Triangle], triangle_tangents: &[[glam::Vec4; 3]]) -> u32 {
        let base = self.shading.len() as u32;
        self.shading.extend(triangles.iter().map(shading));
        if scene.materials.iter().any(|m| m.has_textures()) {
            self.uvs.extend(triangles.iter().map(uv));
        }
        if scene.materials.iter().any(|m| m.normal_texture.is_some()) {
            self.tangents.extend((0..triangles.len()).map(|i| tangents(triangle_tangents.get(i))));
        }
        base
    }

    /// Adds an emitter for each emitting triangle of `scene.triangles`, its shading entry
    /// `base` plus its index.
    pub fn add_own_emitters(&mut self, scene: &Scene, base: u32) {
        self.emitters.extend(scene.emissive_triangles().into_iter().map(|prim| emitter(scene, &scene.triangles[prim as usize], base + prim, 0)));
    }
}

/// A triangle's shading entry: its normals (the geometric one at each vertex where the file
/// has none) and material.
pub fn shading(t: &Triangle) -> GpuShading {
    let n = t.n.unwrap_or([t.cross().normalize_or_zero(); 3]);
    GpuShading { n0: n[0].to_array(), material: t.material, n1: n[1].to_array(), _pad0: 0, n2: n[2].to_array(), _pad1: 0 }
}

/// A triangle's texture coordinates (zero where the file has none).
pub fn uv(t: &Triangle) -> GpuUv {
    let uv = t.uv.unwrap_or_default();
    GpuUv { uv0: uv[0].to_array(), uv1: uv[1].to_array(), uv2: uv[2].to_array(), _pad0: 0, _pad1: 0 }
}

/// A triangle's vertex tangents (zero where it has none).
pub fn tangents(t: Option<&[glam::Vec4; 3]>) -> GpuTangents {
    let t = t.copied().unwrap_or_default();
    GpuTangents { t0: t[0].to_array(), t1: t[1].to_array(), t2: t[2].to_array() }
}

/// An emitting triangle `t` (in the world) whose shading entry is `prim`.
pub fn emitter(scene: &Scene, t: &Triangle, prim: u32, flags: u32) -> GpuEmitter {
    GpuEmitter {
        v0: t.p[0].to_array(),
        prim,
        v1: t.p[1].to_array(),
        area: t.area(),
        v2: t.p[2].to_array(),
        flags,
        // The factor only, also with an emission texture: the light picker weighs a triangle
        // by it and the shader multiplies in the texel at the sampled point (lights.glsl), so
        // light sampling stays unbiased (a dark texture only makes the pick less well matched
        // to the power).
        radiance: scene.materials[t.material as usize].emission.to_array(),
        _pad1: 0,
    }
}
