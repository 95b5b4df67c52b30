//! Insertion-based optimisation of a finished BVH (Bittner, Hapala & Havran 2013, "Fast
//! insertion-based optimization of bounding volume hierarchies", Computer Graphics Forum 32(1)).
//!
//! A top-down builder decides each split once, greedily. Reinsertion revisits the tree: take a
//! node N whose box looks wasteful, remove it (its parent P goes too, and N's sibling takes P's
//! place), and insert N again as the sibling of the node X where it adds the least SAH cost,
//! reusing P as their new parent. The cost of inserting at X is area(X u N) (the new parent)
//! plus, for every ancestor A of X, the growth area(A u N) - area(A): the "induced cost". A
//! best-first search with the lower bound induced + area(N) finds the best X without visiting
//! most of the tree. A move is kept only if it saves more than it costs, so the SAH cost (the
//! Σ area-ratio sum of `sah.rs`) only ever drops.
//!
//! Candidates come in batches: the 1% of nodes with the highest inefficiency
//! M = M_area * M_min * M_sum (the paper's combined measure: big nodes whose children fill them
//! badly). Batches repeat until one gains under 0.1% or `MAX_BATCHES` have run.
//!
//! Trade-off: `bvh::build` starts it from the binned SAH tree, so it costs that build plus about
//! as much again (2-4x the binned build alone; less than the full sweep on the shared scenes) and
//! gives the lowest SAH cost of the builders here, which is why it is the default. Starting from
//! the sweep's tree instead took twice the time for costs within 1-3 %
//! (docs/experiments/reinsertion-default.md). Leaves keep their primitives; only the tree above
//! them changes, and the result is renumbered depth first with leaf order rebuilt.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::bvh::{BuildConfig, Bvh, Node, NodeKind};
use crate::geom::Aabb;

/// Upper bound on candidate batches (each reinserts 1% of the nodes).
const MAX_BATCHES: usize = 40;
/// Stop once a batch lowers the total cost by less than this fraction.
const MIN_BATCH_GAIN: f64 = 1e-3;

/// Working tree: the nodes with parent links.
struct Tree {
    nodes: Vec<Node>,
    parent: Vec<u32>,
}

fn area(b: &Aabb) -> f64 {
    f64::from(b.area())
}

impl Tree {
    fn children(&self, i: u32) -> Option<(u32, u32)> {
        match self.nodes[i as usize].kind {
            NodeKind::Interior { left, right } => Some((left, right)),
            NodeKind::Leaf { .. } => None,
        }
    }
    fn replace_child(&mut self, parent: u32, old: u32, new: u32) {
        if let NodeKind::Interior { left, right } = &mut self.nodes[parent as usize].kind {
            if *left == old {
                *left = new;
            } else if *right == old {
                *right = new;
            }
        }
        self.parent[new as usize] = parent;
    }
    /// Recompute boxes from `i` up to the root; returns the total area removed (negative if
    /// boxes grew).
    fn refit_from(&mut self, mut i: u32) -> f64 {
        let mut shrunk = 0.0;
        loop {
            if let Some((l, r)) = self.children(i) {
                let old = area(&self.nodes[i as usize].bounds);
                let b = self.nodes[l as usize].bounds.union(&self.nodes[r as usize].bounds);
                self.nodes[i as usize].bounds = b;
                shrunk += old - area(&b);
            }
            if i == 0 {
                return shrunk;
            }
            i = self.parent[i as usize];
        }
    }
    /// Cheapest node to become `n`'s sibling, and the cost of making it so (root excluded, so
    /// the root stays node 0). Best-first search on the induced cost.
    fn best_position(&self, n_box: &Aabb) -> Option<(u32, f64)> {
        let n_area = area(n_box);
        let root = &self.nodes[0].bounds;
        let root_growth = area(&root.union(n_box)) - area(root);
        let mut heap = BinaryHeap::new();
        let (l, r) = self.children(0)?;
        heap.push(Candidate { induced: root_growth, node: l });
        heap.push(Candidate { induced: root_growth, node: r });
        let mut best: Option<(u32, f64)> = None;
        while let Some(Candidate { induced, node }) = heap.pop() {
            let best_cost = best.map_or(f64::INFINITY, |b| b.1);
            if induced + n_area >= best_cost {
                break;
            }
            let b = &self.nodes[node as usize].bounds;
            let direct = area(&b.union(n_box));
            if induced + direct < best_cost {
                best = Some((node, induced + direct));
            }
            let child_induced = induced + direct - area(b);
            if let Some((l, r)) = self.children(node) {
                if child_induced + n_area < best.map_or(f64::INFINITY, |b| b.1) {
                    heap.push(Candidate { induced: child_induced, node: l });
                    heap.push(Candidate { induced: child_induced, node: r });
                }
            }
        }
        best
    }
    /// Bittner et al.'s M_area * M_min * M_sum; leaves (no children) score their area.
    fn inefficiency(&self, i: u32) -> f64 {
        let a = area(&self.nodes[i as usize].bounds);
        match self.children(i) {
            Some((l, r)) => {
                let (al, ar) = (area(&self.nodes[l as usize].bounds), area(&self.nodes[r as usize].bounds));
                let m_min = a / al.min(ar).max(f64::MIN_POSITIVE);
                let m_sum = a / (0.5 * (al + ar)).max(f64::MIN_POSITIVE);
                a * m_min * m_sum
            }
            None => a,
        }
    }
}

