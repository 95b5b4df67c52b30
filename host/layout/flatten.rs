//! Flatten a [`Bvh`] into the arrays the shaders walk: the triangles in leaf order (shared by
//! every layout) and the nodes of the chosen [`LayoutKind`]. The threaded layout is built here;
//! the others live in `multi_order.rs`, `parent_link.rs`, `compact.rs` and `wide.rs`.

use super::constants::{LEAF_COUNT_BITS, NODE_NONE};
use super::compact::{self, QuantGrid};
use super::{cpu_trace, multi_order, parent_link, wide, GpuCompactNode, GpuHit, GpuNode, GpuParentNode, GpuRay, GpuTriangle, GpuWideNode, LayoutKind};
use crate::bvh::{Bvh, NodeKind};
use crate::scene::Triangle;

/// The node array of one layout.
#[derive(Debug, Clone, PartialEq)]
pub enum FlatNodes {
    /// Depth-first pre-order with escape links.
    Threaded(Vec<GpuNode>),
    /// Six threaded orders, `len / 6` nodes each, concatenated (order = 2 * axis + negative).
    MultiOrder(Vec<GpuNode>),
    /// Sibling pairs with parent links.
    ParentLink(Vec<GpuParentNode>),
    /// The threaded order in 16-byte nodes, and the grid their boxes are quantised to.
    Compact(Vec<GpuCompactNode>, QuantGrid),
    /// 4-ary nodes, depth first.
    Wide(Vec<GpuWideNode>),
}

impl Default for FlatNodes {
    fn default() -> Self {
        FlatNodes::Threaded(Vec::new())
    }
}

/// The flat arrays of one layout: nodes, and the triangles reordered so that each leaf's
/// triangles are contiguous.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlatBvh {
    pub nodes: FlatNodes,
    pub triangles: Vec<GpuTriangle>,
}

impl FlatBvh {
    pub fn layout(&self) -> LayoutKind {
        match self.nodes {
            FlatNodes::Threaded(_) => LayoutKind::Threaded,
            FlatNodes::MultiOrder(_) => LayoutKind::MultiOrder,
            FlatNodes::ParentLink(_) => LayoutKind::ParentLink,
            FlatNodes::Compact(..) => LayoutKind::Compact,
            FlatNodes::Wide(_) => LayoutKind::Wide,
        }
    }
    /// The node array as uploaded to the GPU.
    pub fn node_bytes(&self) -> &[u8] {
        match &self.nodes {
            FlatNodes::Threaded(n) | FlatNodes::MultiOrder(n) => bytemuck::cast_slice(n),
            FlatNodes::ParentLink(n) => bytemuck::cast_slice(n),
            FlatNodes::Compact(n, _) => bytemuck::cast_slice(n),
            FlatNodes::Wide(n) => bytemuck::cast_slice(n),
        }
    }
    /// The compact layout's grid; zero for the others.
    pub fn grid(&self) -> QuantGrid {
        match &self.nodes {
            FlatNodes::Compact(_, grid) => *grid,
            _ => QuantGrid::default(),
        }
    }
    /// Entries in the node array (for the multi-order layout, all six orders).
    pub fn node_count(&self) -> usize {
        match &self.nodes {
            FlatNodes::Threaded(n) | FlatNodes::MultiOrder(n) => n.len(),
            FlatNodes::ParentLink(n) => n.len(),
            FlatNodes::Compact(n, _) => n.len(),
            FlatNodes::Wide(n) => n.len(),
        }
    }
    /// Bytes the node and triangle arrays occupy on the GPU.
    pub fn bytes(&self) -> usize {
        self.node_bytes().len() + std::mem::size_of_val(self.triangles.as_slice())
    }
    /// The CPU twin of this layout's shader: same hit, same counters.
    pub fn trace(&self, ray: &GpuRay, any_hit: bool) -> GpuHit {
        match &self.nodes {
            FlatNodes::Threaded(n) => cpu_trace::trace(n, &self.triangles, ray, any_hit),
            FlatNodes::MultiOrder(n) => multi_order::trace(n, &self.triangles, ray, any_hit),
            FlatNodes::ParentLink(n) => parent_link::trace(n, &self.triangles, ray, any_hit),
            FlatNodes::Compact(n, grid) => compact::trace(n, grid, &self.triangles, ray, any_hit),
            FlatNodes::Wide(n) => wide::trace(n, &self.triangles, ray, any_hit),
        }
    }
}

