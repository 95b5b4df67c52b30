//! What each render and dispatch passes besides the scene: the frame and path-tracer uniforms,
//! the push constants, and the ray and hit records of batch queries (`vkrt trace`).

gpu_structs! {
    /// Per-render settings (uniform buffer, std140: every vec3 is followed by a 4-byte scalar).
    pub struct GpuFrame {
        pub cam_origin: [f32; 3],
        pub tan_half_fov_y: f32,
        pub cam_forward: [f32; 3],
        pub aspect: f32,
        pub cam_right: [f32; 3],
        pub width: u32,
        pub cam_up: [f32; 3],
        pub height: u32,
        pub ambient: [f32; 3],
        pub max_depth: u32,
        pub light_count: u32,
        pub emitter_count: u32,
        pub seed: u32,
        /// Largest |coordinate| of the scene bounds: the length scale for ray offsets
        /// (`shaders/include/offset.glsl`).
        pub scene_scale: f32,
        /// Radiance of escaping rays: this colour, times the cube map's texel if `sky_texture` is
        /// set (black: no sky).
        pub sky_color: [f32; 3],
        /// First of the six cube-map faces (+x, -x, +y, -y, +z, -z) in the texture table, or
        /// `TEXTURE_NONE` for a constant sky.
        pub sky_texture: u32,
        /// The thin lens (`crate::scene::camera::Lens`): aperture radius (0: a pinhole) and the
        /// distance to the plane in focus.
        pub aperture_radius: f32,
        pub focus_distance: f32,
        /// The environment map (`crate::prepare::envmap`): its size in texels (0: none), the
        /// cosine and sine of its rotation about +y, and the probability that light sampling
        /// picks it (the light table's last entry), and the luminance taken off each texel's
        /// where it weighs the map's sampling (`prepare::EnvLight::compensation`).
        pub env_width: u32,
        pub env_height: u32,
        pub env_rotation_cos: f32,
        pub env_rotation_sin: f32,
        pub env_pick_pmf: f32,
        pub env_compensation: f32,
    }

    /// Per-dispatch values (push constants): which tile and which samples this dispatch renders.
    pub struct GpuPush {
        pub tile_x: u32,
        pub tile_y: u32,
        /// Index of the first sample this dispatch takes per pixel.
        pub sample_base: u32,
        /// Samples per pixel in this dispatch.
        pub sample_count: u32,
        /// Spp of the whole render (for stratification).
        pub total_spp: u32,
        /// Rays in the batch (ray queries) or 0.
        pub ray_count: u32,
        /// 1: any-hit (shadow) queries; 0: closest hit.
        pub any_hit: u32,
        /// Nodes in the BVH array (all orders of a multi-order layout).
        pub node_count: u32,
        /// The compact layout's grid (`crate::accel::compact::QuantGrid`); zero for the other layouts.
        pub grid_origin: [f32; 3],
        /// Image kernels: the stride that deals the dispatch's workgroups to the tile's regions
        /// (`crate::integrator::tiles::group_stride`); 0 or 1 is in order.
        pub group_stride: u32,
        pub grid_scale: [f32; 3],
        /// Image kernels: the workgroup's shape in invocations (the shaders' `gl_WorkGroupSize`
        /// is not specialised on Mesa 25.0 lavapipe: it reads 1 x 1, see tile_region.glsl).
        pub group_width: u32,
        pub group_height: u32,
        /// The path tracer: 1 for the mirror-probe pass (one value per pixel into
        /// BINDING_MIRROR_PROBE, no samples; shaders/include/mirror_probe.glsl), 0 to sample.
        pub probe: u32,
        /// The triangle list (`crate::accel::triangle_list`): where it starts in the
        /// triangle array, and how many triangles it holds (0: none; the shaders unroll its
        /// loop for SPEC_LIST_TRIANGLES, which the pipelines set to this count).
        pub list_first: u32,
        pub list_count: u32,
        /// A two-level BVH laid out in the multi-order layout (`crate::accel::two_level`):
        /// nodes per order of its top level (order `k` starts at `k * top_order_nodes`); 0 for
        /// threaded levels and for the one-level layouts.
        pub top_order_nodes: u32,
        /// A two-level BVH laid out in the compact layout: nodes of its top level (its walk
        /// ends there; `grid_origin` and `grid_scale` are its grid); 0 otherwise.
        pub top_nodes: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// The path tracer's per-render settings (uniform buffer, std140).
    pub struct GpuPathParams {
        /// Path segments (rays) per path; `PATH_DEPTH_UNBOUNDED` for none.
        pub max_depth: u32,
        /// Depth from which Russian roulette may end a path.
        pub rr_depth: u32,
        /// `SAMPLER_*`.
        pub sampler_kind: u32,
        /// Strata per pixel side for `SAMPLER_STRATIFIED`.
        pub sample_rate: u32,
        /// Entries in the light-selection table (emissive triangles, then lights).
        pub pick_count: u32,
        /// 1: next-event estimation with MIS; 0: BSDF sampling only.
        pub nee: u32,
        /// 1 / the total selection weight (see `crate::prepare::light_table`), so that an emissive
        /// triangle's area density is pi * mean(Ke) * inv_total_weight.
        pub inv_total_weight: f32,
        /// Pixels that draw the same sample numbers (1: every pixel its own; see
        /// `crate::integrator::path::PathSettings::coherence`).
        pub coherence: u32,
        /// Adaptive sampling: the pixels per block (`crate::integrator::path::adaptive::BlockGrid`), each block
        /// taking the samples BINDING_BLOCK_SAMPLES gives it; 0: every pixel takes the push
        /// constants' `sample_base .. + sample_count`.
        pub adaptive: u32,
        /// log2 of the side of the square blocks over which a coherence group's pixels are
        /// scattered; 0: groups are `coherence` pixels in a row (see
        /// `crate::integrator::path::PathSettings::coherence_block`).
        pub coherence_block_bits: u32,
        /// `SAMPLER_ZSOBOL`: log2 of the samples per pixel of one Z-ordered set (sample k
        /// belongs to set k >> zsobol_log2), at most `ZSOBOL_MAX_LOG2`.
        pub zsobol_log2: u32,
        /// Mirror planes (BINDING_MIRROR_PLANES) to sample light through; 0: none.
        pub mirror_count: u32,
        /// Caustic casters (BINDING_CASTERS) that diffuse bounces are partly aimed at; 0: none.
        pub caster_count: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }

    /// A ray for batch queries: origin, tmin, direction, tmax (the `vkrt trace` file layout).
    pub struct GpuRay {
        pub origin: [f32; 3],
        pub tmin: f32,
        pub direction: [f32; 3],
        pub tmax: f32,
    }

    /// The result of a batch query, with traversal counters.
    pub struct GpuHit {
        /// Distance along the ray; +inf on a miss.
        pub t: f32,
        /// Primitive id, or `PRIM_NONE`.
        pub prim: u32,
        /// Barycentrics of v1 and v2.
        pub u: f32,
        pub v: f32,
        /// Nodes whose boxes were tested.
        pub nodes_visited: u32,
        /// Triangles tested.
        pub tris_tested: u32,
        pub _pad0: u32,
        pub _pad1: u32,
    }
}

const _: () = assert!(std::mem::size_of::<GpuFrame>() == 144);
const _: () = assert!(std::mem::size_of::<GpuPush>() == 96);
const _: () = assert!(std::mem::size_of::<GpuPathParams>() == 64);
const _: () = assert!(std::mem::size_of::<GpuRay>() == 32);
const _: () = assert!(std::mem::size_of::<GpuHit>() == 32);
