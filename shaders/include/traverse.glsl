// Stackless traversal of the threaded BVH2. CPU twin: cpu_trace::trace (host/layout/cpu_trace.rs).
//
// Nodes are in depth-first pre-order; a box hit on an interior node continues at the next
// node (its left child), anything else continues at the node's escape link (Smits 1998).
// Closest-hit queries shrink tmax to the best hit, so nodes that start beyond it are skipped.
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

Hit trace_threaded(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    RayPre r = ray_pre(origin, dir, tmin);
    Hit hit;
    hit.t = 1.0 / 0.0;
    hit.prim = PRIM_NONE;
    hit.u = 0.0;
    hit.v = 0.0;
    hit.nodes_visited = 0u;
    hit.tris_tested = 0u;
    hit.slot = 0u;
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    uint index = nodes.length() == 0 ? NODE_NONE : 0u;
    while (index != NODE_NONE) {
        GpuNode node = nodes[index];
        hit.nodes_visited++;
        float t_enter;
        if (!intersect_box(r, node.bmin, node.bmax, tmax, t_enter)) {
            index = node.escape;
            continue;
        }
        uint count = node.leaf & count_mask;
        if (count == 0u) {
            index++;
            continue;
        }
        uint first = node.leaf >> LEAF_COUNT_BITS;
        for (uint i = first; i < first + count; i++) {
            GpuTriangle tri = triangles[i];
            hit.tris_tested++;
            float t, u, v;
            if (intersect_triangle(r, tri.v0, tri.v1, tri.v2, tmax, t, u, v)) {
                tmax = t;
                hit.t = t;
                hit.prim = tri.prim;
                hit.u = u;
                hit.v = v;
                hit.slot = i;
                if (any_hit) return hit;
            }
        }
        index = node.escape;
    }
    return hit;
}

// The interface every integrator uses; layouts differ only behind it.

// Closest hit along origin + t*dir for tmin < t < tmax.
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_threaded(origin, dir, tmin, tmax, false);
}

// Shadow query: is anything opaque between origin + tmin*dir and origin + tmax*dir?
bool occluded(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_threaded(origin, dir, tmin, tmax, true).prim != PRIM_NONE;
}

#endif
