//! What every layout's walk shares besides the box and triangle tests: the packed leaf word,
//! the leaf test (CPU twin of `test_leaf` in shaders/include/traverse.glsl), the miss record,
//! and the brute-force reference at the root of the agreement chain.

use super::intersect::{intersect_triangle, RayPre};
use crate::gpu_abi::constants::{LEAF_COUNT_BITS, PRIM_NONE};
use crate::gpu_abi::{GpuHit, GpuRay, GpuTriangle};

/// A miss, as the shader writes it.
pub fn miss() -> GpuHit {
    GpuHit { t: f32::INFINITY, prim: PRIM_NONE, u: 0.0, v: 0.0, nodes_visited: 0, tris_tested: 0, _pad0: 0, _pad1: 0 }
}

/// The triangle count of a packed leaf word; 0 for an interior node.
pub fn leaf_count(leaf: u32) -> u32 {
    leaf & ((1u32 << LEAF_COUNT_BITS) - 1)
}

/// `test_leaf` in traverse.glsl: test a leaf's triangles in order, shrinking `tmax` and
/// updating `hit` on each closer hit; true if any triangle was hit. An any-hit query stops at
/// the first hit: any opaque hit answers it.
pub fn test_leaf(leaf: u32, tris: &[GpuTriangle], r: &RayPre, tmax: &mut f32, hit: &mut GpuHit, any_hit: bool) -> bool {
    let first = leaf >> LEAF_COUNT_BITS;
    let mut found = false;
    for i in first..first + leaf_count(leaf) {
        let Some(tri) = tris.get(i as usize) else { break };
        hit.tris_tested += 1;
        if let Some(h) = intersect_triangle(r, tri.v0.into(), tri.v1.into(), tri.v2.into(), *tmax) {
            *tmax = h.t;
            hit.t = h.t;
            hit.prim = tri.prim;
            hit.u = h.u;
            hit.v = h.v;
            found = true;
            if any_hit {
                break;
            }
        }
    }
    found
}

/// Brute force over every triangle, in primitive-id order: the root of the agreement chain.
pub fn brute_force(tris: &[crate::scene::Triangle], ray: &GpuRay) -> GpuHit {
    let r = RayPre::new(ray);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    for (prim, t) in tris.iter().enumerate() {
        hit.tris_tested += 1;
        if let Some(h) = intersect_triangle(&r, t.p[0], t.p[1], t.p[2], tmax) {
            tmax = h.t;
            hit = GpuHit { t: h.t, prim: prim as u32, u: h.u, v: h.v, ..hit };
        }
    }
    hit
}
