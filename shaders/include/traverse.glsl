// The traversal interface every integrator uses: trace_closest() and occluded(), returning a Hit.
// The BVH layout behind them is picked at compile time by a define per shader variant
// (host/pipeline/variants.rs): LAYOUT_MULTI_ORDER, LAYOUT_PARENT_LINK, LAYOUT_COMPACT, LAYOUT_WIDE, or none
// (threaded);
// PACKET_TRAVERSAL walks the threaded layout a subgroup at a time (trace.comp only).
// Each layout file defines `Hit traverse(origin, dir, tmin, tmax, any_hit)`; its CPU twin is named
// in its first line.
// Needs bvh_bindings.glsl and intersect.glsl.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL

struct Hit {
    float t;
    uint prim;
    float u;
    float v;
    // Instrumentation: boxes tested and triangles tested for this query.
    uint nodes_visited;
    uint tris_tested;
    // Index of the hit triangle in leaf order (triangles[]), for fetching its vertices.
    uint slot;
};

Hit hit_none() {
    Hit hit;
    hit.t = 1.0 / 0.0;
    hit.prim = PRIM_NONE;
    hit.u = 0.0;
    hit.v = 0.0;
    hit.nodes_visited = 0u;
    hit.tris_tested = 0u;
    hit.slot = 0u;
    return hit;
}

// Test a leaf's triangles in order, shrinking tmax and updating hit on each closer hit; true if
// any was hit. An any-hit query stops at the first hit. CPU twin: cpu_trace::test_leaf.
bool test_leaf(uint leaf, RayPre r, inout float tmax, inout Hit hit, bool any_hit) {
    uint first = leaf >> LEAF_COUNT_BITS;
    uint count = leaf & ((1u << LEAF_COUNT_BITS) - 1u);
    bool found = false;
    for (uint i = first; i < first + count; i++) {
        GpuTriangle tri = load_triangle(i);
        hit.tris_tested++;
        float t, u, v;
        if (intersect_triangle(r, tri.v0, tri.v1, tri.v2, tmax, t, u, v)) {
#ifdef VKRT_ALPHA_GLSL
            // A see-through texel is no hit at all (alpha.glsl).
            if (!alpha_passes(tri.prim, u, v)) continue;
#endif
            tmax = t;
            hit.t = t;
            hit.prim = tri.prim;
            hit.u = u;
            hit.v = v;
            hit.slot = i;
            found = true;
            if (any_hit) break;
        }
    }
    return found;
}

#if defined(LAYOUT_PARENT_LINK)
#include "traverse_parent_link.glsl"
#elif defined(PACKET_TRAVERSAL)
// The threaded layout walked by whole subgroups (experiment; needs the subgroup vote extension).
#include "traverse_packet.glsl"
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    return traverse_packet_from(0u, ray_pre(origin, dir, tmin), tmax, any_hit);
}
#elif defined(LAYOUT_COMPACT)
#include "traverse_compact.glsl"
#elif defined(LAYOUT_WIDE)
#include "traverse_wide.glsl"
#elif defined(LAYOUT_MULTI_ORDER)
#include "traverse_threaded.glsl"
#include "traverse_multi_order.glsl"
#else
#include "traverse_threaded.glsl"
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    return traverse_threaded_from(0u, ray_pre(origin, dir, tmin), tmax, any_hit);
}
#endif

// Closest hit along origin + t*dir for tmin < t < tmax.
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return traverse(origin, dir, tmin, tmax, false);
}

// Shadow query: is anything opaque between origin + tmin*dir and origin + tmax*dir?
bool occluded(vec3 origin, vec3 dir, float tmin, float tmax) {
    return traverse(origin, dir, tmin, tmax, true).prim != PRIM_NONE;
}

#endif
