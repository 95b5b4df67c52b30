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
// Bit i: the list's i-th triangle is a wall, the whole scene on one side of its plane
// (host/accel/walls.rs), which no segment between two points of the scene can cross.
layout(constant_id = SPEC_LIST_WALLS) const uint LIST_WALLS = 0u;

// The block itself, list_triangles[], is declared in bvh_bindings.glsl, where the layout probe
// sees it too (tests/layout.rs).

// The closest hit among the list's triangles below tmax, in list order (a later triangle wins
// only if strictly closer). A ray with an empty interval, or a NaN anywhere (ray_pre gives it
// tmin = +inf), tests nothing, as it fails at a BVH's root. No early exit for any-hit queries:
// the loop is unrolled, and its lanes run every test anyway. `between`: the ray runs between
// two points of the scene (a shadow ray), so the walls are skipped; the unrolled loop's wall
// bits are constants, so a call site whose `between` is constant keeps only its own tests.
Hit trace_list(RayPre r, float tmax, bool between) {
    Hit hit = hit_none();
    if (r.tmin < tmax) {
        [[unroll]] for (uint i = 0u; i < LIST_TRIANGLES; i++) {
            if (!(between && ((LIST_WALLS >> i) & 1u) != 0u)) test_triangle(list_triangles[i], push.list_first + i, r, tmax, hit);
        }
    }
    return hit;
}

#endif
