//! SAH cost of a finished tree, the usual single-number score of BVH quality.
//!
//! Under the surface area heuristic (Goldsmith & Salmon 1987; MacDonald & Booth 1990) a random
//! ray that hits the root hits a node with probability area(node) / area(root). The expected cost
//! of a ray is then the sum over interior nodes of that probability (one traversal step each) plus,
//! for leaves, that probability times the primitives tested. Traversal and intersection are both
//! weighted 1 here, the normalisation other libraries (e.g. tinybvh) report, so numbers compare
//! across libraries and independent of a builder's `BuildConfig` costs.

use crate::bvh::{Bvh, NodeKind};

/// sum over interior nodes of area(node) / area(root)
/// + sum over leaves of area(leaf) / area(root) * primitive count.
///
/// 0 for an empty tree. If the root has zero area (every box on one line or point), each node is
/// weighted 1 instead, the limit of the ratio as the scene shrinks uniformly, so the result stays
/// finite. Every node in `nodes` is counted; run `validate` first if the tree may be malformed.
pub fn sah_cost(bvh: &Bvh) -> f32 {
    let Some(root) = bvh.nodes.first() else {
        return 0.0;
    };
    let root_area = f64::from(root.bounds.area());
    // f64 sums: Conference-sized trees have ~10^5 terms, enough to lose digits in f32.
    let weight = |area: f32| {
        if root_area > 0.0 {
            f64::from(area) / root_area
        } else {
            1.0
        }
    };
    let total: f64 = bvh
        .nodes
        .iter()
        .map(|node| match node.kind {
            NodeKind::Interior { .. } => weight(node.bounds.area()),
            NodeKind::Leaf { count, .. } => weight(node.bounds.area()) * f64::from(count),
        })
        .sum();
    total as f32
}
