//! Binned SAH builder (Wald 2007, "On fast construction of SAH-based bounding volume
//! hierarchies", IEEE Symposium on Interactive Ray Tracing).
//!
//! The surface area heuristic (Goldsmith & Salmon 1987; MacDonald & Booth 1990) estimates the cost
//! of a node split into L and R as
//!
//!   C = C_trav + (A_L * N_L + A_R * N_R) / A_parent * C_isect,
//!
//! where A is surface area (the chance that a random ray hitting the parent also hits the child)
//! and N is primitive count. Trying every primitive as a split plane (a full sweep) needs sorting;
//! Wald instead drops the centroids of a node into K equal-width bins per axis over the *centroid*
//! bounds, keeps a box and a count per bin, and evaluates only the K - 1 planes between bins with
//! two sweeps over the bins. A node then costs one O(N) binning pass plus one O(N) in-place
//! partition, independent of K, and the whole build is O(N log N).
//!
//! The knobs, all in [`BuildConfig`]:
//! - `sah_bins` (default 16, clamped to 2..=256 here): more bins find planes closer to the full
//!   sweep's optimum but cost O(K) per node in the sweep and 3K boxes of scratch to clear per
//!   node; Wald found 16 bins already close to the full sweep's quality.
//! - `traversal_cost` / `intersection_cost` (defaults 1.0 / 1.0): they never change which plane
//!   wins, only whether splitting beats a leaf, and only their ratio matters there; a larger
//!   traversal cost makes leaves cheaper relative to splitting, so the builder stops earlier and
//!   trees get shallower with fuller leaves.
//! - `max_leaf_size` (default 4, clamped to 1..=MAX_LEAF_SIZE): a node with more primitives is
//!   always split, even when the SAH would prefer a leaf; at or below it the SAH decides.

use std::borrow::Cow;

use glam::Vec3;

use crate::bvh::{Aabb, BuildConfig, Bvh, Node, NodeKind, MAX_LEAF_SIZE};

/// Fewer than 2 bins has no plane between bins; more than this buys nothing measurable and only
/// grows the per-node scratch that must be cleared.
const MAX_BINS: u32 = 256;

/// One node still to be built. Its box is already in `nodes[node].bounds` (the parent got it from
/// the bins for free); `centroid_bounds` was gathered while partitioning the parent.
struct Task {
    node: u32,
    begin: usize,
    end: usize,
    centroid_bounds: Aabb,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        count: 0,
    };
}

/// Maps a centroid coordinate on one axis to its bin: floor((c - min) * scale), clamped to the last
/// bin (Wald 2007, eq. 1). The scale is precomputed so binning is a subtract and a multiply.
#[derive(Clone, Copy)]
struct AxisBins {
    min: f32,
    scale: f32,
    /// False when the centroids do not spread along this axis: no plane separates them there.
    usable: bool,
}

impl AxisBins {
    fn new(lo: f32, hi: f32, bins: usize) -> Self {
        let extent = hi - lo;
        let scale = bins as f32 / extent;
        Self {
            min: lo,
            scale,
            usable: extent > 0.0 && scale.is_finite(),
        }
    }
    #[inline]
    fn bin(&self, c: f32, last: usize) -> usize {
        // `as usize` saturates (negatives and NaN become 0), and the `min` folds the maximum
        // centroid, which lands exactly on `bins`, into the last bin.
        (((c - self.min) * self.scale) as usize).min(last)
    }
}

/// The best plane found for a node.
struct Split {
    axis: usize,
    /// Primitives in bins `< bin` go left.
    bin: usize,
    /// A_L * N_L + A_R * N_R, i.e. the SAH cost's variable part without the division by A_parent.
    weighted_area: f32,
    /// |N_L - N_R|, the tie-breaker.
    imbalance: u32,
    left: Aabb,
    right: Aabb,
}