#[derive(PartialEq)]
struct Candidate {
    induced: f64,
    node: u32,
}
impl Eq for Candidate {}
impl Ord for Candidate {
    /// Smallest induced cost first (BinaryHeap is a max-heap).
    fn cmp(&self, o: &Self) -> Ordering {
        o.induced.total_cmp(&self.induced).then(o.node.cmp(&self.node))
    }
}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Optimise `bvh` by reinsertion. Trees of fewer than 5 nodes have nothing to move.
pub fn optimize(bvh: Bvh, _config: &BuildConfig) -> Bvh {
    let count = bvh.nodes.len();
    if count < 5 {
        return bvh;
    }
    let mut parent = vec![0u32; count];
    for (i, node) in bvh.nodes.iter().enumerate() {
        if let NodeKind::Interior { left, right } = node.kind {
            parent[left as usize] = i as u32;
            parent[right as usize] = i as u32;
        }
    }
    let prim_indices = bvh.prim_indices;
    let mut tree = Tree { nodes: bvh.nodes, parent };
    let root_area = area(&tree.nodes[0].bounds).max(f64::MIN_POSITIVE);
    let mut total: f64 = tree.nodes.iter().map(|n| area(&n.bounds)).sum::<f64>() / root_area;
    let batch = (count / 100).max(1);
    for _ in 0..MAX_BATCHES {
        let mut order: Vec<(f64, u32)> = (1..count as u32).filter(|&i| tree.parent[i as usize] != 0).map(|i| (tree.inefficiency(i), i)).collect();
        let k = batch.min(order.len());
        if k == 0 {
            break;
        }
        order.select_nth_unstable_by(k - 1, |a, b| b.0.total_cmp(&a.0));
        let mut gained = 0.0;
        for &(_, n) in &order[..k] {
            gained += reinsert(&mut tree, n);
        }
        total -= gained / root_area;
        if gained / root_area < MIN_BATCH_GAIN * total {
            break;
        }
    }
    compact(&tree, &prim_indices)
}

/// Remove `n` and insert it where it costs least; returns the area saved (0 if it stayed).
fn reinsert(tree: &mut Tree, n: u32) -> f64 {
    let p = tree.parent[n as usize];
    if n == 0 || p == 0 {
        return 0.0;
    }
    let Some((l, r)) = tree.children(p) else { return 0.0 };
    let s = if l == n { r } else { l };
    let g = tree.parent[p as usize];
    // Detach: the sibling takes the parent's place; what the removal saves is the parent's
    // area plus the shrinking of its ancestors.
    let p_area = area(&tree.nodes[p as usize].bounds);
    tree.replace_child(g, p, s);
    let removal_gain = p_area + tree.refit_from(g);
    let n_box = tree.nodes[n as usize].bounds;
    let (target, cost) = match tree.best_position(&n_box) {
        // Move only for a real gain; ties and float noise keep the node where it was.
        Some((x, cost)) if cost < removal_gain * (1.0 - 1e-6) => (x, cost),
        _ => (s, 0.0),
    };
    let gx = tree.parent[target as usize];
    tree.replace_child(gx, target, p);
    tree.nodes[p as usize].kind = NodeKind::Interior { left: target, right: n };
    tree.parent[target as usize] = p;
    tree.parent[n as usize] = p;
    tree.refit_from(p);
    if target == s {
        0.0
    } else {
        removal_gain - cost
    }
}

/// Renumber depth first (children as adjacent pairs, as the builders emit them) and lay the
/// primitives out in leaf order, so leaves close in the tree are close in memory.
fn compact(tree: &Tree, prim_indices: &[u32]) -> Bvh {
    let mut nodes = Vec::with_capacity(tree.nodes.len());
    let mut prims = Vec::with_capacity(prim_indices.len());
    nodes.push(Node { bounds: tree.nodes[0].bounds, kind: NodeKind::Leaf { first: 0, count: 0 } });
    let mut stack = vec![(0u32, 0u32)];
    while let Some((src, dst)) = stack.pop() {
        let kind = match tree.nodes[src as usize].kind {
            NodeKind::Leaf { first, count } => {
                let new_first = prims.len() as u32;
                prims.extend_from_slice(&prim_indices[first as usize..(first + count) as usize]);
                NodeKind::Leaf { first: new_first, count }
            }
            NodeKind::Interior { left, right } => {
                let l = nodes.len() as u32;
                for c in [left, right] {
                    nodes.push(Node { bounds: tree.nodes[c as usize].bounds, kind: NodeKind::Leaf { first: 0, count: 0 } });
                }
                stack.push((right, l + 1));
                stack.push((left, l));
                NodeKind::Interior { left: l, right: l + 1 }
            }
        };
        nodes[dst as usize].kind = kind;
    }
    Bvh { nodes, prim_indices: prims }
}
