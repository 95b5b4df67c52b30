//! The threaded layout (Smits 1998, "Efficiency issues for ray tracing"): the binary BVH in
//! depth-first pre-order, each node with an escape link to the next node outside its subtree.
//! A box hit on an interior node continues at the next node (its first child); anything else
//! continues at the escape link. No stack, one fixed child order, 32 B per node (`GpuNode`).
//! Shader: `shaders/include/traverse_threaded.glsl`.
//!
//! The multi-order layout walks six such arrays (`multi_order`), and the compact layout packs
//! this one into 16-byte nodes (`compact`).

use super::intersect::{intersect_box, RayPre};
use super::leaf::{leaf_count, miss, test_leaf};
use super::{node_array, LayoutKind};
use crate::bvh::{Bvh, NodeKind};
use crate::gpu_abi::constants::{LEAF_COUNT_BITS, NODE_NONE};
use crate::gpu_abi::{GpuHit, GpuNode, GpuRay, GpuTriangle};
use glam::Vec3;

node_array!(Threaded, GpuNode, LayoutKind::Threaded, "The threaded node array.");

/// A threaded layout in pre-order, visiting the children of each interior node in the order
/// `order(node, left, right)` returns. Each node's escape link is the index just past its
/// subtree, offset by `base` (where this array will start in a concatenation), or NODE_NONE
/// past the end.
pub fn threaded(bvh: &Bvh, order: impl Fn(usize, u32, u32) -> (u32, u32), base: u32) -> Vec<GpuNode> {
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
pub fn flatten(bvh: &Bvh) -> Vec<GpuNode> {
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

/// `traverse` in traverse_threaded.glsl: closest hit (or, with `any_hit`, the first hit found)
/// along the ray, walking the threaded BVH from the root.
pub fn trace(nodes: &[GpuNode], tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
    trace_threaded_from(nodes, 0, tris, &RayPre::new(ray), ray.tmax, any_hit)
}

/// `traverse_threaded_from`: walk a threaded node array from `start` until an escape link says
/// NODE_NONE. Closest-hit queries shrink tmax to the best hit, so the box test skips every node
/// whose entry distance exceeds it.
pub fn trace_threaded_from(nodes: &[GpuNode], start: u32, tris: &[GpuTriangle], r: &RayPre, tmax: f32, any_hit: bool) -> GpuHit {
    let mut hit = miss();
    let mut tmax = tmax;
    let mut index = if (start as usize) < nodes.len() { start } else { NODE_NONE };
    while let Some(node) = nodes.get(index as usize) {
        hit.nodes_visited += 1;
        if intersect_box(r, Vec3::from(node.bmin), Vec3::from(node.bmax), tmax).is_none() {
            index = node.escape;
            continue;
        }
        if leaf_count(node.leaf) == 0 {
            index += 1;
            continue;
        }
        if test_leaf(node.leaf, tris, r, &mut tmax, &mut hit, any_hit) && any_hit {
            return hit;
        }
        index = node.escape;
    }
    hit
}
