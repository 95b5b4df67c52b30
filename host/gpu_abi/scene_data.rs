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
        /// Index into the texture table whose sRGB colour replaces `diffuse`, or `TEXTURE_NONE`.
        pub diffuse_texture: u32,
        /// Index of the texture whose alpha cuts the surface out (alpha < 0.2 is see-through), or
        /// `TEXTURE_NONE`. Only read when `flags` has `MATERIAL_ALPHA`.
        pub alpha_texture: u32,
        pub _pad0: u32,
        pub _pad1: u32,
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
        pub _pad0: u32,
        pub radiance: [f32; 3],
        pub _pad1: u32,
    }

    /// One entry of the light-selection alias table (Vose 1991, "A linear algorithm for
    /// generating random numbers with a given distribution"): pick entry i uniformly, keep it if
    /// u < `threshold`, else take `alias`. `pmf` is the probability of selecting entry i itself.
    pub struct GpuLightPick {
        pub pmf: f32,
        pub alias: u32,
        pub threshold: f32,
        pub _pad0: u32,
    }
}

const _: () = assert!(std::mem::size_of::<GpuShading>() == 48);
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 64);
const _: () = assert!(std::mem::size_of::<GpuTexture>() == 16);
const _: () = assert!(std::mem::size_of::<GpuUv>() == 32);
const _: () = assert!(std::mem::size_of::<GpuLight>() == 48);
const _: () = assert!(std::mem::size_of::<GpuEmitter>() == 64);
const _: () = assert!(std::mem::size_of::<GpuLightPick>() == 16);
