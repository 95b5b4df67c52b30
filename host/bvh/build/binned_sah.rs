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
//! Where the time goes, and what it costs in quality: most nodes are small, so per-node overhead
//! (clearing and sweeping 3K bins) matters as much as the per-primitive binning pass. Nodes of at
//! most 4 primitives therefore try every split into two sets exactly (no bins; over half the
//! nodes), nodes of at most 64 use at most 8 bins, and larger ones `sah_bins`. Binning
//! alternates between two bin grids on large nodes, because neighbouring primitives mostly land
//! in the same bin and each update would wait for the previous one's store. Against 16 bins
//! everywhere this builds Conference about 1.6x faster at SAH 44.5 instead of 44.3 (8 bins
//! everywhere would be 52.7: the top of the tree needs the finer planes). docs/experiments/bvh-builders.md
//! has the numbers.
//!
//! The knobs, all in [`BuildConfig`]:
//! - `sah_bins` (default 16, clamped to 2..=256 here; nodes of at most 64 primitives use
//!   `min(sah_bins, 8)`): more bins find planes closer to the full sweep's optimum but cost O(K)
//!   per node in the sweep and 3K (large nodes: 6K) boxes of scratch to clear per node; Wald
//!   found 16 bins already close to the full sweep's quality.
//! - `traversal_cost` / `intersection_cost` (defaults 1.0 / 1.0): they never change which plane
//!   wins, only whether splitting beats a leaf, and only their ratio matters there; a larger
//!   traversal cost makes leaves cheaper relative to splitting, so the builder stops earlier and
//!   trees get shallower with fuller leaves.
//! - `max_leaf_size` (default 4, clamped to 1..=MAX_LEAF_SIZE): a node with more primitives is
//!   always split, even when the SAH would prefer a leaf; at or below it the SAH decides.

use std::borrow::Cow;

use crate::geom::{Aabb, SimdAabb};
use glam::{Vec3, Vec3A};

use crate::bvh::{BuildConfig, Bvh, Node, NodeKind, MAX_LEAF_SIZE};

/// Fewer than 2 bins has no plane between bins; more than this buys nothing measurable and only
/// grows the per-node scratch that must be cleared and swept.
const MAX_BINS: u32 = 256;

/// A primitive's box, centroid and id in one record (the layout of Embree's `PrimRef`).
/// Partitioning moves the records themselves, not indices into `boxes`, so every pass over a node
/// reads memory sequentially instead of gathering from all over the input.
#[derive(Clone, Copy)]
struct PrimRef {
    bounds: SimdAabb,
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
    centroid_bounds: SimdAabb,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: SimdAabb,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin { bounds: SimdAabb::EMPTY, count: 0 };

    fn add(self, o: &Bin) -> Bin {
        Bin { bounds: self.bounds.union(o.bounds), count: self.count + o.count }
    }
}

/// Maps a centroid to its bin on each axis: about floor((c - min) * scale), clamped to the bins
/// (Wald 2007, eq. 1). The scale is precomputed per node so binning is a handful of SIMD ops for
/// all three axes at once.
struct Binning {
    min: Vec3A,
    scale: Vec3A,
    /// 0.5 and bins - 0.5 on every axis: the clamp range before rounding (see [`Binning::bins`]).
    lo: Vec3A,
    hi: Vec3A,
    last: usize,
    /// False where the centroids do not spread along an axis: no plane separates them there.
    /// Such an axis gets scale 0, so everything lands in bin 0 and the sweep skips it.
    usable: [bool; 3],
}

/// 2^23 - 0.5: adding it to a float in [0.5, 2^22] leaves round(x - 0.5) in the low mantissa
/// bits (floats from 2^23 to 2^24 are the integers), the usual float-to-int trick without a
/// (saturating, scalar) `as` cast per lane.
const ROUND_MAGIC: f32 = 8_388_607.5;
/// The bit pattern of 2^23, subtracted to leave the integer.
const ROUND_MAGIC_BITS: u32 = 0x4B00_0000;

