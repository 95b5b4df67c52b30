// The triangle list: the scene's few largest triangles (a room's walls), kept out of the BVH and
// tested by every ray before its walk. host/accel/triangle_list.rs says why and chooses them;
// it is also the CPU twin of trace_list.
//
// The loop is unrolled for the list's size (a specialization constant), so every triangle is
// read at a constant offset of a uniform block: lavapipe then loads it once as scalars and
// broadcasts it to the lanes (lp_bld_nir_soa.c, emit_load_ubo on an always-uniform offset),
// where the walk pays a texel-fetch call per node and triangle (docs/experiments/
// triangle-list.md); GPUs read it through their constant cache.
#ifndef VKRT_TRIANGLE_LIST_GLSL
#define VKRT_TRIANGLE_LIST_GLSL
#include "leaf.glsl"

layout(constant_id = SPEC_LIST_TRIANGLES) const uint LIST_TRIANGLES = 0u;

// The block itself, list_triangles[], is declared in bvh_bindings.glsl, where the layout probe
// sees it too (tests/layout.rs).

// The closest hit among the list's triangles below tmax, in list order (a later triangle wins
// only if strictly closer). A ray with an empty interval, or a NaN anywhere (ray_pre gives it
// tmin = +inf), tests nothing, as it fails at a BVH's root. No early exit for any-hit queries:
// the loop is unrolled, and its lanes run every test anyway.
Hit trace_list(RayPre r, float tmax) {
    Hit hit = hit_none();
    if (r.tmin < tmax) {
        [[unroll]] for (uint i = 0u; i < LIST_TRIANGLES; i++) {
            test_triangle(list_triangles[i], push.list_first + i, r, tmax, hit);
        }
    }
    return hit;
}

#endif
