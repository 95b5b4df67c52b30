//! Shape statistics of a tree, for the bench and the tests' reports.

use crate::bvh::{sah::sah_cost, Bvh, NodeKind};

/// Summary of a [`Bvh`]'s shape. All zero for an empty tree.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BvhStats {
    /// Nodes reachable from the root, interior and leaf.
    pub nodes: usize,
    pub leaves: usize,
    /// Edges on the longest root-to-leaf path (a root that is a leaf has depth 0). A stack-based
    /// traversal needs at most this many entries; stackless ones don't care.
    pub max_depth: usize,
    /// Primitives in the fullest leaf.
    pub max_leaf_size: u32,
    /// Mean primitives per leaf.
    pub avg_leaf_size: f32,
    /// See [`crate::bvh::sah::sah_cost`].
    pub sah_cost: f32,
}

/// Walk the tree from the root and summarise it. The walk stops after `nodes.len()` visits, so a
/// malformed tree (a cycle) cannot make it loop forever; `validate` is what reports such trees.
pub fn stats(bvh: &Bvh) -> BvhStats {
    let mut s = BvhStats { sah_cost: sah_cost(bvh), ..BvhStats::default() };
    if bvh.nodes.is_empty() {
        return s;
    }
    let mut prims = 0u64;
    // Explicit stack of (node, depth): deep trees must not overflow the call stack.
    let mut stack = vec![(0usize, 0usize)];
    while let Some((i, depth)) = stack.pop() {
        let Some(node) = bvh.nodes.get(i) else {
            continue;
        };
        if s.nodes >= bvh.nodes.len() {
            break;
        }
        s.nodes += 1;
        s.max_depth = s.max_depth.max(depth);
        match node.kind {
            NodeKind::Interior { left, right } => {
                stack.push((right as usize, depth + 1));
                stack.push((left as usize, depth + 1));
            }
            NodeKind::Leaf { count, .. } => {
                s.leaves += 1;
                s.max_leaf_size = s.max_leaf_size.max(count);
                prims += u64::from(count);
            }
        }
    }
    if s.leaves > 0 {
        s.avg_leaf_size = (prims as f64 / s.leaves as f64) as f32;
    }
    s
}