impl Binning {
    fn new(centroid_bounds: &SimdAabb, bins: usize) -> Self {
        let extent = centroid_bounds.max - centroid_bounds.min;
        let scale = Vec3A::splat(bins as f32) / extent;
        let usable = [0, 1, 2].map(|a| extent[a] > 0.0 && scale[a].is_finite());
        let scale = Vec3A::from_array([0, 1, 2].map(|a| if usable[a] { scale[a] } else { 0.0 }));
        Self { min: centroid_bounds.min, scale, lo: Vec3A::splat(0.5), hi: Vec3A::splat(bins as f32 - 0.5), last: bins - 1, usable }
    }
    /// Bin index on each axis. The binning pass and the partition both call this, so they agree
    /// exactly on every primitive's side. t = (c - min) * scale lies in [0, bins]; clamped to
    /// [0.5, bins - 0.5] and rounded after subtracting 0.5 it becomes a bin in 0..bins (floor(t)
    /// except that exact integers may round down, which only has to be monotone and the same
    /// for both callers). `max` and `min` map NaN to the clamp bounds; the final `min` keeps any
    /// index in range regardless.
    #[inline]
    fn bins(&self, c: Vec3A) -> [usize; 3] {
        // A change here must be mirrored in `bin`.
        let t = ((c - self.min) * self.scale).max(self.lo).min(self.hi) + Vec3A::splat(ROUND_MAGIC);
        t.to_array().map(|x| (x.to_bits().wrapping_sub(ROUND_MAGIC_BITS) as usize).min(self.last))
    }
    /// `bins(c)[axis]` from the centroid's coordinate on that axis alone, with the same float
    /// operations in scalar form, so the two agree bit for bit (scalar `f32::max`/`min` return
    /// the non-NaN operand, as SSE's `maxps`/`minps` do when only the first operand is NaN; a
    /// unit test checks the agreement).
    #[inline]
    fn bin(&self, c: f32, axis: usize) -> usize {
        let t = ((c - self.min[axis]) * self.scale[axis]).max(self.lo[axis]).min(self.hi[axis]) + ROUND_MAGIC;
        (t.to_bits().wrapping_sub(ROUND_MAGIC_BITS) as usize).min(self.last)
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
    left: SimdAabb,
    right: SimdAabb,
}

/// Scratch reused across nodes so the build allocates only its output.
struct Binner {
    /// `sah_bins`, clamped: the most bins a node uses.
    bins: usize,
    /// Two grids of 3 axes x `bins` (see [`Binner::best_split`]).
    grid: Vec<Bin>,
    /// For the sweep: bounds and counts of bins `i..` on the current axis.
    suffix: Vec<Bin>,
}

/// Nodes of at most this many primitives skip the bins and try every partition into two
/// non-empty sets (at most 7 for 4 primitives): cheaper than clearing and sweeping 3 x K bins,
/// and exact. Over half the nodes of a tree are this small.
const TINY_NODE: usize = 4;

/// Nodes of at most this many primitives use at most [`MEDIUM_BINS`] bins: the per-node sweep
/// and clearing, not the per-primitive binning, dominate their cost, and a plane error there
/// moves few primitives. 8 bins everywhere would cost Conference 52.7 SAH instead of 44.5.
const MEDIUM_NODE: usize = 64;
const MEDIUM_BINS: usize = 8;

/// How a node will be split, before it is known whether a leaf is cheaper.
enum Plan {
    /// Binned: partition on the split's axis and bin.
    Binned(Binning, Split),
    /// Tiny node: primitive `i` goes left if bit `i` of `mask` is set.
    Subset { mask: u32, weighted_area: f32 },
    /// No plane separates the centroids: split by index in half.
    Halve,
}

/// A node's two halves: `refs[..mid]` and `refs[mid..]` with their boxes and centroid bounds.
struct Children {
    mid: usize,
    left: SimdAabb,
    left_centroids: SimdAabb,
    right: SimdAabb,
    right_centroids: SimdAabb,
}

/// Per-build settings and the scratch reused across nodes, so the build allocates only its
/// output.
struct Builder {
    leaf_size: usize,
    traversal_cost: f32,
    intersection_cost: f32,
    binner: Binner,
    /// For reordering tiny nodes.
    scratch: Vec<PrimRef>,
}

/// Build a BVH with the binned SAH. `centroids[i]` is primitive `i`'s split position; if the slice
/// does not match `boxes` in length, box centres are used instead (a builder must not panic on
/// its input). With `config.threads` other than 1, subtrees of at least [`PARALLEL_GRAIN`]
/// primitives are built in parallel; the tree is the same, node for node, as one thread's.
pub fn build(boxes: &[Aabb], centroids: &[Vec3], config: &BuildConfig) -> Bvh {
    // Node indices are u32 and a binary tree over n leaves has up to 2n - 1 nodes, so inputs
    // beyond 2^31 primitives cannot be represented. Such inputs (48 GiB of boxes) are out of
    // scope; rather than panic we leave the excess out, and `validate` reports them as missing.
    let n = boxes.len().min(u32::MAX as usize / 2);
    if n == 0 {
        return Bvh::default();
    }
    let threads = config.thread_count();
    let parallel = threads > 1 && n >= PARALLEL_GRAIN;
    let mut refs = if parallel {
        in_pool(threads, || prim_refs_parallel(boxes, &matched_centroids(boxes, centroids, n)))
    } else {
        prim_refs(boxes, &matched_centroids(boxes, centroids, n))
    };
    let (root_bounds, root_centroids) = range_bounds(&refs);
    let root = Aabb::from(root_bounds);
    let nodes = if parallel {
        let part = in_pool(threads, || build_part(&mut refs, 0, root, root_centroids, config));
        let mut nodes = Vec::with_capacity(part.node_count());
        nodes.push(Node { bounds: root, kind: NodeKind::Leaf { first: 0, count: 0 } });
        part.emit(0, &mut nodes);
        nodes
    } else {
        build_range(&mut refs, root, root_centroids, config)
    };
    Bvh { nodes, prim_indices: refs.iter().map(|r| r.id).collect() }
}

/// Subtrees of fewer primitives are built by one thread. Forking costs a task and, at the end,
/// a copy of the subtree's nodes into place; at 2^16 primitives that is well under 1 % of the
/// subtree's build, and a 10M-triangle scene still has ~150 subtrees to balance over the cores.
pub const PARALLEL_GRAIN: usize = 1 << 16;

/// Runs `f` on a pool of `threads` workers (rayon's work stealing balances the uneven subtrees
/// that SAH splits make); on the caller's thread if the pool cannot be made.
fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool.install(f),
        Err(_) => f(),
    }
}

