//! Median-split builder.
//!
//! At each node the primitives are split in half at the median centroid along the widest axis of
//! the node's *centroid* bounds (the "equal counts" split, PBRT 4th ed. §7.3.1). Using centroid
//! bounds rather than box bounds matters: a few long primitives can make the box bounds widest on
//! an axis along which the centroids hardly vary, and splitting there separates nothing.
//!
//! The tree is balanced (depth about log2(n / leaf size)), and each level costs O(n) for the bounds
//! pass plus O(n) expected for `select_nth_unstable_by` (introselect), so the build is O(n log n).
//! It ignores primitive sizes and empty space, so its trees score worse under the SAH than the
//! binned SAH builder's; it is here as the fast, predictable baseline.

use std::borrow::Cow;

use glam::Vec3;

use crate::bvh::{BuildConfig, Bvh, Node, NodeKind, MAX_LEAF_SIZE};
use crate::geom::Aabb;

/// One node still to be built: `nodes[node]` will cover `prim_indices[begin..end]`.
struct Task {
    node: u32,
    begin: usize,
    end: usize,
}

/// Build a BVH by median splits. `centroids[i]` is primitive `i`'s split position; if the slice
/// does not match `boxes` in length, box centres are used instead (a builder must not panic on
/// its input).
pub fn build(boxes: &[Aabb], centroids: &[Vec3], config: &BuildConfig) -> Bvh {
    // Node indices are u32 and a binary tree over n leaves has up to 2n - 1 nodes, so inputs
    // beyond 2^31 primitives cannot be represented. Such inputs (48 GiB of boxes) are out of
    // scope; rather than panic we leave the excess out, and `validate` reports them as missing.
    let n = boxes.len().min(u32::MAX as usize / 2);
    if n == 0 {
        return Bvh::default();
    }
    let centroids = matched_centroids(boxes, centroids, n);
    let boxes = &boxes[..n];
    let leaf_size = config.max_leaf_size.clamp(1, MAX_LEAF_SIZE) as usize;

    // `n` fits in u32 (clamped above), so every index below does too.
    let mut prims: Vec<u32> = (0..n as u32).collect();
    let placeholder = Node { bounds: Aabb::EMPTY, kind: NodeKind::Leaf { first: 0, count: 0 } };
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(leaf_size));
    nodes.push(placeholder);

    // An explicit stack instead of recursion: degenerate inputs must never overflow the call
    // stack. Depth-first order keeps a parent's left child right after it in `nodes`.
    let mut stack = vec![Task { node: 0, begin: 0, end: n }];
    while let Some(Task { node, begin, end }) = stack.pop() {
        let range = &mut prims[begin..end];
        let (bounds, centroid_bounds) = range_bounds(range, boxes, &centroids);
        let count = end - begin;
        let kind = if count <= leaf_size {
            NodeKind::Leaf { first: begin as u32, count: count as u32 }
        } else {
            let half = count / 2;
            let axis = centroid_bounds.widest_axis();
            // If the centroids coincide on every axis no position separates them; any half is as
            // good as another, so keep the index order and split by count alone.
            if centroid_bounds.extent()[axis] > 0.0 {
                range.select_nth_unstable_by(half, |&a, &b| centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis]));
            }
            let left = nodes.len() as u32;
            nodes.push(placeholder);
            nodes.push(placeholder);
            stack.push(Task { node: left + 1, begin: begin + half, end });
            stack.push(Task { node: left, begin, end: begin + half });
            NodeKind::Interior { left, right: left + 1 }
        };
        nodes[node as usize] = Node { bounds, kind };
    }
    Bvh { nodes, prim_indices: prims }
}

/// The first `n` centroids to split by: the caller's if they match `boxes` one to one, else the
/// box centres.
fn matched_centroids<'a>(boxes: &[Aabb], centroids: &'a [Vec3], n: usize) -> Cow<'a, [Vec3]> {
    match centroids.get(..n) {
        Some(c) if centroids.len() == boxes.len() => Cow::Borrowed(c),
        _ => Cow::Owned(boxes.iter().take(n).map(Aabb::center).collect()),
    }
}

/// Bounds of the primitives' boxes and of their centroids, in one pass.
fn range_bounds(prims: &[u32], boxes: &[Aabb], centroids: &[Vec3]) -> (Aabb, Aabb) {
    prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), &p| (b.union(&boxes[p as usize]), c.grow(centroids[p as usize])))
}
