//! The parent-linked BVH2 with the stackless state machine of Hapala, Davidovič, Wald, Havran &
//! Slusallek 2011, "Efficient stack-less BVH traversal for ray tracing" (SCCG).
//!
//! Each node knows its parent, and siblings are stored side by side, so from any node the walk
//! can reach its parent, its sibling and its children. Three states say where the walk came
//! from: from the parent (test this node), from the sibling (test this node, the far child), or
//! from a child (go up; if the child was the near one, its sibling is next). Children are
//! visited near first by the sign of the ray direction on the node's split axis, so the walk
//! tests exactly the nodes an ordered stack traversal would, in the same order, and is exact:
//! closest-hit culling uses the best hit found so far as tmax. The price is going back up
//! through parents (one node read per level, no box test) instead of popping a stack.
//!
//! Encoding (`GpuParentNode`): node 0 is the root, node 1 an unused filler, and the two children
//! of every interior node sit at (2k, 2k + 1), so a sibling is `index ^ 1` and the near child
//! is the even one when the direction on the split axis is >= 0. The split axis is the axis on
//! which the children's centres differ most; the even child is the one with the smaller centre.
//! `parent` packs (parent << 4) | (own split axis << 2) | parent's split axis, and `leaf` packs a
//! leaf's triangles like the threaded layout or, with count 0, an interior node's even child.
//! Memory: 32 B per node plus one filler node. Shader: `traverse_parent_link.glsl`.

use super::intersect::{intersect_box, RayPre};
use super::leaf::{leaf_count, miss, test_leaf};
use super::{node_array, LayoutKind};
use crate::bvh::{Bvh, NodeKind};
use crate::gpu_abi::constants::LEAF_COUNT_BITS;
use crate::gpu_abi::{GpuHit, GpuParentNode, GpuRay, GpuTriangle};
use anyhow::bail;
use glam::Vec3;

node_array!(ParentLink, GpuParentNode, LayoutKind::ParentLink, "The parent-link node array.");

/// Parent indices get 28 bits; even-child indices the 24 bits above the leaf count.
const MAX_NODES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// Lay `bvh` out in sibling pairs, depth first (a node's children are placed when it is).
pub fn flatten(bvh: &Bvh) -> anyhow::Result<Vec<GpuParentNode>> {
    flatten_at(bvh, 0)
}

/// [`flatten`] for an array in which the tree starts at `base` (a two-level BVH's levels,
/// `two_level`): every parent and child index offset by it. `base` must be even, so that
/// siblings stay the pairs (2k, 2k + 1); every tree's array has an even length (its filler),
/// so trees laid one after another keep that. The root's parent is the root itself.
pub fn flatten_at(bvh: &Bvh, base: u32) -> anyhow::Result<Vec<GpuParentNode>> {
    let n = bvh.nodes.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    anyhow::ensure!(base % 2 == 0, "a parent-link tree must start at an even index, not {base}");
    if base as usize + n + 1 > MAX_NODES {
        bail!("the parent-link array would hold {} nodes; the layout addresses at most {}", base as usize + n, MAX_NODES - 1);
    }
    let empty = GpuParentNode { bmin: [f32::INFINITY; 3], parent: 0, bmax: [f32::NEG_INFINITY; 3], leaf: 0 };
    let mut out = vec![empty; n + 1];
    let mut next_pair = base + 2;
    // (source node, destination index, parent destination, parent's split axis)
    let mut stack = vec![(0u32, base, base, 0u32)];
    while let Some((src, dst, parent, parent_axis)) = stack.pop() {
        let node = &bvh.nodes[src as usize];
        let (leaf, axis) = match node.kind {
            NodeKind::Leaf { first, count } => ((first << LEAF_COUNT_BITS) | count, 0),
            NodeKind::Interior { left, right } => {
                let (cl, cr) = (bvh.nodes[left as usize].bounds.center(), bvh.nodes[right as usize].bounds.center());
                let d = (cr - cl).abs();
                let axis = if d.x >= d.y && d.x >= d.z {
                    0
                } else if d.y >= d.z {
                    1
                } else {
                    2
                };
                let (even, odd) = if cl[axis] <= cr[axis] { (left, right) } else { (right, left) };
                let pair = next_pair;
                next_pair += 2;
                stack.push((odd, pair + 1, dst, axis as u32));
                stack.push((even, pair, dst, axis as u32));
                (pair << LEAF_COUNT_BITS, axis as u32)
            }
        };
        out[(dst - base) as usize] =
            GpuParentNode { bmin: node.bounds.min.to_array(), parent: (parent << 4) | (axis << 2) | parent_axis, bmax: node.bounds.max.to_array(), leaf };
    }
    Ok(out)
}

/// Where the walk came from (Hapala et al. 2011, fig. 2; the paper's state names).
#[derive(Clone, Copy, PartialEq, Eq)]
#[allow(clippy::enum_variant_names)]
pub(super) enum State {
    FromParent,
    FromSibling,
    FromChild,
}

/// The near child of an interior node whose even child is `even`, split on `axis`.
pub(super) fn near_child(even: u32, axis: u32, dir: Vec3) -> u32 {
    if dir[axis as usize] >= 0.0 {
        even
    } else {
        even + 1
    }
}

/// CPU twin of `traverse` in traverse_parent_link.glsl.
pub fn trace(nodes: &[GpuParentNode], tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let r = RayPre::new(ray);
    let dir = Vec3::from(ray.direction);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    let Some(root) = nodes.first() else { return hit };
    hit.nodes_visited += 1;
    if intersect_box(&r, root.bmin.into(), root.bmax.into(), tmax).is_none() {
        return hit;
    }
    if leaf_count(root.leaf) != 0 {
        test_leaf(root.leaf, tris, &r, &mut tmax, &mut hit, any_hit);
        return hit;
    }
    let mut current = near_child(root.leaf >> LEAF_COUNT_BITS, (root.parent >> 2) & 3, dir);
    let mut state = State::FromParent;
    // A well-formed array ends the walk back at the root; the step bound (each node is entered
    // at most three times) keeps a malformed one from looping forever.
    let mut steps = 3 * nodes.len() + 3;
    while steps > 0 {
        steps -= 1;
        let Some(node) = nodes.get(current as usize) else { break };
        let parent = node.parent >> 4;
        if state == State::FromChild {
            if current == 0 {
                break;
            }
            if current == near_child(current & !1, node.parent & 3, dir) {
                current ^= 1;
                state = State::FromSibling;
            } else {
                current = parent;
            }
            continue;
        }
        hit.nodes_visited += 1;
        let entered = intersect_box(&r, node.bmin.into(), node.bmax.into(), tmax).is_some();
        if entered && leaf_count(node.leaf) == 0 {
            current = near_child(node.leaf >> LEAF_COUNT_BITS, (node.parent >> 2) & 3, dir);
            state = State::FromParent;
            continue;
        }
        if entered && test_leaf(node.leaf, tris, &r, &mut tmax, &mut hit, any_hit) && any_hit {
            return hit;
        }
        // Done with this node: the far sibling is next if this was the near one, else go up.
        if state == State::FromParent {
            current ^= 1;
            state = State::FromSibling;
        } else {
            current = parent;
            state = State::FromChild;
        }
    }
    hit
}
