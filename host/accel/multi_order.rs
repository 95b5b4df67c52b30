//! The multi-order threaded BVH: six threaded (escape-link) orders of the same tree, one per
//! dominant ray direction axis and sign. In order `2 * axis + negative` every interior node's
//! children are visited nearer-centre-first along that axis and sign, so a ray picks the order
//! of its dominant direction component and walks its tree roughly front to back without a
//! stack: closer hits come early and shrink tmax, and far subtrees are culled by the box test.
//! (The idea of precomputed per-direction traversal orders goes back to the "ray direction
//! octant" orders of Smits 1998 and is used by e.g. tinybvh's BVH_GPU variants; the six-order
//! form here is ours.)
//!
//! Memory: six copies of the 32-byte nodes (6 x 32 B = 192 B per node), triangles shared.
//! Traversal is exactly the threaded one from a different start (`order * nodes_per_order`);
//! escape links are absolute indices into the concatenated array. Shader:
//! `shaders/include/traverse_multi_order.glsl`.

use super::intersect::RayPre;
use super::threaded::{threaded, trace_threaded_from};
use super::{node_array, LayoutKind};
use crate::bvh::Bvh;
use crate::gpu_abi::{GpuHit, GpuNode, GpuRay, GpuTriangle};

/// Number of orders: (x, y, z) x (+, -).
pub const ORDERS: usize = 6;

node_array!(MultiOrder, GpuNode, LayoutKind::MultiOrder, "The multi-order node array.");

/// The six orders, concatenated: order `o` occupies `o * n .. (o + 1) * n` for n tree nodes.
pub fn flatten(bvh: &Bvh) -> Vec<GpuNode> {
    orders(bvh, 0)
}

/// [`flatten`]'s six orders with their escape links offset by `base`, where the array will
/// start in a concatenation (a two-level BVH's levels, `two_level`).
pub fn orders(bvh: &Bvh, base: u32) -> Vec<GpuNode> {
    let n = bvh.nodes.len();
    let mut out = Vec::with_capacity(ORDERS * n);
    for order in 0..ORDERS {
        let axis = order / 2;
        let negative = order % 2 == 1;
        let key = |i: u32| bvh.nodes[i as usize].bounds.center()[axis];
        let child_order = |_: usize, left: u32, right: u32| {
            // Near child first: smaller centre for a positive direction, larger for negative.
            let left_first = if negative { key(left) >= key(right) } else { key(left) <= key(right) };
            if left_first {
                (left, right)
            } else {
                (right, left)
            }
        };
        out.extend(threaded(bvh, child_order, base + (order * n) as u32));
    }
    out
}

/// `ray_order` in the shader: 2 * (axis of the largest |direction| component) + (1 if that
/// component is negative). The same axis the watertight triangle test shears along (kz).
pub fn ray_order(r: &RayPre, ray: &GpuRay) -> usize {
    2 * r.kz + usize::from(ray.direction[r.kz] < 0.0)
}

/// CPU twin of `traverse` in traverse_multi_order.glsl.
pub fn trace(nodes: &[GpuNode], tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let r = RayPre::new(ray);
    let per_order = nodes.len() / ORDERS;
    let start = (ray_order(&r, ray) * per_order) as u32;
    trace_threaded_from(nodes, start, tris, &r, ray.tmax, any_hit)
}
