//! The wide layout: the binary BVH collapsed into a 4-ary one, walked without a stack by
//! re-entering the parent (shader: `traverse_wide.glsl`).
//!
//! Why it was built: the per-step profile of the binary walks on lavapipe suggested that a
//! step costs more in loop overhead, texel-fetch calls and the reloads after them than in its
//! one box test (docs/experiments/per-step-cost.md); the result below says how far that held.
//! A wide node puts four child boxes in one visit, so a ray makes fewer, fatter steps: the
//! multi-BVH idea of CPU ray tracers (Dammertz, Hanika & Keller 2008; Wald, Benthin & Boulos
//! 2008), here for the lockstep lanes of a SIMT shader rather than for SIMD across the boxes.
//!
//! **Collapse.** Each wide node starts from a binary interior node's two children and opens the
//! interior member with the largest surface area until it has four members or only leaves
//! (the usual top-down collapse, as in Embree's BVH4 builders). Members that are binary leaves
//! become leaf slots (their triangles, as in the other layouts); interior members become wide
//! children. A binary tree whose root is a leaf becomes one wide node with one slot.
//!
//! **Order.** A node's slots are sorted by box centre along the axis on which the centres
//! spread most; a ray visits them in that order if its direction on the axis is >= 0, else
//! in reverse: near to far per node, without sorting per ray.
//!
//! **Walk.** Entering a node tests all its valid slots against the current tmax, then visits
//! the hit slots in the ray's order: leaves are tested at once (a closer hit shrinks tmax, and
//! a later slot whose entry distance is past it is skipped, the same answer as re-testing its
//! box), and the first interior child is descended into. When a node has no slot left, the
//! walk goes to its parent and enters it again, restricted to the slots after the one it came
//! from, with its boxes re-tested against the shrunk tmax. The state is a node index and a slot
//! number: no stack, no trail, no depth limit. The price is that each return visits the parent
//! again. Áfra & Szirmay-Kalos 2014 ("Stackless multi-BVH traversal for CPU, MIC and GPU ray
//! tracing") avoid that with a bitmask per level; such a trail (16 levels of 4-bit masks,
//! re-entering only after a closer hit) was built and measured here: 22-28 % fewer visits, no
//! faster on lavapipe, so the simpler walk stayed (docs/experiments/wide-bvh.md).
//!
//! **Result on lavapipe:** a ray makes 2.6-3.5x fewer visits than the threaded walk's box
//! tests, but a visit (eight texel fetches, four box tests) costs about as much as three
//! threaded steps, so the layout runs at 0.65-0.89x of threaded on `vkrt trace` and takes 1.37x
//! the time in the path tracer (docs/experiments/wide-bvh.md). It is kept for devices where fetches are cheap relative to loop steps.
//!
//! Counters: `nodes_visited` counts wide-node visits (each tests up to four boxes), so it is
//! not comparable one for one with the binary layouts' box tests.
//! Memory: 128 B per wide node, about a quarter as many nodes as the binary tree (Conference,
//! SAH: 65,374 wide nodes for 269,939 binary ones).

use super::intersect::{intersect_box, RayPre, SLAB_FAR_PAD};
use super::leaf::{leaf_count, miss, test_leaf};
use super::{node_array, LayoutKind};
use crate::bvh::{Bvh, NodeKind};
use crate::gpu_abi::constants::{LEAF_COUNT_BITS, NODE_NONE, WIDE_ARITY, WIDE_INFO_AXIS_SHIFT, WIDE_INFO_SLOT_SHIFT, WIDE_NO_SLOT};
use crate::gpu_abi::{GpuHit, GpuRay, GpuTriangle, GpuWideNode};
use anyhow::bail;
use bytemuck::Zeroable;
use glam::Vec3;

node_array!(Wide, GpuWideNode, LayoutKind::Wide, "The wide node array.");

const ARITY: usize = WIDE_ARITY as usize;

/// Interior children are addressed by the bits above the leaf count.
const MAX_NODES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// The binary nodes that become the slots of the wide node made from binary node `src`.
fn members(bvh: &Bvh, src: u32) -> Vec<u32> {
    let NodeKind::Interior { left, right } = bvh.nodes[src as usize].kind else {
        return vec![src];
    };
    let mut members = vec![left, right];
    while members.len() < ARITY {
        // Open the interior member with the largest surface area: it is the one a ray is most
        // likely to enter, so its children are the ones most worth testing in this visit.
        let widest = members
            .iter()
            .enumerate()
            .filter(|(_, &m)| matches!(bvh.nodes[m as usize].kind, NodeKind::Interior { .. }))
            .max_by(|(_, &a), (_, &b)| bvh.nodes[a as usize].bounds.area().total_cmp(&bvh.nodes[b as usize].bounds.area()))
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let NodeKind::Interior { left, right } = bvh.nodes[members[i] as usize].kind else { unreachable!() };
        members[i] = left;
        members.insert(i + 1, right);
    }
    members
}

