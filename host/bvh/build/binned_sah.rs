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

use glam::{UVec3, Vec3, Vec3A};

use crate::bvh::{Aabb, BuildConfig, Bvh, Node, NodeKind, MAX_LEAF_SIZE};

/// Fewer than 2 bins has no plane between bins; more than this buys nothing measurable and only
/// grows the per-node scratch that must be cleared and swept.
const MAX_BINS: u32 = 256;

/// A box in 16-byte lanes (`Vec3A` is SSE/NEON-backed), so a union is two SIMD min/max ops: the
/// binning loop, the hottest in the build, does three per primitive per level.
#[derive(Clone, Copy)]
struct Box3 {
    min: Vec3A,
    max: Vec3A,
}

impl Box3 {
    const EMPTY: Box3 = Box3 {
        min: Vec3A::INFINITY,
        max: Vec3A::NEG_INFINITY,
    };

    fn union(self, o: Box3) -> Box3 {
        Box3 {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    fn grow(self, p: Vec3A) -> Box3 {
        Box3 {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    /// Surface area; 0 for the empty box (its negative extent is clamped away).
    fn area(self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
    fn aabb(self) -> Aabb {
        Aabb {
            min: self.min.into(),
            max: self.max.into(),
        }
    }
}

/// A primitive's box, centroid and id in one record (the layout of Embree's `PrimRef`).
/// Partitioning moves the records themselves, not indices into `boxes`, so every pass over a node
/// reads memory sequentially instead of gathering from all over the input.
#[derive(Clone, Copy)]
struct PrimRef {
    bounds: Box3,
    centroid: Vec3,
    id: u32,
}

/// One node still to be built: `nodes[node]` covers `refs[begin..end]`. Its box is already in
/// `nodes[node].bounds` (the parent got it from the bins for free); `centroid_bounds` was gathered
/// while partitioning the parent.
struct Task {
    node: u32,
    begin: usize,
    end: usize,
    centroid_bounds: Box3,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Box3,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Box3::EMPTY,
        count: 0,
    };

    fn add(self, o: &Bin) -> Bin {
        Bin {
            bounds: self.bounds.union(o.bounds),
            count: self.count + o.count,
        }
    }
}

/// Maps a centroid to its bin on each axis: floor((c - min) * scale), clamped to the last bin
/// (Wald 2007, eq. 1). The scale is precomputed per node so binning is a subtract and a multiply
/// for all three axes at once.
struct Binning {
    min: Vec3A,
    scale: Vec3A,
    last: UVec3,
    /// False where the centroids do not spread along an axis: no plane separates them there.
    /// Such an axis gets scale 0, so everything lands in bin 0 and the sweep skips it.
    usable: [bool; 3],
}

impl Binning {
    fn new(centroid_bounds: &Box3, bins: usize) -> Self {
        let extent = centroid_bounds.max - centroid_bounds.min;
        let scale = Vec3A::splat(bins as f32) / extent;
        let usable = [0, 1, 2].map(|a| extent[a] > 0.0 && scale[a].is_finite());
        let scale = Vec3A::from_array([0, 1, 2].map(|a| if usable[a] { scale[a] } else { 0.0 }));
        Self {
            min: centroid_bounds.min,
            scale,
            last: UVec3::splat(bins as u32 - 1),
            usable,
        }
    }
    /// Bin index on each axis. The binning pass and the partition both call this, so they agree
    /// exactly on every primitive's side. `as` casts saturate (negatives and NaN become 0), and
    /// the `min` folds the largest centroid, which lands exactly on `bins`, into the last bin.
    #[inline]
    fn bins(&self, c: Vec3) -> UVec3 {
        ((Vec3A::from(c) - self.min) * self.scale)
            .as_uvec3()
            .min(self.last)
    }
}

/// The best plane found for a node.
struct Split {
    axis: usize,
    /// Primitives in bins `< bin` go left.
    bin: u32,
    /// A_L * N_L + A_R * N_R, i.e. the SAH cost's variable part without the division by A_parent.
    weighted_area: f32,
    /// |N_L - N_R|, the tie-breaker.
    imbalance: u32,
    left: Box3,
    right: Box3,
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
    // `n` fits in u32 (clamped above), so every index below does too.
    let mut refs: Vec<PrimRef> = boxes
        .iter()
        .zip(centroids.iter())
        .zip(0..n as u32)
        .map(|((b, &centroid), id)| PrimRef {
            bounds: Box3 {
                min: b.min.into(),
                max: b.max.into(),
            },
            centroid,
            id,
        })
        .collect();
    let leaf_size = config.max_leaf_size.clamp(1, MAX_LEAF_SIZE) as usize;
    let bins = config.sah_bins.clamp(2, MAX_BINS) as usize;
    let mut binner = Binner {
        bins,
        grid: vec![Bin::EMPTY; 3 * bins],
        suffix: vec![Bin::EMPTY; bins],
    };

    let (root_bounds, root_centroids) = range_bounds(&refs);
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(leaf_size));
    nodes.push(Node {
        bounds: root_bounds.aabb(),
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
        let range = &mut refs[task.begin..task.end];
        let binning = Binning::new(&task.centroid_bounds, bins);
        let split = if count > 1 {
            binner.best_split(range, &binning)
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
            let (mid, lc, rc) = partition(range, &binning, s.axis, s.bin);
            Some((mid, s.left, lc, s.right, rc))
        } else {
            // Centroids coincide on every axis (or no plane separated them) and the node is too
            // big for a leaf: split by index in half, which keeps the depth logarithmic.
            let mid = count / 2;
            let (lb, lc) = range_bounds(&range[..mid]);
            let (rb, rc) = range_bounds(&range[mid..]);
            Some((mid, lb, lc, rb, rc))
        };

        let kind = match children {
            None => NodeKind::Leaf {
                first: task.begin as u32,
                count: count as u32,
            },
            Some((mid, left_bounds, left_centroids, right_bounds, right_centroids)) => {
                let left = nodes.len() as u32;
                let placeholder = NodeKind::Leaf { first: 0, count: 0 };
                nodes.push(Node {
                    bounds: left_bounds.aabb(),
                    kind: placeholder,
                });
                nodes.push(Node {
                    bounds: right_bounds.aabb(),
                    kind: placeholder,
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
        prim_indices: refs.iter().map(|r| r.id).collect(),
    }
}

impl Binner {
    /// Bin the primitives and sweep the K - 1 planes between bins on every usable axis; `None`
    /// when no plane leaves primitives on both sides.
    fn best_split(&mut self, refs: &[PrimRef], binning: &Binning) -> Option<Split> {
        let k = self.bins;
        self.grid.fill(Bin::EMPTY);
        for r in refs {
            let b = binning.bins(r.centroid);
            // All three axes, unusable ones included (they all land in bin 0): cheaper than a
            // branch per axis in the hottest loop of the build.
            for axis in 0..3 {
                let bin = &mut self.grid[axis * k + b[axis] as usize];
                bin.bounds = bin.bounds.union(r.bounds);
                bin.count += 1;
            }
        }

        let mut best: Option<Split> = None;
        for axis in (0..3).filter(|&a| binning.usable[a]) {
            let grid = &self.grid[axis * k..(axis + 1) * k];
            // Right-to-left: suffix[i] = union of bins i.. ; then left-to-right, the plane before
            // bin i has bins ..i on the left and suffix[i] on the right.
            let mut acc = Bin::EMPTY;
            for (s, g) in self.suffix.iter_mut().zip(grid).rev() {
                acc = acc.add(g);
                *s = acc;
            }
            let mut left = Bin::EMPTY;
            for (i, (g, right)) in grid.iter().zip(&self.suffix[1..]).enumerate() {
                // After an empty bin the plane splits the same sets as the one before it.
                if g.count == 0 {
                    continue;
                }
                left = left.add(g);
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
                    let bin = i as u32 + 1;
                    best = Some(Split {
                        axis,
                        bin,
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

/// Partition `refs` in place so primitives whose centroid falls in a bin `< split_bin` on `axis`
/// come first; returns the first right index and the left and right centroid bounds, gathered
/// here so the children need no extra pass.
fn partition(
    refs: &mut [PrimRef],
    binning: &Binning,
    axis: usize,
    split_bin: u32,
) -> (usize, Box3, Box3) {
    let (mut i, mut j) = (0, refs.len());
    let (mut lc, mut rc) = (Box3::EMPTY, Box3::EMPTY);
    while i < j {
        let c = refs[i].centroid;
        if binning.bins(c)[axis] < split_bin {
            lc = lc.grow(c.into());
            i += 1;
        } else {
            rc = rc.grow(c.into());
            j -= 1;
            refs.swap(i, j);
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
fn range_bounds(refs: &[PrimRef]) -> (Box3, Box3) {
    refs.iter().fold((Box3::EMPTY, Box3::EMPTY), |(b, c), r| {
        (b.union(r.bounds), c.grow(r.centroid.into()))
    })
}