/// Scratch reused across nodes so the build allocates only its output.
struct Binner {
    bins: usize,
    /// 3 axes x `bins`.
    grid: Vec<Bin>,
    /// For the sweep: bounds and counts of bins `i..` on the current axis.
    suffix: Vec<Bin>,
}

/// Build a BVH with the binned SAH. `centroids[i]` is primitive `i`'s split position; if the slice
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
    let bins = config.sah_bins.clamp(2, MAX_BINS) as usize;
    let mut binner = Binner {
        bins,
        grid: vec![Bin::EMPTY; 3 * bins],
        suffix: vec![Bin::EMPTY; bins],
    };

    // `n` fits in u32 (clamped above), so every index below does too.
    let mut prims: Vec<u32> = (0..n as u32).collect();
    let (root_bounds, root_centroids) = range_bounds(&prims, boxes, &centroids);
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(leaf_size));
    nodes.push(Node {
        bounds: root_bounds,
        kind: NodeKind::Leaf { first: 0, count: 0 },
    });

    // An explicit stack instead of recursion: SAH splits can peel off a few primitives at a time,
    // so depth is not bounded by log n and must never overflow the call stack. Depth-first order
    // keeps a parent's left child right after it in `nodes`.
    let mut stack = vec![Task {
        node: 0,
        begin: 0,
        end: n,
        centroid_bounds: root_centroids,
    }];
    while let Some(task) = stack.pop() {
        let bounds = nodes[task.node as usize].bounds;
        let count = task.end - task.begin;
        let range = &mut prims[task.begin..task.end];
        let axes = [0, 1, 2].map(|a| {
            AxisBins::new(
                task.centroid_bounds.min[a],
                task.centroid_bounds.max[a],
                bins,
            )
        });
        let split = if count > 1 {
            binner.best_split(range, boxes, &centroids, &axes)
        } else {
            None
        };

        // Costs are compared multiplied through by A_parent, so a zero-area node (all boxes on a
        // line or a point) needs no division: C_leaf = N * C_isect against C_trav +
        // (A_L N_L + A_R N_R) / A_parent * C_isect.
        let area = bounds.area();
        let leaf_cost = count as f32 * config.intersection_cost * area;
        let make_leaf = count <= leaf_size
            && split.as_ref().map_or(true, |s| {
                leaf_cost
                    <= config.traversal_cost * area + s.weighted_area * config.intersection_cost
            });

        let children = if make_leaf {
            None
        } else if let Some(s) = split {
            let (mid, lc, rc) =
                partition(range, &centroids, s.axis, &axes[s.axis], s.bin, bins - 1);
            Some((mid, s.left, lc, s.right, rc))
        } else {
            // Centroids coincide on every axis (or no plane separated them) and the node is too
            // big for a leaf: split by index in half, which keeps the depth logarithmic.
            let mid = count / 2;
            let (lb, lc) = range_bounds(&range[..mid], boxes, &centroids);
            let (rb, rc) = range_bounds(&range[mid..], boxes, &centroids);
            Some((mid, lb, lc, rb, rc))
        };

        let kind = match children {
            None => NodeKind::Leaf {
                first: task.begin as u32,
                count: count as u32,
            },
            Some((mid, left_bounds, left_centroids, right_bounds, right_centroids)) => {
                let left = nodes.len() as u32;
                nodes.push(Node {
                    bounds: left_bounds,
                    kind: NodeKind::Leaf { first: 0, count: 0 },
                });
                nodes.push(Node {
                    bounds: right_bounds,
                    kind: NodeKind::Leaf { first: 0, count: 0 },
                });
                let mid = task.begin + mid;
                stack.push(Task {
                    node: left + 1,
                    begin: mid,
                    end: task.end,
                    centroid_bounds: right_centroids,
                });
                stack.push(Task {
                    node: left,
                    begin: task.begin,
                    end: mid,
                    centroid_bounds: left_centroids,
                });
                NodeKind::Interior {
                    left,
                    right: left + 1,
                }
            }
        };
        nodes[task.node as usize].kind = kind;
    }
    Bvh {
        nodes,
        prim_indices: prims,
    }
}