/// The axis on which the members' box centres spread most, and the members sorted along it
/// (stable, so ties keep the binary tree's order).
fn order_members(bvh: &Bvh, mut members: Vec<u32>) -> (u32, Vec<u32>) {
    let centre = |m: u32| bvh.nodes[m as usize].bounds.center();
    let (lo, hi) = members.iter().fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &m| (lo.min(centre(m)), hi.max(centre(m))));
    let d = hi - lo;
    let axis = if d.x >= d.y && d.x >= d.z {
        0
    } else if d.y >= d.z {
        1
    } else {
        2
    };
    members.sort_by(|&a, &b| centre(a)[axis].total_cmp(&centre(b)[axis]));
    (axis as u32, members)
}

/// Collapse `bvh` into wide nodes, depth first (a node's children follow it, first slot's
/// subtree first).
pub fn flatten(bvh: &Bvh) -> anyhow::Result<Vec<GpuWideNode>> {
    flatten_at(bvh, 0)
}

/// [`flatten`] for an array in which the tree starts at `base` (a two-level BVH's levels,
/// `two_level`): its parent links and interior children offset by it; the root's parent is
/// still NODE_NONE, where a walk of the tree ends.
pub fn flatten_at(bvh: &Bvh, base: u32) -> anyhow::Result<Vec<GpuWideNode>> {
    if bvh.nodes.is_empty() {
        return Ok(Vec::new());
    }
    let mut out: Vec<GpuWideNode> = Vec::new();
    // (binary node, parent wide node, slot in the parent)
    let mut pending = vec![(0u32, NODE_NONE, 0u32)];
    while let Some((src, parent, slot_in_parent)) = pending.pop() {
        if base as usize + out.len() >= MAX_NODES {
            bail!("BVH needs more than {MAX_NODES} wide nodes; the wide layout addresses at most that many");
        }
        let index = base + out.len() as u32;
        if parent != NODE_NONE {
            out[(parent - base) as usize].children[slot_in_parent as usize] = index << LEAF_COUNT_BITS;
        }
        let (axis, slots) = order_members(bvh, members(bvh, src));
        let mut node = GpuWideNode {
            parent,
            info: slots.len() as u32 | (axis << WIDE_INFO_AXIS_SHIFT) | (slot_in_parent << WIDE_INFO_SLOT_SHIFT),
            ..GpuWideNode::zeroed()
        };
        // Interior slots are pushed in reverse so the first slot's subtree is laid out first.
        for (slot, &m) in slots.iter().enumerate().rev() {
            let b = &bvh.nodes[m as usize];
            node.min_x[slot] = b.bounds.min.x;
            node.min_y[slot] = b.bounds.min.y;
            node.min_z[slot] = b.bounds.min.z;
            node.max_x[slot] = b.bounds.max.x;
            node.max_y[slot] = b.bounds.max.y;
            node.max_z[slot] = b.bounds.max.z;
            match b.kind {
                NodeKind::Leaf { first, count } => node.children[slot] = (first << LEAF_COUNT_BITS) | count,
                // Filled in when the child is placed.
                NodeKind::Interior { .. } => pending.push((m, index, slot as u32)),
            }
        }
        out.push(node);
    }
    Ok(out)
}

/// A node's child count.
pub fn child_count(info: u32) -> u32 {
    info & ((1 << WIDE_INFO_AXIS_SHIFT) - 1)
}

/// Whether the ray visits this node's slots from the last to the first.
pub(super) fn reversed(info: u32, dir: Vec3) -> bool {
    dir[((info >> WIDE_INFO_AXIS_SHIFT) & 3) as usize] < 0.0
}

/// The slots of a node still to visit after coming back from `from` (`WIDE_NO_SLOT`: all).
pub(super) fn slots_after(from: u32, reverse: bool) -> u32 {
    if from == WIDE_NO_SLOT {
        0xF
    } else if reverse {
        (1 << from) - 1
    } else {
        (0xE << from) & 0xF
    }
}

/// `wide_box_mask` in traverse_wide.glsl: which of the node's valid slots the ray enters
/// within [tmin, tmax], and their entry distances. Each slot is exactly `intersect_box`.
pub(super) fn box_mask(r: &RayPre, n: &GpuWideNode, tmax: f32) -> (u32, [f32; 4]) {
    let mut mask = 0;
    let mut t_enter = [0.0f32; 4];
    for slot in 0..ARITY {
        let lo = Vec3::new(n.min_x[slot], n.min_y[slot], n.min_z[slot]);
        let hi = Vec3::new(n.max_x[slot], n.max_y[slot], n.max_z[slot]);
        // The shader tests every slot and masks afterwards; the result is the same.
        if let Some(t) = intersect_box(r, lo, hi, tmax) {
            mask |= 1 << slot;
            t_enter[slot] = t;
        }
    }
    (mask & ((1 << child_count(n.info)) - 1), t_enter)
}