/// `prim_refs` on every worker of the current pool.
fn prim_refs_parallel(boxes: &[Aabb], centroids: &[Vec3]) -> Vec<PrimRef> {
    use rayon::prelude::*;
    boxes.par_iter().zip(centroids).enumerate().map(|(id, (b, &centroid))| PrimRef { bounds: SimdAabb::from(*b), centroid, id: id as u32 }).collect()
}

/// A subtree built by the parallel build: its nodes, numbered as the one-thread build numbers a
/// subtree (see [`build_range`]), and where its primitives start in the whole build's order.
/// Above [`PARALLEL_GRAIN`] a split is a fork whose halves were built by different workers.
enum Part {
    Nodes { nodes: Vec<Node>, first: usize },
    Fork { left_bounds: Aabb, right_bounds: Aabb, left: Box<Part>, right: Box<Part> },
}

impl Part {
    fn node_count(&self) -> usize {
        match self {
            Part::Nodes { nodes, .. } => nodes.len(),
            Part::Fork { left, right, .. } => 1 + left.node_count() + right.node_count(),
        }
    }

    /// Writes this subtree, whose root is `nodes[at]` (placed by its parent), in the one-thread
    /// build's order: a node's two children are appended when the node is, then the left
    /// child's descendants, then the right's.
    fn emit(self, at: usize, nodes: &mut Vec<Node>) {
        match self {
            Part::Fork { left_bounds, right_bounds, left, right } => {
                let l = nodes.len();
                nodes[at].kind = NodeKind::Interior { left: l as u32, right: l as u32 + 1 };
                let placeholder = NodeKind::Leaf { first: 0, count: 0 };
                nodes.push(Node { bounds: left_bounds, kind: placeholder });
                nodes.push(Node { bounds: right_bounds, kind: placeholder });
                left.emit(l, nodes);
                right.emit(l + 1, nodes);
            }
            Part::Nodes { nodes: local, first } => {
                // Local node 0 goes to `at`, local j >= 1 to base + j - 1.
                let base = nodes.len() as u32;
                let place = |j: u32| if j == 0 { at as u32 } else { base + j - 1 };
                let moved = |node: &Node| Node {
                    bounds: node.bounds,
                    kind: match node.kind {
                        NodeKind::Interior { left, right } => NodeKind::Interior { left: place(left), right: place(right) },
                        NodeKind::Leaf { first: f, count } => NodeKind::Leaf { first: f + first as u32, count },
                    },
                };
                let mut placed = local.iter().map(moved);
                if let Some(root) = placed.next() {
                    nodes[at] = root;
                }
                nodes.extend(placed);
            }
        }
    }
}

