//! The scene's shading arrays: per-triangle data, materials, textures, lights and the light
//! picker's alias table. Filled by `crate::prepare`.

gpu_structs! {
    /// Per-primitive shading data, indexed by primitive id.
    pub struct GpuShading {
        /// Vertex normals (the geometric normal three times if the file has none).
        pub n0: [f32; 3],
        pub material: u32,
        pub n1: [f32; 3],
        pub _pad0: u32,
        pub n2: [f32; 3],
        pub _pad1: u32,
    }

    /// A material as the shaders read it. See `crate::scene::Material` for the meaning of each field.
    pub struct GpuMaterial {
        pub diffuse: [f32; 3],
        /// `MATERIAL_*` bits.
        pub flags: u32,
        pub specular: [f32; 3],
        pub shininess: f32,
        pub emission: [f32; 3],
        pub ior: f32,
        /// Index into the texture table of the sRGB colour texture, or `TEXTURE_NONE`: it replaces
        /// `diffuse` (MTL, lab) or, with `MATERIAL_METALLIC_ROUGHNESS`, multiplies it (glTF's base
        /// colour texture times its factor).
        pub diffuse_texture: u32,
        /// Index of the texture whose alpha cuts the surface out (alpha < `alpha_cutoff` is
        /// see-through), or `TEXTURE_NONE`. Only read when `flags` has `MATERIAL_ALPHA`.
        pub alpha_texture: u32,
        /// glTF `emissiveTexture` (sRGB), multiplying `emission`, or `TEXTURE_NONE`.
        pub emission_texture: u32,
        /// Alpha below this is see-through (0.2, the lab's rule, for MTL; glTF `alphaCutoff`).
        /// With `MATERIAL_BLEND` the path tracer reads alpha as coverage instead (alpha.glsl).
        pub alpha_cutoff: f32,
        /// glTF `metallicFactor` and `roughnessFactor` (perceptual: GGX alpha = roughness^2);
        /// read with `MATERIAL_METALLIC_ROUGHNESS` only.
        pub metallic: f32,
        pub roughness: f32,
        /// glTF `metallicRoughnessTexture` (linear; blue scales metallic, green roughness), or
        /// `TEXTURE_NONE`.
        pub metallic_roughness_texture: u32,
        /// glTF `normalTexture.scale`: scales the tangent-space normal's x and y.
        pub normal_scale: f32,
        /// Tangent-space normal map (linear), read with `MATERIAL_NORMAL_MAP`, or `TEXTURE_NONE`.
        pub normal_texture: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// One texture in the texel atlas (`BINDING_TEXELS`): texel (x, y) of this texture, row 0 the
    /// top row of the image file, is `texels[offset + y * width + x]`.
    pub struct GpuTexture {
        pub offset: u32,
        pub width: u32,
        pub height: u32,
        pub _pad0: u32,
    }

    /// A triangle's vertex texture coordinates, by primitive id (zero if the file has none).
    pub struct GpuUv {
        pub uv0: [f32; 2],
        pub uv1: [f32; 2],
        pub uv2: [f32; 2],
        pub _pad0: u32,
        pub _pad1: u32,
    }

    /// A triangle's vertex tangents by primitive id (xyz, w = +-1 the bitangent's sign, as
    /// glTF's TANGENT: bitangent = w * cross(normal, tangent)); zero where none could be made.
    pub struct GpuTangents {
        pub t0: [f32; 4],
        pub t1: [f32; 4],
        pub t2: [f32; 4],
    }

    /// A point, directional, spot or cone light. See `crate::scene::Light` for the units.
    pub struct GpuLight {
        pub position: [f32; 3],
        /// `LIGHT_*`.
        pub kind: u32,
        /// Normalised; for a directional light, the direction toward the light; for spot and
        /// cone lights, the way they shine.
        pub direction: [f32; 3],
        /// Spot: the sphere's radius. Cone: the cosine of the inner cone angle.
        pub radius: f32,
        pub intensity: [f32; 3],
        /// Cone: the cosine of the outer cone angle; 0 for the other kinds.
        pub cos_outer: f32,
    }

    /// An emissive triangle, for light sampling.
    pub struct GpuEmitter {
        pub v0: [f32; 3],
        pub prim: u32,
        pub v1: [f32; 3],
        pub area: f32,
        pub v2: [f32; 3],
        /// `EMITTER_SWAPPED`: a mirrored copy's triangle (a two-level BVH's), whose second and
        /// third vertices are in the other order than its shading entry's.
        pub flags: u32,
        pub radiance: [f32; 3],
        pub _pad1: u32,
    }

    /// A planar mirror triangle (`crate::prepare::mirrors`), for light sampled through it.
    pub struct GpuMirror {
        pub v0: [f32; 3],
        /// Its material (`MATERIAL_PLANAR_MIRROR`).
        pub material: u32,
        pub v1: [f32; 3],
        pub _pad0: u32,
        pub v2: [f32; 3],
        pub _pad1: u32,
    }

    /// The mirror triangles of one plane and material (`crate::prepare::mirrors`): entries
    /// `first .. first + count` of BINDING_MIRRORS.
    pub struct GpuMirrorPlane {
        pub first: u32,
        pub count: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }

    /// A caustic caster (`crate::prepare::casters`): a curved glossy, mirror or glass piece that
    /// diffuse bounces are partly aimed at (shaders/include/caster_guide.glsl).
    pub struct GpuCaster {
        /// Its bounding sphere.
        pub center: [f32; 3],
        pub radius: f32,
        /// The emissive triangles' bounding sphere, which the spot cone aims to mirror.
        pub target: [f32; 3],
        pub target_radius: f32,
        /// The spot cone's allowance for the lobe's spread (radians); negative: no spot cone
        /// (glass, not a ball, or no emissive triangles).
        pub spot_spread: f32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// One entry of the light-selection alias table (Vose 1991, "A linear algorithm for
    /// generating random numbers with a given distribution"): pick entry i uniformly, keep it if
    /// u < `threshold`, else take `alias`. `pmf` is the probability of selecting entry i itself,
    /// `alias_pmf` that of entry `alias` (a copy of its `pmf`), so that a pick reads one entry:
    /// lavapipe runs each texel fetch as a call, and the second cost ~1 of the path tracer's
    /// 25-40 fetches per bounce.
    pub struct GpuLightPick {
        pub pmf: f32,
        pub alias: u32,
        pub threshold: f32,
        pub alias_pmf: f32,
    }
}

const _: () = assert!(std::mem::size_of::<GpuShading>() == 48);
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 96);
const _: () = assert!(std::mem::size_of::<GpuTexture>() == 16);
const _: () = assert!(std::mem::size_of::<GpuUv>() == 32);
const _: () = assert!(std::mem::size_of::<GpuTangents>() == 48);
const _: () = assert!(std::mem::size_of::<GpuLight>() == 48);
const _: () = assert!(std::mem::size_of::<GpuEmitter>() == 64);
const _: () = assert!(std::mem::size_of::<GpuLightPick>() == 16);
