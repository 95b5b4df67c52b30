//! Flatten a [`Bvh`] into the threaded layout the shaders walk.

use super::constants::{LEAF_COUNT_BITS, NODE_NONE};
use super::{GpuNode, GpuTriangle};
use crate::bvh::{Bvh, NodeKind};
use crate::scene::Triangle;

/// The arrays of the threaded BVH2: nodes in depth-first pre-order with escape links, and the
/// triangles reordered so that each leaf's triangles are contiguous.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlatBvh {
    pub nodes: Vec<GpuNode>,
    pub triangles: Vec<GpuTriangle>,
}

impl FlatBvh {
    /// Bytes the two arrays occupy on the GPU.
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice()) + std::mem::size_of_val(self.triangles.as_slice())
    }
}

/// The largest triangle count the leaf encoding can address.
pub const MAX_FLAT_TRIANGLES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// Lay `bvh` out in pre-order. Interior nodes are followed by their left subtree, then their
/// right subtree; each node's escape link is the index just past its subtree.
pub fn flatten(bvh: &Bvh, tris: &[Triangle]) -> anyhow::Result<FlatBvh> {
    if tris.len() > MAX_FLAT_TRIANGLES {
        anyhow::bail!(
            "scene has {} triangles; the threaded layout addresses at most {MAX_FLAT_TRIANGLES}",
            tris.len()
        );
    }
    let triangles: Vec<GpuTriangle> = bvh
        .prim_indices
        .iter()
        .map(|&prim| {
            let t = &tris[prim as usize];
            GpuTriangle {
                v0: t.p[0].to_array(),
                prim,
                v1: t.p[1].to_array(),
                _pad0: 0,
                v2: t.p[2].to_array(),
                _pad1: 0,
            }
        })
        .collect();
    let count = bvh.nodes.len();
    let mut nodes = Vec::with_capacity(count);
    if count == 0 {
        return Ok(FlatBvh { nodes, triangles });
    }
    // In pre-order a subtree occupies a contiguous run of indices, so a node's escape link is
    // its own index plus the size of its subtree. Sizes first (children before parents via a
    // reversed pre-order), then the emission walk.
    let preorder = preorder(bvh);
    let mut subtree = vec![1u32; count];
    for &src in preorder.iter().rev() {
        if let NodeKind::Interior { left, right } = bvh.nodes[src as usize].kind {
            subtree[src as usize] = 1 + subtree[left as usize] + subtree[right as usize];
        }
    }
    for (index, &src) in preorder.iter().enumerate() {
        let node = &bvh.nodes[src as usize];
        let end = index as u32 + subtree[src as usize];
        let escape = if end as usize >= count { NODE_NONE } else { end };
        let leaf = match node.kind {
            NodeKind::Leaf { first, count } => (first << LEAF_COUNT_BITS) | count,
            NodeKind::Interior { .. } => 0,
        };
        nodes.push(GpuNode { bmin: node.bounds.min.to_array(), escape, bmax: node.bounds.max.to_array(), leaf });
    }
    Ok(FlatBvh { nodes, triangles })
}

/// Node ids in depth-first pre-order, left child first.
fn preorder(bvh: &Bvh) -> Vec<u32> {
    let mut order = Vec::with_capacity(bvh.nodes.len());
    let mut stack = vec![0u32];
    while let Some(src) = stack.pop() {
        order.push(src);
        if let NodeKind::Interior { left, right } = bvh.nodes[src as usize].kind {
            stack.push(right);
            stack.push(left);
        }
    }
    order
}