/// The parallel build of the subtree over `refs`, whose primitives start at `first` in the
/// whole build and whose box is `bounds`: splits as the one-thread build does, handing the two
/// halves to `rayon::join` until they are smaller than [`PARALLEL_GRAIN`].
fn build_part(refs: &mut [PrimRef], first: usize, bounds: Aabb, centroid_bounds: SimdAabb, config: &BuildConfig) -> Part {
    if refs.len() >= PARALLEL_GRAIN {
        if let Some(c) = Builder::new(config).split(refs, &centroid_bounds, bounds.area()) {
            let (l, r) = refs.split_at_mut(c.mid);
            let (left_bounds, right_bounds) = (Aabb::from(c.left), Aabb::from(c.right));
            let (left, right) = rayon::join(
                || build_part(l, first, left_bounds, c.left_centroids, config),
                || build_part(r, first + c.mid, right_bounds, c.right_centroids, config),
            );
            return Part::Fork { left_bounds, right_bounds, left: Box::new(left), right: Box::new(right) };
        }
    }
    Part::Nodes { nodes: build_range(refs, bounds, centroid_bounds, config), first }
}

/// The one-thread build of the subtree over `refs` with box `bounds`: node 0 is its root, leaves
/// index `refs`.
fn build_range(refs: &mut [PrimRef], bounds: Aabb, centroid_bounds: SimdAabb, config: &BuildConfig) -> Vec<Node> {
    let n = refs.len();
    let mut builder = Builder::new(config);
    let mut nodes = Vec::with_capacity(2 * n.div_ceil(builder.leaf_size));
    nodes.push(Node { bounds, kind: NodeKind::Leaf { first: 0, count: 0 } });

    // An explicit stack instead of recursion: SAH splits can peel off a few primitives at a time,
    // so depth is not bounded by log n and must never overflow the call stack. Depth-first order
    // keeps a parent's left child right after it in `nodes`.
    let mut stack = vec![Task { node: 0, begin: 0, end: n, centroid_bounds }];
    while let Some(task) = stack.pop() {
        let bounds = nodes[task.node as usize].bounds;
        let range = &mut refs[task.begin..task.end];
        let kind = match builder.split(range, &task.centroid_bounds, bounds.area()) {
            None => NodeKind::Leaf {
                // `n` fits in u32 (clamped by `build`), so every index does too.
                first: task.begin as u32,
                count: range.len() as u32,
            },
            Some(c) => {
                let left = nodes.len() as u32;
                let placeholder = NodeKind::Leaf { first: 0, count: 0 };
                nodes.push(Node { bounds: Aabb::from(c.left), kind: placeholder });
                nodes.push(Node { bounds: Aabb::from(c.right), kind: placeholder });
                let mid = task.begin + c.mid;
                stack.push(Task { node: left + 1, begin: mid, end: task.end, centroid_bounds: c.right_centroids });
                stack.push(Task { node: left, begin: task.begin, end: mid, centroid_bounds: c.left_centroids });
                NodeKind::Interior { left, right: left + 1 }
            }
        };
        nodes[task.node as usize].kind = kind;
    }
    nodes
}