/// The largest triangle count the leaf encoding can address.
pub const MAX_FLAT_TRIANGLES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// Lay `bvh` out as `layout`.
pub fn flatten_as(bvh: &Bvh, tris: &[Triangle], layout: LayoutKind) -> anyhow::Result<FlatBvh> {
    let triangles = leaf_order_triangles(bvh, tris)?;
    let nodes = match layout {
        LayoutKind::Threaded => FlatNodes::Threaded(threaded_in_tree_order(bvh)),
        LayoutKind::MultiOrder => FlatNodes::MultiOrder(multi_order::flatten(bvh)),
        LayoutKind::ParentLink => FlatNodes::ParentLink(parent_link::flatten(bvh)?),
        LayoutKind::Compact => {
            let (nodes, grid) = compact::from_threaded(&threaded_in_tree_order(bvh))?;
            FlatNodes::Compact(nodes, grid)
        }
        LayoutKind::Wide => FlatNodes::Wide(wide::flatten(bvh)?),
    };
    Ok(FlatBvh { nodes, triangles })
}

/// Lay `bvh` out as the threaded layout (the default).
pub fn flatten(bvh: &Bvh, tris: &[Triangle]) -> anyhow::Result<FlatBvh> {
    flatten_as(bvh, tris, LayoutKind::Threaded)
}

/// The triangles in `prim_indices` order, so a leaf's `first..first + count` indexes them.
fn leaf_order_triangles(bvh: &Bvh, tris: &[Triangle]) -> anyhow::Result<Vec<GpuTriangle>> {
    if tris.len() > MAX_FLAT_TRIANGLES {
        anyhow::bail!("scene has {} triangles; the flat layouts address at most {MAX_FLAT_TRIANGLES}", tris.len());
    }
    bvh.prim_indices
        .iter()
        .map(|&prim| {
            let t = tris
                .get(prim as usize)
                .ok_or_else(|| anyhow::anyhow!("BVH names primitive {prim} of {} triangles", tris.len()))?;
            Ok(GpuTriangle {
                v0: t.p[0].to_array(),
                prim,
                v1: t.p[1].to_array(),
                _pad0: 0,
                v2: t.p[2].to_array(),
                _pad1: 0,
            })
        })
        .collect()
}

/// A threaded layout in pre-order, visiting the children of each interior node in the order
/// `order(node, left, right)` returns. Each node's escape link is the index just past its
/// subtree, offset by `base` (where this array will start in a concatenation), or NODE_NONE
/// past the end.
pub(super) fn threaded(bvh: &Bvh, order: impl Fn(usize, u32, u32) -> (u32, u32), base: u32) -> Vec<GpuNode> {
    let count = bvh.nodes.len();
    let mut nodes = Vec::with_capacity(count);
    if count == 0 {
        return nodes;
    }
    // In pre-order a subtree occupies a contiguous run of indices, so a node's escape link is
    // its own index plus the size of its subtree; sizes do not depend on the child order.
    let preorder = preorder(bvh, &order);
    let mut subtree = vec![1u32; count];
    for &src in preorder.iter().rev() {
        if let NodeKind::Interior { left, right } = bvh.nodes[src as usize].kind {
            subtree[src as usize] = 1 + subtree[left as usize] + subtree[right as usize];
        }
    }
    for (index, &src) in preorder.iter().enumerate() {
        let node = &bvh.nodes[src as usize];
        let end = index as u32 + subtree[src as usize];
        let escape = if end as usize >= count { NODE_NONE } else { base + end };
        let leaf = match node.kind {
            NodeKind::Leaf { first, count } => (first << LEAF_COUNT_BITS) | count,
            NodeKind::Interior { .. } => 0,
        };
        nodes.push(GpuNode { bmin: node.bounds.min.to_array(), escape, bmax: node.bounds.max.to_array(), leaf });
    }
    nodes
}

/// The threaded layout with each node's children in the tree's own (left, right) order: the
/// default layout, and the order the compact layout packs.
fn threaded_in_tree_order(bvh: &Bvh) -> Vec<GpuNode> {
    threaded(bvh, |_, left, right| (left, right), 0)
}

/// Node ids in depth-first pre-order, children in the order `order` gives.
fn preorder(bvh: &Bvh, order: &impl Fn(usize, u32, u32) -> (u32, u32)) -> Vec<u32> {
    let mut out = Vec::with_capacity(bvh.nodes.len());
    let mut stack = vec![0u32];
    while let Some(src) = stack.pop() {
        out.push(src);
        if let NodeKind::Interior { left, right } = bvh.nodes[src as usize].kind {
            let (first, second) = order(src as usize, left, right);
            stack.push(second);
            stack.push(first);
        }
    }
    out
}
