// The stackless BVH layouts, in one list. `crate::accel` gives each its flatten step and CPU
// twin; host/build.rs includes this file on its own (so it imports nothing) and compiles every
// tracing shader once per entry, with the entry's define, walking the entry's GLSL file.
//
// Adding a layout: a row here and a variant of `LayoutKind`; its node struct in
// `gpu_abi/nodes.rs` and `shaders/include/gpu_abi.glsl`; its file in `accel/` (flatten + CPU
// twin) with one arm in `accel::flatten`; its walk in `shaders/include/traverse_<id>.glsl`.
// The shader variants, the layout and texel-decode probes and every agreement test follow
// from the list.

/// How the BVH is laid out for stackless traversal on the GPU (see [`LAYOUTS`] for each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum LayoutKind {
    #[default]
    Threaded,
    MultiOrder,
    ParentLink,
    Compact,
    Wide,
}

/// What the command line, the build and the pipelines know of a layout.
pub struct LayoutInfo {
    pub kind: LayoutKind,
    /// The name on the command line and in reports.
    pub name: &'static str,
    /// Identifier in shader variant and file names: `traverse_<id>.glsl`, `path_<id>`.
    pub id: &'static str,
    /// The define that selects it in a shader variant (`shaders/include/traverse.glsl`).
    pub define: &'static str,
    /// Its node struct, in `gpu_abi` and `gpu_abi.glsl`.
    pub node_struct: &'static str,
    /// One line for `--help`.
    pub help: &'static str,
    /// The layout whose `_two_level_<id>` shader build walks a two-level BVH (`accel::two_level`)
    /// with both levels in this one: itself, or one whose walk covers it (the multi-order
    /// layout's orders are data to the threaded build); None where the levels cannot be laid
    /// out in it (`accel::two_level::LAYOUTS` says why).
    pub two_level: Option<LayoutKind>,
}

/// Every layout, in `LayoutKind` order.
pub const LAYOUTS: [LayoutInfo; 5] = [
    LayoutInfo {
        kind: LayoutKind::Threaded,
        name: "threaded",
        id: "threaded",
        define: "LAYOUT_THREADED",
        node_struct: "GpuNode",
        help: "Threaded BVH2 with escape links (Smits 1998): one fixed child order, 32 B per node",
        two_level: Some(LayoutKind::Threaded),
    },
    LayoutInfo {
        kind: LayoutKind::MultiOrder,
        name: "multi-order",
        id: "multi_order",
        define: "LAYOUT_MULTI_ORDER",
        node_struct: "GpuNode",
        help: "Six threaded orders of the tree, one per dominant ray axis and sign: near-to-far without a stack, 6x the node memory",
        two_level: Some(LayoutKind::Threaded),
    },
    LayoutInfo {
        kind: LayoutKind::ParentLink,
        name: "parent-link",
        id: "parent_link",
        define: "LAYOUT_PARENT_LINK",
        node_struct: "GpuParentNode",
        help: "Parent links walked by the Hapala et al. 2011 state machine: ordered by each node's split axis, 32 B per node",
        two_level: Some(LayoutKind::ParentLink),
    },
    LayoutInfo {
        kind: LayoutKind::Compact,
        name: "compact",
        id: "compact",
        define: "LAYOUT_COMPACT",
        node_struct: "GpuCompactNode",
        help: "The threaded layout in 16 B nodes: boxes rounded outwards to a 16-bit grid, one texel fetch per node",
        two_level: Some(LayoutKind::Compact),
    },
    LayoutInfo {
        kind: LayoutKind::Wide,
        name: "wide",
        id: "wide",
        define: "LAYOUT_WIDE",
        node_struct: "GpuWideNode",
        help: "A 4-ary BVH collapsed from the binary one: four boxes per visit, 128 B per node, children ordered per node",
        two_level: Some(LayoutKind::Wide),
    },
];

const _: () = {
    let mut i = 0;
    while i < LAYOUTS.len() {
        assert!(LAYOUTS[i].kind as usize == i, "LAYOUTS must be in LayoutKind order");
        i += 1;
    }
};

impl LayoutKind {
    pub const ALL: [LayoutKind; 5] = [LayoutKind::Threaded, LayoutKind::MultiOrder, LayoutKind::ParentLink, LayoutKind::Compact, LayoutKind::Wide];

    pub fn info(self) -> &'static LayoutInfo {
        &LAYOUTS[self as usize]
    }

    /// The name on the command line and in reports.
    pub fn name(self) -> &'static str {
        self.info().name
    }
}