/// One record per primitive; ids are below 2^31 (the caller clamps `n`).
fn prim_refs(boxes: &[Aabb], centroids: &[Vec3]) -> Vec<PrimRef> {
    boxes.iter().zip(centroids).zip(0u32..).map(|((b, &centroid), id)| PrimRef { bounds: SimdAabb::from(*b), centroid, id }).collect()
}

impl Builder {
    fn new(config: &BuildConfig) -> Self {
        let bins = config.sah_bins.clamp(2, MAX_BINS) as usize;
        Self {
            leaf_size: config.max_leaf_size.clamp(1, MAX_LEAF_SIZE) as usize,
            traversal_cost: config.traversal_cost,
            intersection_cost: config.intersection_cost,
            binner: Binner { bins, grid: vec![Bin::EMPTY; 6 * bins], suffix: vec![Bin::EMPTY; bins] },
            scratch: Vec::with_capacity(TINY_NODE),
        }
    }

    /// Split `refs` (reordering them) if the SAH says so or the node is too big for a leaf;
    /// `None` for a leaf.
    fn split(&mut self, refs: &mut [PrimRef], centroid_bounds: &SimdAabb, area: f32) -> Option<Children> {
        let count = refs.len();
        // One primitive is always a leaf (leaf_size is at least 1).
        if count <= 1 {
            return None;
        }
        let plan = self.plan(refs, centroid_bounds);
        if count <= self.leaf_size && self.leaf_is_cheaper(count, area, &plan) {
            return None;
        }
        Some(match plan {
            Plan::Binned(binning, s) => {
                let (mid, left_centroids, right_centroids) = partition(refs, &binning, s.axis, s.bin);
                Children { mid, left: s.left, left_centroids, right: s.right, right_centroids }
            }
            Plan::Subset { mask, .. } => {
                let mid = apply_subset(refs, mask, &mut self.scratch);
                halves(refs, mid)
            }
            // Centroids coincide on every axis (or no plane separated them) and the node is too
            // big for a leaf: split by index in half, which keeps the depth logarithmic.
            Plan::Halve => halves(refs, count / 2),
        })
    }

    fn plan(&mut self, refs: &[PrimRef], centroid_bounds: &SimdAabb) -> Plan {
        if refs.len() <= TINY_NODE {
            return match best_subset(refs) {
                Some((mask, weighted_area)) => Plan::Subset { mask, weighted_area },
                None => Plan::Halve,
            };
        }
        let bins = if refs.len() <= MEDIUM_NODE { self.binner.bins.min(MEDIUM_BINS) } else { self.binner.bins };
        let binning = Binning::new(centroid_bounds, bins);
        match self.binner.best_split(refs, &binning) {
            Some(s) => Plan::Binned(binning, s),
            None => Plan::Halve,
        }
    }

    /// Costs are compared multiplied through by A_parent, so a zero-area node (all boxes on a
    /// line or a point) needs no division: C_leaf = N * C_isect against C_trav +
    /// (A_L N_L + A_R N_R) / A_parent * C_isect. With no plane at all, a leaf it is.
    fn leaf_is_cheaper(&self, count: usize, area: f32, plan: &Plan) -> bool {
        let weighted_area = match plan {
            Plan::Binned(_, s) => s.weighted_area,
            Plan::Subset { weighted_area, .. } => *weighted_area,
            Plan::Halve => return true,
        };
        count as f32 * self.intersection_cost * area <= self.traversal_cost * area + weighted_area * self.intersection_cost
    }
}

/// `refs[..mid]` and `refs[mid..]` with their bounds, for splits that did not bin.
fn halves(refs: &[PrimRef], mid: usize) -> Children {
    let (left, left_centroids) = range_bounds(&refs[..mid]);
    let (right, right_centroids) = range_bounds(&refs[mid..]);
    Children { mid, left, left_centroids, right, right_centroids }
}

