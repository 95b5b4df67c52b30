// Numbers shared by the host and the shaders, named once.
//
// This file is compiled twice: as `vkrt::gpu_abi::constants`, and by `host/build.rs`, which
// writes each entry of `ALL` as a `#define` into the generated `constants.glsl` that every
// shader includes, and each of `ALL_VEC3` as a `const vec3`. Add a line to a table and both
// sides see it.

macro_rules! shared_constants {
    ($($(#[$meta:meta])* $name:ident = $value:expr;)*) => {
        $($(#[$meta])* pub const $name: u32 = $value;)*
        /// Every shared constant by name, for the GLSL generator and the tests.
        pub const ALL: &[(&str, u32)] = &[$((stringify!($name), $name)),*];
    };
}

shared_constants! {
    // Descriptor set 0 bindings. The arrays the integrators read (BVH, shading data, textures,
    // light picks) are uniform texel buffers, RGBA32UI except TEXELS (R32UI)
    // (shaders/include/bvh_bindings.glsl and scene_bindings.glsl say why), which the layout
    // probe (shaders/test/layout_probe.comp) declares as struct arrays to check their layout;
    // FRAME and PATH_PARAMS are uniform buffers; the rest storage buffers.
    /// Flattened BVH nodes (`GpuNode[]`, 2 texels each).
    BINDING_NODES = 0;
    /// Triangles in leaf order (`GpuTriangle[]`, 3 texels each).
    BINDING_TRIANGLES = 1;
    /// Per-triangle shading data by primitive id (`GpuShading[]`).
    BINDING_SHADING = 2;
    /// Materials (`GpuMaterial[]`).
    BINDING_MATERIALS = 3;
    /// Point, directional and spot lights (`GpuLight[]`).
    BINDING_LIGHTS = 4;
    /// Emissive triangles (`GpuEmitter[]`).
    BINDING_EMITTERS = 5;
    /// Per-frame settings (`GpuFrame`, uniform buffer).
    BINDING_FRAME = 6;
    /// Accumulated radiance, one vec4 per pixel (rgb sum, sample count in w).
    BINDING_ACCUM = 7;
    /// Rays for batch queries (`GpuRay[]`).
    BINDING_RAYS = 8;
    /// Hit records for batch queries (`GpuHit[]`).
    BINDING_HITS = 9;
    /// The path tracer's light-selection alias table (`GpuLightPick[]`): emissive triangles
    /// first, then point, directional and spot lights.
    BINDING_LIGHT_PICKS = 10;
    /// The path tracer's settings (`GpuPathParams`, uniform buffer).
    BINDING_PATH_PARAMS = 11;
    /// Texture table (`GpuTexture[]`): where each texture's texels start in BINDING_TEXELS.
    BINDING_TEXTURES = 13;
    /// Every texture's texels, packed RGBA8 (one u32 each, red in the low byte), concatenated:
    /// one binding holds any number of textures (`crate::prepare::texture_atlas`).
    BINDING_TEXELS = 14;
    /// Per-primitive texture coordinates by primitive id (`GpuUv[]`).
    BINDING_UVS = 15;
    /// First of the ten outputs of the texel-decode test probe (shaders/test/texel_decode_probe.comp).
    BINDING_DECODE_OUT = 16;
    /// Adaptive sampling: each block's (first sample index, sample count) for the dispatch,
    /// `uvec2[]` indexed as `sample_key` with the block width (`crate::integrator::path::adaptive`).
    /// After the decode probe's ten outputs.
    BINDING_BLOCK_SAMPLES = 26;
    /// The path tracer's rays traced per pixel (`uint[]`, added to by each dispatch): what the
    /// progress line's rays/s counts. Each pixel is one invocation's, so no atomics.
    BINDING_RAY_COUNTS = 27;
    /// The path tracer's sums: six planes of one fixed-point u64 per pixel (`uvec2` low, high
    /// word), the even-indexed samples' r, g, b and the odd-indexed samples' r, g, b (two
    /// independent half-images, whose difference estimates the error), and a plane of
    /// (samples taken, samples dropped) per pixel. Planes, not one struct per pixel, so that
    /// one binding stays 8 bytes per pixel (a 4096² image in lavapipe's 128 MiB).
    BINDING_SUM_EVEN_R = 28;
    BINDING_SUM_EVEN_G = 29;
    BINDING_SUM_EVEN_B = 30;
    BINDING_SUM_ODD_R = 31;
    BINDING_SUM_ODD_G = 32;
    BINDING_SUM_ODD_B = 33;
    BINDING_SAMPLE_COUNTS = 34;
    /// The environment map (`--envmap`; `crate::prepare::envmap`): its radiance, one RGBA32F
    /// texel per map texel (as RGBA32UI bits; alpha unused), row 0 the top row...
    BINDING_ENV_TEXELS = 38;
    /// ... and its sampling distribution, floats as R32UI bits: the marginal CDF over the
    /// H - 1 rows of cells (H entries), then each row's conditional CDF over its W cells
    /// (W + 1 entries each).
    BINDING_ENV_CDF = 39;
    /// Per-primitive vertex tangents by primitive id (`GpuTangents[]`): bound always, filled
    /// only when some material has a normal map (else one zero entry).
    BINDING_TANGENTS = 35;
    /// The texel-decode probe's output of decoded tangents (after BINDING_TANGENTS).
    BINDING_DECODE_OUT_TANGENTS = 36;
    /// The path tracer's mirror probe (`uint[]`, one per pixel, written by the probe pass and
    /// read by every sampling dispatch; shaders/include/mirror_probe.glsl): the probability
    /// with which the camera ray's first hit takes a mirror lobe over its Lambert lobe, as
    /// float bits, or 0 for the material's own choice.
    BINDING_MIRROR_PROBE = 37;
    /// The path tracer's planar mirror triangles (`GpuMirror[]`, 3 texels each;
    /// `crate::prepare::mirrors`): next-event estimation through them. Grouped by plane ...
    BINDING_MIRRORS = 40;
    /// ... and the groups (`GpuMirrorPlane[]`): light sampling picks a plane.
    BINDING_MIRROR_PLANES = 41;
    /// The path tracer's caustic casters (`GpuCaster[]`, 3 texels each; `crate::prepare::casters`):
    /// diffuse bounces are partly aimed at them (one zero entry without any).
    BINDING_CASTERS = 42;
    /// The triangle list (`GpuTriangle[MAX_LIST_TRIANGLES]`, uniform buffer): the scene's few
    /// largest triangles, kept out of the BVH and tested by every ray before its walk
    /// (`crate::accel::triangle_list`).
    BINDING_TRIANGLE_LIST = 43;
    /// A two-level BVH's instances (`GpuInstance[]`, 9 texels each; the
    /// `_two_level_<id>` builds of the tracing shaders only).
    BINDING_INSTANCES = 44;
    /// `GpuInstance::flags`: the instance's transform mirrors.
    INSTANCE_MIRRORED = 1;
    /// `GpuEmitter::flags`: the emitter is a mirrored copy's triangle.
    EMITTER_SWAPPED = 1;
    /// Triangles the triangle list holds at most: each is a test for every ray and an unrolled
    /// copy of the test at every trace call site (pipeline creation time), so only a room's
    /// worth (docs/experiments/triangle-list.md: 44 of Sponza's listed cost 13 %).
    MAX_LIST_TRIANGLES = 16;
    /// Fractional bits of those sums: a sample's radiance c >= 0 adds round(c 2^24). Integer
    /// sums are exact and the same in any order, so a run split into batches, resumed runs and
    /// merged shards give the same bytes as one run. Quantum 6e-8; a pixel's sum holds up to
    /// 2^40 (1.1e12) of radiance: 1e6 samples of 1e6.
    ACCUM_FRACTION_BITS = 24;
    /// Samples brighter than 2^ACCUM_MAX_SAMPLE_LOG2 (4.3e9) in a channel are dropped and
    /// counted, like NaN and Inf: the sums could not hold many.
    ACCUM_MAX_SAMPLE_LOG2 = 32;

    /// Specialization constant ids of the workgroup size (`local_size_*_id`); the sizes are
    /// chosen per device by `gpu::Workgroups::for_device`.
    SPEC_WORKGROUP_X = 10;
    SPEC_WORKGROUP_Y = 11;
    SPEC_WORKGROUP_1D = 12;
    /// Specialization constant id: 1 where the device's division may be off by ulps, so the
    /// ray setup and the triangle test correct their quotients to the rounded ones the CPU twin
    /// computes (`div_rn`, shaders/include/division.glsl); 0 on lavapipe, whose division is
    /// IEEE already. Set for every pipeline from `gpu::DeviceInfo::divides_exactly`.
    SPEC_CORRECT_DIVISION = 17;
    /// How many triangles the triangle list holds (`GpuPush::list_count`): the tracing shaders
    /// unroll its loop for this count; 0 compiles it out.
    SPEC_LIST_TRIANGLES = 18;
    /// Which of the list's triangles are walls (bit i: the list's i-th; `accel::walls`): the
    /// whole scene on one side of their plane, so the integrators' shadow rays, which run
    /// between two points of the scene, skip them. 0 (batch queries) tests every one.
    SPEC_LIST_WALLS = 20;
    /// Specialization constant id of the path tracer: 1 where each sample also traces one light
    /// vertex and connects its surface vertices to it (`integrator::path::connections`); 0
    /// compiles that code out, and the samples are those of a run without it.
    SPEC_LIGHT_CONNECTIONS = 19;
    /// The path tracer's estimator as `PathParams::nee` and checkpoints record it: BSDF sampling
    /// only (`--no-nee`), next-event estimation with MIS, or that and light-vertex connections.
    NEE_OFF = 0;
    NEE_ON = 1;
    NEE_WITH_CONNECTIONS = 2;

    /// A leaf packs (first triangle << LEAF_COUNT_BITS) | count into one u32; 0 count = interior.
    LEAF_COUNT_BITS = 8;
    /// Escape link value meaning "traversal is done".
    NODE_NONE = 0xFFFF_FFFF;
    /// Marks a leaf in `GpuCompactNode::link` (`crate::accel::compact`).
    COMPACT_LEAF_FLAG = 0x8000_0000;
    /// Bits per box-corner cell index in `GpuCompactNode`: two cells per u32.
    COMPACT_CELL_BITS = 16;
    /// Primitive id of a miss.
    PRIM_NONE = 0xFFFF_FFFF;

    /// Material flags (`GpuMaterial::flags`).
    MATERIAL_MIRROR = 1;
    MATERIAL_DIELECTRIC = 2;
    MATERIAL_EMISSIVE = 4;
    /// The material has an alpha texture with see-through texels: rays test it (alpha.glsl).
    MATERIAL_ALPHA = 8;
    /// glTF 2.0 metallic-roughness: `metallic`, `roughness` and the base colour make the BSDF
    /// (bsdf.glsl), and `diffuse_texture` multiplies `diffuse` instead of replacing it.
    MATERIAL_METALLIC_ROUGHNESS = 16;
    /// The material has a tangent-space normal map (`normal_texture`; surface.glsl).
    MATERIAL_NORMAL_MAP = 32;
    /// glTF `alphaMode: BLEND`: alpha is coverage (stochastic transparency in the path tracer,
    /// a cut-out at 0.5 in Whitted; alpha.glsl). Set with `MATERIAL_ALPHA`.
    MATERIAL_BLEND = 64;
    /// A mirror whose every triangle is flat and untextured, so that the path tracer samples
    /// light through it (`crate::prepare::mirrors`, shaders/include/mirror_light.glsl). Set at
    /// upload, not stored in prepared scenes.
    MATERIAL_PLANAR_MIRROR = 128;
    /// `GpuMaterial::diffuse_texture`, `alpha_texture` and `GpuFrame::sky_texture` meaning "none".
    TEXTURE_NONE = 0xFFFF_FFFF;

    /// Specialization constant ids (shaders/include/features.glsl, `crate::prepare::features`): each
    /// switches one feature's code on; a scene that lacks the feature runs with it compiled out.
    SPEC_HAS_TEXTURES = 0;
    SPEC_HAS_ALPHA = 1;
    SPEC_HAS_DIELECTRIC = 2;
    SPEC_HAS_MIRROR = 3;
    SPEC_HAS_GLOSSY = 4;
    SPEC_HAS_EMITTERS = 5;
    SPEC_HAS_POINT = 6;
    SPEC_HAS_DIRECTIONAL = 7;
    SPEC_HAS_SPOT = 8;
    SPEC_HAS_SKY = 9;
    SPEC_HAS_ENVMAP = 16;
    // 10-12 are the workgroup sizes above.
    SPEC_HAS_METALLIC_ROUGHNESS = 13;
    SPEC_HAS_NORMAL_MAP = 14;
    /// glTF spot lights (`LIGHT_CONE`); after the workgroup ids and the ids other features took.
    SPEC_HAS_CONE = 15;

    /// Light kinds (`GpuLight::kind`).
    LIGHT_POINT = 0;
    LIGHT_DIRECTIONAL = 1;
    LIGHT_SPOT = 2;
    /// A glTF spot light (`scene::Light::Cone`): `GpuLight::radius` holds the cosine of its
    /// inner cone angle, `cos_outer` that of the outer one.
    LIGHT_CONE = 3;

    /// Fixed samples per emissive triangle in the Whitted integrator (a stratified pattern).
    WHITTED_EMITTER_SAMPLES = 4;
    /// Whitted ray-tree stack entries; max depth is clamped to this minus one.
    WHITTED_STACK_SIZE = 16;

    /// The wide layout (`crate::accel::wide`): children per node, and how `GpuWideNode::info` packs
    /// a node's child count (low 3 bits), its ordering axis and its slot in its parent.
    WIDE_ARITY = 4;
    WIDE_INFO_AXIS_SHIFT = 3;
    WIDE_INFO_SLOT_SHIFT = 5;
    /// "Entered from the parent": every slot of the node is still to visit.
    WIDE_NO_SLOT = 0xFF;

    /// Path tracer samplers (`GpuPathParams::sampler`).
    SAMPLER_INDEPENDENT = 0;
    /// Owen-scrambled Sobol (Burley 2020), each pixel its own sequence.
    SAMPLER_SOBOL = 1;
    /// `sample_rate`^2 strata per pixel for the pixel position, independent elsewhere.
    SAMPLER_STRATIFIED = 2;
    /// Sobol with the pixels' sample sets in Z order (Ahmed & Wonka 2020), the default:
    /// neighbouring pixels take neighbouring parts of one sequence, so errors are blue noise.
    SAMPLER_ZSOBOL = 3;
    /// The largest log2 of a Z-ordered set's samples per pixel (`GpuPathParams::zsobol_log2`):
    /// the set's index, `ZSOBOL_CELL_BITS` of position and this many of sample, is 32 bits.
    ZSOBOL_MAX_LOG2 = 16;
    /// Bits of a Z-ordered cell's position in its tile (a 256 x 256 tile of pixels, or of
    /// groups in a row; with scattered coherence a block's groups, at most 2^16 of them).
    ZSOBOL_CELL_BITS = 16;
    /// Path depth at which Russian roulette starts (Mitsuba's default, which the references use).
    PATH_RR_DEPTH = 5;
    /// `GpuPathParams::max_depth` meaning "unbounded".
    PATH_DEPTH_UNBOUNDED = 0xFFFF_FFFF;
}

/// Rec. 709 luminance weights of linear RGB (sRGB primaries): how the environment map's
/// sampling distribution weighs its texels (as Mitsuba's envmap does; `prepare::envmap` and
/// environment.glsl's `env_luminance`) and how automatic exposure meters an image
/// (`output::display`). `crate::gpu_abi::luminance` applies them.
pub const REC709_LUMINANCE: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// The shared `vec3` constants by name, for the GLSL generator.
pub const ALL_VEC3: &[(&str, [f32; 3])] = &[("REC709_LUMINANCE", REC709_LUMINANCE)];