/// The next slot of `mask` in the ray's order, taken out of it, and its child word: the slot
/// loop of the wide walks (traverse_wide.glsl, traverse_two_level_wide.glsl, where it is
/// written out). A slot whose entry is past `tmax` is passed over: a leaf of this node found a
/// closer hit, the same answer as re-testing the box. None when no slot is left.
pub(super) fn next_slot(mask: &mut u32, reverse: bool, t_enter: &[f32; 4], tmax: f32, node: &GpuWideNode) -> Option<(u32, u32)> {
    while *mask != 0 {
        let slot = if reverse { 31 - mask.leading_zeros() } else { mask.trailing_zeros() };
        *mask &= !(1 << slot);
        if t_enter[slot as usize] > tmax * SLAB_FAR_PAD {
            continue;
        }
        return Some((slot, node.children[slot as usize]));
    }
    None
}

/// CPU twin of `traverse` in traverse_wide.glsl.
pub fn trace(nodes: &[GpuWideNode], tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let r = RayPre::new(ray);
    let dir = Vec3::from(ray.direction);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    let mut index = 0u32;
    let mut from = WIDE_NO_SLOT;
    // Each node is entered once from its parent and once back from each child; the bound only
    // guards a malformed array.
    let mut steps = 2 * nodes.len() + 1;
    while steps > 0 {
        steps -= 1;
        let Some(node) = nodes.get(index as usize) else { break };
        hit.nodes_visited += 1;
        let reverse = reversed(node.info, dir);
        let (hits, t_enter) = box_mask(&r, node, tmax);
        let mut mask = hits & slots_after(from, reverse);
        let mut next = NODE_NONE;
        while let Some((_, child)) = next_slot(&mut mask, reverse, &t_enter, tmax, node) {
            if leaf_count(child) == 0 {
                next = child >> LEAF_COUNT_BITS;
                break;
            }
            if test_leaf(child, tris, &r, &mut tmax, &mut hit, any_hit) && any_hit {
                return hit;
            }
        }
        if next != NODE_NONE {
            index = next;
            from = WIDE_NO_SLOT;
            continue;
        }
        if node.parent == NODE_NONE {
            break;
        }
        from = (node.info >> WIDE_INFO_SLOT_SHIFT) & 3;
        index = node.parent;
    }
    hit
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{build, BuildConfig, BuilderKind};
    use crate::geom::Aabb;
    use crate::rng::Pcg32;

    /// Every binary leaf ends up in exactly one slot, every wide child's link points back to
    /// the slot that names it, and slots are sorted along their node's axis.
    #[test]
    fn collapse_keeps_every_leaf_once_and_links_back() {
        let mut rng = Pcg32::new(7);
        let boxes: Vec<Aabb> = (0..500)
            .map(|_| {
                let p = rng.vec3() * 10.0;
                Aabb::from_points(&[p, p + rng.vec3() * 0.5])
            })
            .collect();
        let centroids: Vec<Vec3> = boxes.iter().map(|b| b.center()).collect();
        for kind in BuilderKind::ALL {
            let bvh = build(kind, &boxes, &centroids, &BuildConfig::default());
            let nodes = flatten(&bvh).unwrap();
            let mut seen = vec![0u32; bvh.prim_indices.len()];
            for (i, n) in nodes.iter().enumerate() {
                let count = child_count(n.info) as usize;
                assert!((1..=ARITY).contains(&count), "node {i} has {count} children");
                let axis = ((n.info >> WIDE_INFO_AXIS_SHIFT) & 3) as usize;
                let centre = |k: usize| {
                    let lo = [n.min_x[k], n.min_y[k], n.min_z[k]];
                    let hi = [n.max_x[k], n.max_y[k], n.max_z[k]];
                    0.5 * (lo[axis] + hi[axis])
                };
                for k in 1..count {
                    assert!(centre(k - 1) <= centre(k), "node {i}: slots out of order");
                }
                for (k, &c) in n.children[..count].iter().enumerate() {
                    if leaf_count(c) == 0 {
                        let child = &nodes[(c >> LEAF_COUNT_BITS) as usize];
                        assert_eq!(child.parent, i as u32);
                        assert_eq!((child.info >> WIDE_INFO_SLOT_SHIFT) & 3, k as u32);
                    } else {
                        let first = (c >> LEAF_COUNT_BITS) as usize;
                        for s in &mut seen[first..first + leaf_count(c) as usize] {
                            *s += 1;
                        }
                    }
                }
            }
            assert_eq!(nodes[0].parent, NODE_NONE);
            assert!(seen.iter().all(|&s| s == 1), "{kind:?}: a primitive is in {:?} leaves", seen.iter().max());
            assert!(nodes.len() < bvh.nodes.len() / 2 + 1, "{kind:?}: {} wide nodes for {} binary", nodes.len(), bvh.nodes.len());
        }
    }

    #[test]
    fn slots_after_follow_the_visit_order() {
        assert_eq!(slots_after(WIDE_NO_SLOT, false), 0b1111);
        assert_eq!(slots_after(0, false), 0b1110);
        assert_eq!(slots_after(2, false), 0b1000);
        assert_eq!(slots_after(3, false), 0);
        assert_eq!(slots_after(3, true), 0b0111);
        assert_eq!(slots_after(0, true), 0);
    }
}