/// The cheapest split of at most [`TINY_NODE`] primitives into two non-empty sets, by trying
/// them all: (mask of the left set, A_L N_L + A_R N_R). The last primitive always goes right, so
/// each partition is tried once; ties go to the most balanced, then the first mask. `None` for
/// fewer than 2 refs.
fn best_subset(refs: &[PrimRef]) -> Option<(u32, f32)> {
    let n = refs.len().min(TINY_NODE);
    let mut best: Option<(f32, u32, u32)> = None;
    for mask in 1..(1u32 << n.saturating_sub(1)) {
        let (mut left, mut right) = (SimdAabb::EMPTY, SimdAabb::EMPTY);
        for (i, r) in refs[..n].iter().enumerate() {
            if mask >> i & 1 == 1 {
                left = left.union(r.bounds);
            } else {
                right = right.union(r.bounds);
            }
        }
        let n_left = mask.count_ones();
        let n_right = n as u32 - n_left;
        let weighted_area = left.area() * n_left as f32 + right.area() * n_right as f32;
        let imbalance = n_left.abs_diff(n_right);
        if best.map_or(true, |(w, imb, _)| weighted_area < w || (weighted_area == w && imbalance < imb)) {
            best = Some((weighted_area, imbalance, mask));
        }
    }
    best.map(|(w, _, mask)| (mask, w))
}

/// Move the primitives in `mask` (see [`best_subset`]) to the front, keeping their order;
/// returns how many there are. `scratch` is reused across nodes.
fn apply_subset(refs: &mut [PrimRef], mask: u32, scratch: &mut Vec<PrimRef>) -> usize {
    let in_left = |i: usize| mask >> i & 1 == 1;
    scratch.clear();
    let indexed = || refs.iter().enumerate();
    scratch.extend(indexed().filter(|&(i, _)| in_left(i)).map(|(_, r)| *r));
    let mid = scratch.len();
    scratch.extend(indexed().filter(|&(i, _)| !in_left(i)).map(|(_, r)| *r));
    refs.copy_from_slice(scratch);
    mid
}

/// Add one primitive to its bin on each axis of `grid` (3 x `k` bins). All three axes, unusable
/// ones included (they all land in bin 0): cheaper than a branch per axis in the hottest loop of
/// the build.
#[inline]
fn bin_into(grid: &mut [Bin], k: usize, binning: &Binning, r: &PrimRef) {
    let b = binning.bins(r.centroid.into());
    for (axis, &i) in b.iter().enumerate() {
        if let Some(bin) = grid.get_mut(axis * k + i) {
            bin.bounds = bin.bounds.union(r.bounds);
            bin.count += 1;
        }
    }
}

impl Binner {
    /// Bin the primitives and sweep the K - 1 planes between bins on every usable axis; `None`
    /// when no plane leaves primitives on both sides.
    fn best_split(&mut self, refs: &[PrimRef], binning: &Binning) -> Option<Split> {
        let k = binning.last + 1;
        let (grid, spare) = self.grid.split_at_mut(3 * self.bins);
        let (grid, spare) = (&mut grid[..3 * k], &mut spare[..3 * k]);
        grid.fill(Bin::EMPTY);
        if refs.len() <= MEDIUM_NODE {
            for r in refs {
                bin_into(grid, k, binning, r);
            }
        } else {
            // Neighbouring primitives often land in the same bin, and each update must wait for
            // the previous one's store; alternating between two grids halves those chains. Not
            // worth the second grid's clearing and merging on medium nodes.
            spare.fill(Bin::EMPTY);
            let mut pairs = refs.chunks_exact(2);
            for pair in &mut pairs {
                bin_into(grid, k, binning, &pair[0]);
                bin_into(spare, k, binning, &pair[1]);
            }
            for r in pairs.remainder() {
                bin_into(grid, k, binning, r);
            }
            for (g, s) in grid.iter_mut().zip(spare.iter()) {
                *g = g.add(s);
            }
        }

        let mut best: Option<Split> = None;
        for axis in (0..3).filter(|&a| binning.usable[a]) {
            let grid = &self.grid[axis * k..(axis + 1) * k];
            // Right-to-left: suffix[i] = union of bins i.. ; then left-to-right, the plane before
            // bin i has bins ..i on the left and suffix[i] on the right.
            let mut acc = Bin::EMPTY;
            for (s, g) in self.suffix[..k].iter_mut().zip(grid).rev() {
                acc = acc.add(g);
                *s = acc;
            }
            let mut left = Bin::EMPTY;
            for (i, (g, right)) in grid.iter().zip(&self.suffix[1..k]).enumerate() {
                // After an empty bin the plane splits the same sets as the one before it.
                if g.count == 0 {
                    continue;
                }
                left = left.add(g);
                if left.count == 0 || right.count == 0 {
                    continue;
                }
                let weighted_area = left.bounds.area() * left.count as f32 + right.bounds.area() * right.count as f32;
                // Among planes of equal cost take the most balanced one. Ties are common exactly
                // where it matters: zero-area boxes (all on a line or a point) cost 0 everywhere,
                // and always taking the first plane would peel off one bin at a time and make
                // the tree as deep as the input is long.
                let imbalance = left.count.abs_diff(right.count);
                if best.as_ref().map_or(true, |b| weighted_area < b.weighted_area || (weighted_area == b.weighted_area && imbalance < b.imbalance)) {
                    let bin = i as u32 + 1;
                    best = Some(Split { axis, bin, weighted_area, imbalance, left: left.bounds, right: right.bounds });
                }
            }
        }
        best
    }
}

