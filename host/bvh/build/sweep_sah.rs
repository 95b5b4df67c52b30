//! Full-sweep SAH builder: at every node, every split between consecutive centroids along each
//! axis is scored with the surface area heuristic, and the cheapest taken (MacDonald & Booth
//! 1990; the "sweep" form of Wald, Boulos & Shirley 2007, "Ray tracing deformable scenes using
//! dynamic bounding volume hierarchies", sec. 4.3).
//!
//! Trade-off: the best trees a top-down object-split builder makes (the binned builder only
//! tries K - 1 planes per axis), at 2-3x its build time. Sorting per node would cost
//! O(n log^2 n); instead the primitives are sorted once per axis, and each split partitions the
//! three sorted lists *stably* (by a side flag per primitive), so every list stays sorted and a
//! node costs O(n): one right-to-left pass for the suffix areas and one left-to-right sweep per
//! axis, then the stable partition. Memory: three index lists, one suffix-area array and a flag
//! per primitive.
//!
//! Knobs (`BuildConfig`): `traversal_cost`/`intersection_cost` decide when a leaf beats the best
//! split; `max_leaf_size` forces a split above it. `sah_bins` is unused.

use std::borrow::Cow;

use crate::geom::{Aabb, SimdAabb};
use glam::Vec3;

use crate::bvh::{BuildConfig, Bvh, Node, NodeKind, MAX_LEAF_SIZE};

/// One node still to be built: it covers positions `begin..end` of all three sorted lists.
struct Task {
    node: u32,
    begin: usize,
    end: usize,
}

/// The cheapest split of a node: the first `count` primitives of the list sorted on `axis` go
/// left.
struct Split {
    axis: usize,
    count: usize,
    /// A_L * N_L + A_R * N_R.
    weighted_area: f32,
    imbalance: usize,
    left: SimdAabb,
    right: SimdAabb,
}

/// Build a BVH with the full-sweep SAH. Centroids as in the other builders (box centres if the
/// slice does not match `boxes`).
pub fn build(boxes: &[Aabb], centroids: &[Vec3], config: &BuildConfig) -> Bvh {
    // See median.rs: u32 node indices cap the input at 2^31 primitives.
    let n = boxes.len().min(u32::MAX as usize / 2);
    if n == 0 {
        return Bvh::default();
    }
    let centroids: Cow<[Vec3]> = match centroids.get(..n) {
        Some(c) if centroids.len() == boxes.len() => Cow::Borrowed(c),
        _ => Cow::Owned(boxes.iter().take(n).map(Aabb::center).collect()),
    };
    let boxes: Vec<SimdAabb> = boxes[..n].iter().map(|&b| SimdAabb::from(b)).collect();
    let leaf_size = config.max_leaf_size.clamp(1, MAX_LEAF_SIZE) as usize;

    // One list per axis, sorted by centroid (ties by id, so the build is deterministic; NaN-free
    // input is the loader's job, and total_cmp keeps even NaN from panicking).
    let sorted: [Vec<u32>; 3] = [0, 1, 2].map(|axis| {
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_unstable_by(|&a, &b| centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis]).then(a.cmp(&b)));
        order
    });
    let mut sorted = sorted;
    let mut suffix = vec![0f32; n + 1];
    let mut goes_left = vec![false; n];
    let mut scratch = vec![0u32; n];

    let root_bounds = boxes.iter().fold(SimdAabb::EMPTY, |b, &o| b.union(o));
    let placeholder = NodeKind::Leaf { first: 0, count: 0 };
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(leaf_size));
    nodes.push(Node { bounds: Aabb::from(root_bounds), kind: placeholder });
    // Explicit stack: SAH trees can be deep (see binned_sah.rs).
    let mut stack = vec![Task { node: 0, begin: 0, end: n }];
    while let Some(Task { node, begin, end }) = stack.pop() {
        let count = end - begin;
        let area = nodes[node as usize].bounds.area();
        let split = if count > 1 { best_split(&sorted, begin, end, &boxes, &mut suffix) } else { None };
        // Compared multiplied through by A_parent, as in binned_sah.rs.
        let leaf_cost = count as f32 * config.intersection_cost * area;
        let make_leaf =
            count <= leaf_size && split.as_ref().map_or(true, |s| leaf_cost <= config.traversal_cost * area + s.weighted_area * config.intersection_cost);
        let split = match split {
            Some(s) if !make_leaf => s,
            _ => {
                // A leaf (a split always exists for count >= 2, so this is count <= leaf_size).
                nodes[node as usize].kind = NodeKind::Leaf { first: begin as u32, count: count as u32 };
                continue;
            }
        };
        let mid = begin + split.count;
        for &p in &sorted[split.axis][begin..mid] {
            goes_left[p as usize] = true;
        }
        for &p in &sorted[split.axis][mid..end] {
            goes_left[p as usize] = false;
        }
        for axis in (0..3).filter(|&a| a != split.axis) {
            stable_partition(&mut sorted[axis][begin..end], &goes_left, &mut scratch);
        }
        let left = nodes.len() as u32;
        nodes.push(Node { bounds: Aabb::from(split.left), kind: placeholder });
        nodes.push(Node { bounds: Aabb::from(split.right), kind: placeholder });
        stack.push(Task { node: left + 1, begin: mid, end });
        stack.push(Task { node: left, begin, end: mid });
        nodes[node as usize].kind = NodeKind::Interior { left, right: left + 1 };
    }
    // Any of the lists is the leaf order: all three hold each leaf's primitives in its range.
    let [prim_indices, _, _] = sorted;
    Bvh { nodes, prim_indices }
}

