//! The BVH arrays as the shaders walk them: one node type per stackless layout (each layout's
//! flatten step and CPU twin are in `crate::accel`), and the triangles in leaf order that every
//! layout shares.

gpu_structs! {
    /// A node of the threaded (escape-link) BVH2, in depth-first pre-order.
    ///
    /// Traversal: test the box; on a hit, an interior node continues at the next node in the
    /// array (its left child) and a leaf tests its triangles and continues at `escape`; on a
    /// miss, continue at `escape`, the next node that is not a descendant. No stack is needed
    /// (Smits 1998, "Efficiency issues for ray tracing").
    pub struct GpuNode {
        pub bmin: [f32; 3],
        /// Index of the next node after this subtree, or `NODE_NONE`.
        pub escape: u32,
        pub bmax: [f32; 3],
        /// (first triangle << LEAF_COUNT_BITS) | count; count 0 marks an interior node.
        pub leaf: u32,
    }

    /// A node of the parent-linked BVH2 walked by the Hapala et al. 2011 state machine
    /// (`crate::accel::parent_link`). Siblings sit in pairs at indices (2k, 2k+1), k >= 1, so a node's sibling
    /// is `index ^ 1`; the root is node 0 and node 1 is an unused (empty) filler.
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

    /// A node of the compact threaded BVH (`crate::accel::compact`): the threaded layout's node in 16 bytes,
    /// its box as 16-bit cells of a per-scene grid (`GpuPush::grid_origin`, `grid_scale`).
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

    /// A node of the wide (4-ary) BVH walked by `traverse_wide.glsl` (`crate::accel::wide`): the boxes of
    /// up to four children side by side (structure of arrays, so one node is eight RGBA32UI texels
    /// and one visit tests four boxes), what each child is, and the link back to the parent.
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

    /// A triangle in leaf order, with what intersection needs and nothing else.
    pub struct GpuTriangle {
        pub v0: [f32; 3],
        /// Primitive id: the index in `Scene::triangles` (in a two-level BVH, where the
        /// triangle is one of a mesh's, relative to its instance's `prim_base`).
        pub prim: u32,
        pub v1: [f32; 3],
        /// In a two-level BVH: the triangle's entry in its mesh's shading data (relative to its
        /// instance's `shading_base`). 0 in the one-level layouts, whose shading data is by
        /// primitive id.
        pub shading: u32,
        pub v2: [f32; 3],
        pub _pad1: u32,
    }

    /// An instance of a two-level BVH (`crate::accel::two_level`): what a top-level leaf names.
    /// The walk takes the ray into object space by `world_to_object` (direction not
    /// renormalised, so that t stays the world ray's), walks the mesh's tree from `root`, and
    /// adds `prim_base` to the mesh-local primitive id it hits.
    pub struct GpuInstance {
        /// The world-to-object transform's three rows: object = rows * (world, 1).
        pub world_to_object: [[f32; 4]; 3],
        /// The object-to-world transform's rows: where shading puts a hit triangle's vertices.
        pub object_to_world: [[f32; 4]; 3],
        /// The mesh's bottom-level root in the node array.
        pub root: u32,
        /// Primitive id of this copy's first triangle (`Scene::triangles`).
        pub prim_base: u32,
        /// `INSTANCE_MIRRORED` where the transform mirrors: the copy's second and third
        /// vertices are swapped, so are the hit's barycentrics.
        pub flags: u32,
        /// Where its mesh's shading data starts (BINDING_SHADING, BINDING_UVS,
        /// BINDING_TANGENTS hold one block per mesh, in object space).
        pub shading_base: u32,
        /// The compact layout's grid of the mesh's tree (`crate::accel::compact::QuantGrid`,
        /// over its root box in object space); zero in the other layouts.
        pub grid_origin: [f32; 3],
        /// Nodes per order of the mesh's tree where it is laid out in the multi-order layout's
        /// six orders (order `k` starts at `root + k * order_nodes`); 0 in the others.
        pub order_nodes: u32,
        pub grid_scale: [f32; 3],
        /// Where the mesh's tree ends in the compact layout (`root` plus its nodes: its walk
        /// ends there); 0 in the others.
        pub node_end: u32,
    }
}

const _: () = assert!(std::mem::size_of::<GpuNode>() == 32);
const _: () = assert!(std::mem::size_of::<GpuParentNode>() == 32);
const _: () = assert!(std::mem::size_of::<GpuCompactNode>() == 16);
const _: () = assert!(std::mem::size_of::<GpuWideNode>() == 128);
const _: () = assert!(std::mem::size_of::<GpuTriangle>() == 48);
const _: () = assert!(std::mem::size_of::<GpuInstance>() == 144);