/// Partition `refs` in place so primitives whose centroid falls in a bin `< split_bin` on `axis`
/// come first; returns the first right index and the left and right centroid bounds, gathered
/// here so the children need no extra pass.
fn partition(refs: &mut [PrimRef], binning: &Binning, axis: usize, split_bin: u32) -> (usize, SimdAabb, SimdAabb) {
    let split_bin = split_bin as usize;
    let goes_left = |r: &PrimRef| binning.bin(r.centroid[axis], axis) < split_bin;
    // Hoare's scheme: scan in from both ends and swap only pairs that are both on the wrong
    // side, so each record moves at most once.
    let (mut i, mut j) = (0, refs.len());
    let (mut lc, mut rc) = (SimdAabb::EMPTY, SimdAabb::EMPTY);
    loop {
        while i < j && goes_left(&refs[i]) {
            lc = lc.grow(refs[i].centroid.into());
            i += 1;
        }
        while i < j && !goes_left(&refs[j - 1]) {
            rc = rc.grow(refs[j - 1].centroid.into());
            j -= 1;
        }
        if j - i < 2 {
            // i == j: done. j == i + 1 cannot happen: refs[i] went right, so the second scan
            // stopped at a left record at j - 1 > i, or at j == i.
            break;
        }
        refs.swap(i, j - 1);
        lc = lc.grow(refs[i].centroid.into());
        rc = rc.grow(refs[j - 1].centroid.into());
        i += 1;
        j -= 1;
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
fn range_bounds(refs: &[PrimRef]) -> (SimdAabb, SimdAabb) {
    refs.iter().fold((SimdAabb::EMPTY, SimdAabb::EMPTY), |(b, c), r| (b.union(r.bounds), c.grow(r.centroid.into())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The partition's scalar `bin` must put every centroid in the bin the SIMD `bins` chose,
    /// or child boxes taken from the bins would miss primitives.
    #[test]
    fn scalar_and_simd_bins_agree() {
        let bounds = SimdAabb { min: Vec3A::new(-1.0, 0.0, 3.0), max: Vec3A::new(2.0, 1e-30, 3.0) };
        for bins in [2, 8, 16, 256] {
            let binning = Binning::new(&bounds, bins);
            let mut values: Vec<f32> = (-40..=40).map(|i| i as f32 * 0.0625).collect();
            values.extend([f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 1e-30, 2.0, 3.0]);
            for &x in &values {
                for &y in &values {
                    let c = Vec3A::new(x, y, x);
                    let simd = binning.bins(c);
                    for axis in 0..3 {
                        assert_eq!(simd[axis], binning.bin(c[axis], axis), "{c:?} axis {axis}");
                        assert!(simd[axis] < bins);
                    }
                }
            }
        }
    }
}
