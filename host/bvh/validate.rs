//! BVH invariants, checked after every build in the tests.
//!
//! A traversal trusts the tree completely: a primitive outside its leaf's box is silently never
//! hit, and a cycle or a shared child makes the GPU loop or test twice. So every property the
//! flatteners and traversals rely on is checked here, and the first violation is reported with the
//! node it was found at.

use crate::bvh::{Bvh, NodeKind, MAX_LEAF_SIZE};
use crate::geom::Aabb;

/// Check `bvh` against the primitive `boxes` it was built from:
/// - `prim_indices` is a permutation of `0..boxes.len()`;
/// - every node is reachable from the root exactly once (a tree: no cycles, no shared children,
///   no orphans), and child indices are in range;
/// - leaves are nonempty, hold at most [`MAX_LEAF_SIZE`] primitives, lie inside `prim_indices`
///   and together cover it exactly once;
/// - node bounds are free of NaN, children lie inside their parent's bounds, and a leaf's bounds
///   contain each of its primitives' boxes.
pub fn validate(bvh: &Bvh, boxes: &[Aabb]) -> Result<(), String> {
    let n = boxes.len();
    check_permutation(&bvh.prim_indices, n)?;
    if bvh.nodes.is_empty() {
        // An empty scene has no root; anything else needs one.
        return if n == 0 { Ok(()) } else { Err(format!("no nodes for {n} primitives")) };
    }

    let mut reached = vec![false; bvh.nodes.len()];
    let mut covered = vec![false; bvh.prim_indices.len()];
    // Explicit stack: validating a degenerate (deep) tree must not overflow the call stack.
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let Some(seen) = reached.get_mut(i) else {
            return Err(format!("node index {i} out of range ({} nodes)", bvh.nodes.len()));
        };
        if *seen {
            return Err(format!("node {i} reached twice (shared child or cycle)"));
        }
        *seen = true;
        let node = &bvh.nodes[i];
        let b = node.bounds;
        if b.min.is_nan() || b.max.is_nan() {
            return Err(format!("node {i} has NaN bounds {b:?}"));
        }
        match node.kind {
            NodeKind::Interior { left, right } => {
                for child in [left as usize, right as usize] {
                    let Some(c) = bvh.nodes.get(child) else {
                        return Err(format!("node {i}: child {child} out of range ({} nodes)", bvh.nodes.len()));
                    };
                    if !b.contains(&c.bounds) {
                        return Err(format!("node {i}: child {child} bounds {:?} outside parent {b:?}", c.bounds));
                    }
                    stack.push(child);
                }
            }
            NodeKind::Leaf { first, count } => {
                check_leaf(i, first, count, &b, bvh, boxes, &mut covered)?;
            }
        }
    }
    if let Some(i) = reached.iter().position(|&r| !r) {
        return Err(format!("node {i} unreachable from the root"));
    }
    if let Some(slot) = covered.iter().position(|&c| !c) {
        return Err(format!("prim_indices[{slot}] is in no leaf"));
    }
    Ok(())
}

/// `prim_indices` must name each of the `n` primitives exactly once.
fn check_permutation(prim_indices: &[u32], n: usize) -> Result<(), String> {
    if prim_indices.len() != n {
        return Err(format!("prim_indices has {} entries for {n} primitives", prim_indices.len()));
    }
    let mut seen = vec![false; n];
    for (slot, &p) in prim_indices.iter().enumerate() {
        match seen.get_mut(p as usize) {
            None => return Err(format!("prim_indices[{slot}] = {p} out of range ({n} primitives)")),
            Some(true) => return Err(format!("primitive {p} referenced twice (prim_indices[{slot}])")),
            Some(s) => *s = true,
        }
    }
    Ok(())
}

/// A leaf's range must be nonempty, small enough to pack, in bounds, not overlap another leaf's,
/// and its box must contain its primitives' boxes.
fn check_leaf(i: usize, first: u32, count: u32, bounds: &Aabb, bvh: &Bvh, boxes: &[Aabb], covered: &mut [bool]) -> Result<(), String> {
    if count == 0 {
        return Err(format!("leaf {i} is empty"));
    }
    if count > MAX_LEAF_SIZE {
        return Err(format!("leaf {i} holds {count} primitives, more than MAX_LEAF_SIZE = {MAX_LEAF_SIZE}"));
    }
    let (first, end) = (first as usize, first as usize + count as usize);
    let (Some(prims), Some(slots)) = (bvh.prim_indices.get(first..end), covered.get_mut(first..end)) else {
        return Err(format!("leaf {i} range {first}..{end} outside prim_indices (len {})", bvh.prim_indices.len()));
    };
    for (slot, (&p, c)) in prims.iter().zip(slots).enumerate() {
        if *c {
            return Err(format!("leaf {i}: prim_indices[{}] also belongs to another leaf", first + slot));
        }
        *c = true;
        // `check_permutation` ran first, so `p` is in range; stay non-panicking regardless.
        let Some(pb) = boxes.get(p as usize) else {
            return Err(format!("leaf {i}: primitive {p} out of range"));
        };
        if !bounds.contains(pb) {
            return Err(format!("leaf {i} bounds {bounds:?} do not contain primitive {p} box {pb:?}"));
        }
    }
    Ok(())
}
