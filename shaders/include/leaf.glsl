// What every layout's walk shares: the hit record (with the traversal counters) and the leaf
// test. CPU twin: host/accel/leaf.rs.
//
// ALPHA_TEST (a define of the integrators' shader variants, host/pipeline/variants.rs) makes
// the leaf test skip see-through texels (alpha.glsl), so that closest-hit and shadow queries of
// every layout pass through cut-outs; without it (trace.comp) rays see geometry only.
#ifndef VKRT_LEAF_GLSL
#define VKRT_LEAF_GLSL
#include "bvh_bindings.glsl"
#ifdef ALPHA_TEST
#include "alpha.glsl"
#endif
#include "intersect.glsl"

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
    // The hit triangle's entry in the shading data (BINDING_SHADING, _UVS, _TANGENTS): its
    // primitive id, or in a two-level BVH its mesh's entry (GpuTriangle::shading).
    uint shading;
    // The instance hit in a two-level BVH (TWO_LEVEL builds, traverse_two_level.glsl): the
    // triangle's vertices and shading data are in its object space, in the mesh's vertex order,
    // which a mirroring instance swaps (`mirrored`; u and v are the world order's). 0 otherwise.
    uint instance;
    bool mirrored;
};

#ifdef TWO_LEVEL
// While the two-level walk (traverse_two_level.glsl) is in an instance's mesh: where the mesh's
// shading data starts (GpuInstance::shading_base); 0 everywhere else.
uint leaf_shading_base = 0u;
#endif

Hit hit_none() {
    Hit hit;
    hit.t = 1.0 / 0.0;
    hit.prim = PRIM_NONE;
    hit.u = 0.0;
    hit.v = 0.0;
    hit.nodes_visited = 0u;
    hit.tris_tested = 0u;
    hit.slot = 0u;
    hit.shading = 0u;
    hit.instance = 0u;
    hit.mirrored = false;
    return hit;
}

// A triangle's entry in the shading data: its primitive id, or in an instance's mesh its
// mesh's entry, whose barycentrics are those of the triangle as the mesh has it (the walk's, in
// object space).
uint shading_entry(GpuTriangle tri) {
#ifdef TWO_LEVEL
    return leaf_shading_base + tri.shading;
#else
    return tri.prim;
#endif
}

// Test one triangle (at `slot` of the triangle array): on a hit closer than tmax, shrink tmax,
// record it in hit and return true; count the test either way. Shared by the leaf test and the
// triangle list (triangle_list.glsl). CPU twins: accel::leaf::test_leaf, accel::triangle_list::trace.
bool test_triangle(GpuTriangle tri, uint slot, RayPre r, inout float tmax, inout Hit hit) {
    hit.tris_tested++;
    float t, u, v;
    if (!intersect_triangle(r, tri.v0, tri.v1, tri.v2, tmax, t, u, v)) return false;
#ifdef ALPHA_TEST
    // A see-through texel is no hit at all (alpha.glsl).
    if (!alpha_passes(shading_entry(tri), u, v, r)) return false;
#endif
    tmax = t;
    hit.t = t;
    hit.prim = tri.prim;
    hit.u = u;
    hit.v = v;
    hit.slot = slot;
    hit.shading = shading_entry(tri);
    return true;
}

// Test a leaf's triangles in order, shrinking tmax and updating hit on each closer hit; true if
// any was hit. An any-hit query stops at the first hit. CPU twin: accel::leaf::test_leaf.
bool test_leaf(uint leaf, RayPre r, inout float tmax, inout Hit hit, bool any_hit) {
    uint first = leaf >> LEAF_COUNT_BITS;
    uint count = leaf & ((1u << LEAF_COUNT_BITS) - 1u);
    bool found = false;
    for (uint i = first; i < first + count; i++) {
        if (test_triangle(load_triangle(i), i, r, tmax, hit)) {
            found = true;
            if (any_hit) break;
        }
    }
    return found;
}

#endif