impl Binner {
    /// Bin the primitives on every usable axis and sweep the K - 1 planes between bins; `None`
    /// when no plane leaves primitives on both sides.
    fn best_split(
        &mut self,
        prims: &[u32],
        boxes: &[Aabb],
        centroids: &[Vec3],
        axes: &[AxisBins; 3],
    ) -> Option<Split> {
        let k = self.bins;
        let last = k - 1;
        self.grid.fill(Bin::EMPTY);
        for &p in prims {
            let (b, c) = (boxes[p as usize], centroids[p as usize]);
            for (axis, map) in axes.iter().enumerate() {
                if map.usable {
                    let bin = &mut self.grid[axis * k + map.bin(c[axis], last)];
                    bin.bounds = bin.bounds.union(&b);
                    bin.count += 1;
                }
            }
        }

        let mut best: Option<Split> = None;
        for (axis, map) in axes.iter().enumerate() {
            if !map.usable {
                continue;
            }
            let grid = &self.grid[axis * k..(axis + 1) * k];
            // Right-to-left: suffix[i] = union of bins i.. ; then left-to-right, the plane before
            // bin i has bins ..i on the left and suffix[i] on the right.
            let mut acc = Bin::EMPTY;
            for (s, g) in self.suffix.iter_mut().zip(grid).rev() {
                acc = Bin {
                    bounds: acc.bounds.union(&g.bounds),
                    count: acc.count + g.count,
                };
                *s = acc;
            }
            let mut left = Bin::EMPTY;
            for i in 1..k {
                left = Bin {
                    bounds: left.bounds.union(&grid[i - 1].bounds),
                    count: left.count + grid[i - 1].count,
                };
                let right = self.suffix[i];
                if left.count == 0 || right.count == 0 {
                    continue;
                }
                let weighted_area = left.bounds.area() * left.count as f32
                    + right.bounds.area() * right.count as f32;
                // Among planes of equal cost take the most balanced one. Ties are common exactly
                // where it matters: zero-area boxes (all on a line or a point) cost 0 everywhere,
                // and always taking the first plane would peel off one bin at a time and make
                // the tree as deep as the input is long.
                let imbalance = left.count.abs_diff(right.count);
                if best.as_ref().map_or(true, |b| {
                    weighted_area < b.weighted_area
                        || (weighted_area == b.weighted_area && imbalance < b.imbalance)
                }) {
                    best = Some(Split {
                        axis,
                        bin: i,
                        weighted_area,
                        imbalance,
                        left: left.bounds,
                        right: right.bounds,
                    });
                }
            }
        }
        best
    }
}

/// Partition `prims` in place so primitives whose centroid falls in a bin `< split_bin` come
/// first; returns the first right index and the left and right centroid bounds, gathered here so
/// the children need no extra pass. Uses the same `AxisBins::bin` as the binning pass, so the
/// counts agree with the ones the SAH was evaluated on.
fn partition(
    prims: &mut [u32],
    centroids: &[Vec3],
    axis: usize,
    map: &AxisBins,
    split_bin: usize,
    last: usize,
) -> (usize, Aabb, Aabb) {
    let (mut i, mut j) = (0, prims.len());
    let (mut lc, mut rc) = (Aabb::EMPTY, Aabb::EMPTY);
    while i < j {
        let c = centroids[prims[i] as usize];
        if map.bin(c[axis], last) < split_bin {
            lc = lc.grow(c);
            i += 1;
        } else {
            rc = rc.grow(c);
            j -= 1;
            prims.swap(i, j);
        }
    }
    (i, lc, rc)
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
    prims.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), &p| {
        (b.union(&boxes[p as usize]), c.grow(centroids[p as usize]))
    })
}
