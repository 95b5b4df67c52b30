//! Every struct that crosses to the GPU, and the flat arrays built from a scene and its BVH.
//!
//! Each struct here is `#[repr(C)]`, `Pod`, built from 4-byte scalars, with explicit padding
//! and a size assert. `shaders/include/layout.glsl` mirrors them field by field, and the test
//! `tests/layout.rs` checks the mirror against the compiled SPIR-V: nobody keeps them in sync
//! by hand.

pub mod compact;
pub mod constants;
pub mod cpu_trace;
pub mod flatten;
pub mod multi_order;
pub mod parent_link;
pub mod scene_buffers;
pub mod texture_atlas;
pub mod wide;

use bytemuck::{Pod, Zeroable};

/// A node of the threaded (escape-link) BVH2, in depth-first pre-order.
///
/// Traversal: test the box; on a hit, an interior node continues at the next node in the
/// array (its left child) and a leaf tests its triangles and continues at `escape`; on a
/// miss, continue at `escape`, the next node that is not a descendant. No stack is needed
/// (Smits 1998, "Efficiency issues for ray tracing").
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuNode {
    pub bmin: [f32; 3],
    /// Index of the next node after this subtree, or `NODE_NONE`.
    pub escape: u32,
    pub bmax: [f32; 3],
    /// (first triangle << LEAF_COUNT_BITS) | count; count 0 marks an interior node.
    pub leaf: u32,
}
const _: () = assert!(std::mem::size_of::<GpuNode>() == 32);

/// A node of the parent-linked BVH2 walked by the Hapala et al. 2011 state machine
/// (`parent_link.rs`). Siblings sit in pairs at indices (2k, 2k+1), k >= 1, so a node's sibling
/// is `index ^ 1`; the root is node 0 and node 1 is an unused (empty) filler.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuParentNode {
    pub bmin: [f32; 3],
    /// (parent index << 4) | (own split axis << 2) | parent's split axis. The split axis picks
    /// the near child: the even child of a pair is the one with the smaller centre on it.
    pub parent: u32,
    pub bmax: [f32; 3],
    /// Leaf: (first triangle << LEAF_COUNT_BITS) | count. Interior: (even child << LEAF_COUNT_BITS),
    /// count 0.
    pub leaf: u32,
}
const _: () = assert!(std::mem::size_of::<GpuParentNode>() == 32);

/// A node of the compact threaded BVH (`compact.rs`): the threaded layout's node in 16 bytes,
/// its box as 16-bit cells of a per-scene grid (`GpuPush::grid_origin`, `grid_scale`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuCompactNode {
    /// Cells of min x (low 16 bits) and min y (high 16 bits).
    pub min_xy: u32,
    /// Cells of min z (low) and max x (high).
    pub min_z_max_x: u32,
    /// Cells of max y (low) and max z (high).
    pub max_yz: u32,
    /// Interior: escape index (top bit clear; the node count past the end). Leaf: top bit set,
    /// then (first triangle << LEAF_COUNT_BITS) | count; a leaf's escape is the next node.
    pub link: u32,
}
const _: () = assert!(std::mem::size_of::<GpuCompactNode>() == 16);

/// A node of the wide (4-ary) BVH walked by `traverse_wide.glsl` (`wide.rs`): the boxes of
/// up to four children side by side (structure of arrays, so one node is eight RGBA32UI texels
/// and one visit tests four boxes), what each child is, and the link back to the parent.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuWideNode {
    /// Child boxes, one lane per slot; slots past the child count hold zeros and are never
    /// tested.
    pub min_x: [f32; 4],
    pub min_y: [f32; 4],
    pub min_z: [f32; 4],
    pub max_x: [f32; 4],
    pub max_y: [f32; 4],
    pub max_z: [f32; 4],
    /// Per slot: a leaf as (first triangle << LEAF_COUNT_BITS) | count, or an interior child
    /// as (its node index << LEAF_COUNT_BITS) with count 0.
    pub children: [u32; 4],
    /// The parent node's index, or `NODE_NONE` for the root.
    pub parent: u32,
    /// Child count | ordering axis << WIDE_INFO_AXIS_SHIFT | slot in the parent <<
    /// WIDE_INFO_SLOT_SHIFT. Slots are sorted by box centre along the ordering axis.
    pub info: u32,
    pub _pad0: u32,
    pub _pad1: u32,
}
const _: () = assert!(std::mem::size_of::<GpuWideNode>() == 128);

/// How the BVH is laid out for stackless traversal on the GPU. Each has its flatten code, its
/// CPU twin and its shader (`shaders/include/traverse_*.glsl`, picked by a `-D LAYOUT_*` define
/// per shader variant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum)]
pub enum LayoutKind {
    /// Threaded BVH2 with escape links (Smits 1998): one fixed child order, 32 B per node.
    #[default]
    Threaded,
    /// Six threaded orders of the same tree, one per dominant ray axis and sign, picked per ray:
    /// near-to-far without a stack, at 6x the node memory.
    MultiOrder,
    /// Parent links walked by the Hapala et al. 2011 state machine: ordered by the split axis
    /// per node (the node tests of an ordered stack traversal), 32 B per node.
    ParentLink,
    /// The threaded layout in 16 B per node: boxes rounded outwards to a 16-bit grid over the
    /// scene, one texel fetch per node; a ray may visit a few more nodes.
    Compact,
    /// A 4-ary BVH collapsed from the binary one: each visit tests four boxes (128 B per
    /// node), children in order along a per-node axis; going back up re-enters the parent.
    Wide,
}