/// Score every split of positions `begin..end` on every axis; `None` only for one primitive.
fn best_split(sorted: &[Vec<u32>; 3], begin: usize, end: usize, boxes: &[SimdAabb], suffix: &mut [f32]) -> Option<Split> {
    let count = end - begin;
    let mut best: Option<Split> = None;
    for (axis, list) in sorted.iter().enumerate() {
        let list = &list[begin..end];
        // suffix[i] = area of the union of list[i..].
        let mut acc = SimdAabb::EMPTY;
        for i in (1..count).rev() {
            acc = acc.union(boxes[list[i] as usize]);
            suffix[i] = acc.area();
        }
        let mut left = SimdAabb::EMPTY;
        for i in 1..count {
            left = left.union(boxes[list[i - 1] as usize]);
            let weighted_area = left.area() * i as f32 + suffix[i] * (count - i) as f32;
            // Equal costs: take the most balanced split, so zero-area inputs (cost 0 everywhere)
            // still give logarithmic depth.
            let imbalance = i.abs_diff(count - i);
            if best.as_ref().map_or(true, |b| weighted_area < b.weighted_area || (weighted_area == b.weighted_area && imbalance < b.imbalance)) {
                best = Some(Split { axis, count: i, weighted_area, imbalance, left, right: SimdAabb::EMPTY });
            }
        }
    }
    // The right box was not kept during the sweeps (only its area); rebuild it once.
    if let Some(b) = best.as_mut() {
        let list = &sorted[b.axis][begin..end];
        b.right = list[b.count..].iter().fold(SimdAabb::EMPTY, |acc, &p| acc.union(boxes[p as usize]));
    }
    best
}

/// Reorder `list` so primitives flagged left come first, each side keeping its order.
fn stable_partition(list: &mut [u32], goes_left: &[bool], scratch: &mut [u32]) {
    let mut l = 0;
    let mut r = 0;
    let scratch = &mut scratch[..list.len()];
    for i in 0..list.len() {
        let p = list[i];
        if goes_left[p as usize] {
            list[l] = p;
            l += 1;
        } else {
            scratch[r] = p;
            r += 1;
        }
    }
    list[l..].copy_from_slice(&scratch[..r]);
}