impl LayoutKind {
    pub const ALL: [LayoutKind; 5] =
        [LayoutKind::Threaded, LayoutKind::MultiOrder, LayoutKind::ParentLink, LayoutKind::Compact, LayoutKind::Wide];

    /// The suffix of this layout's shader variants (`pipeline::variants`): "" for threaded, so
    /// a shader with no layout variants walks the default layout.
    pub fn variant_suffix(self) -> &'static str {
        match self {
            LayoutKind::Threaded => "",
            LayoutKind::MultiOrder => "_multi_order",
            LayoutKind::ParentLink => "_parent_link",
            LayoutKind::Compact => "_compact",
            LayoutKind::Wide => "_wide",
        }
    }

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            LayoutKind::Threaded => "threaded",
            LayoutKind::MultiOrder => "multi-order",
            LayoutKind::ParentLink => "parent-link",
            LayoutKind::Compact => "compact",
            LayoutKind::Wide => "wide",
        }
    }
}

/// A triangle in leaf order, with what intersection needs and nothing else.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    pub v0: [f32; 3],
    /// Primitive id: the index in `Scene::triangles`.
    pub prim: u32,
    pub v1: [f32; 3],
    pub _pad0: u32,
    pub v2: [f32; 3],
    pub _pad1: u32,
}
const _: () = assert!(std::mem::size_of::<GpuTriangle>() == 48);

/// Per-primitive shading data, indexed by primitive id.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuShading {
    /// Vertex normals (the geometric normal three times if the file has none).
    pub n0: [f32; 3],
    pub material: u32,
    pub n1: [f32; 3],
    pub _pad0: u32,
    pub n2: [f32; 3],
    pub _pad1: u32,
}
const _: () = assert!(std::mem::size_of::<GpuShading>() == 48);

/// A material as the shaders read it. See `scene::Material` for the meaning of each field.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 64);

/// One texture in the texel atlas (`BINDING_TEXELS`): texel (x, y) of this texture, row 0 the
/// top row of the image file, is `texels[offset + y * width + x]`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuTexture {
    pub offset: u32,
    pub width: u32,
    pub height: u32,
    pub _pad0: u32,
}
const _: () = assert!(std::mem::size_of::<GpuTexture>() == 16);

/// A triangle's vertex texture coordinates, by primitive id (zero if the file has none).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuUv {
    pub uv0: [f32; 2],
    pub uv1: [f32; 2],
    pub uv2: [f32; 2],
    pub _pad0: u32,
    pub _pad1: u32,
}
const _: () = assert!(std::mem::size_of::<GpuUv>() == 32);

/// A point, directional or spot light. See `scene::Light` for the units.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 3],
    /// `LIGHT_*`.
    pub kind: u32,
    /// Normalised; for a directional light, the direction toward the light.
    pub direction: [f32; 3],
    pub radius: f32,
    pub intensity: [f32; 3],
    pub _pad0: u32,
}
const _: () = assert!(std::mem::size_of::<GpuLight>() == 48);

/// An emissive triangle, for light sampling.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
const _: () = assert!(std::mem::size_of::<GpuEmitter>() == 64);

/// Per-render settings (uniform buffer, std140: every vec3 is followed by a 4-byte scalar).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
}
const _: () = assert!(std::mem::size_of::<GpuFrame>() == 112);

/// Per-dispatch values (push constants): which tile and which samples this dispatch renders.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
    /// The compact layout's grid (`compact::QuantGrid`); zero for the other layouts.
    pub grid_origin: [f32; 3],
    pub _pad0: u32,
    pub grid_scale: [f32; 3],
    pub _pad1: u32,
}
const _: () = assert!(std::mem::size_of::<GpuPush>() == 64);

/// A ray for batch queries: origin, tmin, direction, tmax (the `vkrt trace` file layout).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuRay {
    pub origin: [f32; 3],
    pub tmin: f32,
    pub direction: [f32; 3],
    pub tmax: f32,
}
const _: () = assert!(std::mem::size_of::<GpuRay>() == 32);

/// The result of a batch query, with traversal counters.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
const _: () = assert!(std::mem::size_of::<GpuHit>() == 32);

/// One entry of the light-selection alias table (Vose 1991, "A linear algorithm for
/// generating random numbers with a given distribution"): pick entry i uniformly, keep it if
/// u < `threshold`, else take `alias`. `pmf` is the probability of selecting entry i itself.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuLightPick {
    pub pmf: f32,
    pub alias: u32,
    pub threshold: f32,
    pub _pad0: u32,
}
const _: () = assert!(std::mem::size_of::<GpuLightPick>() == 16);

/// The path tracer's per-render settings (uniform buffer, std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
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
    /// 1 / the total selection weight (see `integrator::light_table`), so that an emissive
    /// triangle's area density is pi * mean(Ke) * inv_total_weight.
    pub inv_total_weight: f32,
    /// Pixels in a row that draw the same sample numbers (1: every pixel its own; see
    /// `PathSettings::coherence`).
    pub coherence: u32,
    /// Adaptive sampling: the pixels per block (`integrator::adaptive::BlockGrid`), each block
    /// taking the samples BINDING_BLOCK_SAMPLES gives it; 0: every pixel takes the push
    /// constants' `sample_base .. + sample_count`.
    pub adaptive: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub _pad2: u32,
}
const _: () = assert!(std::mem::size_of::<GpuPathParams>() == 48);
