// Stackless walk of a threaded BVH2 (GpuNode), shared by the threaded and multi-order layouts.
// CPU twin: accel::threaded::trace_threaded_from (host/accel/threaded.rs).
//
// Nodes are in depth-first pre-order; a box hit on an interior node continues at the next
// node (its first child), anything else continues at the node's escape link (Smits 1998).
// Closest-hit queries shrink tmax to the best hit, so nodes that start beyond it are skipped.
#ifndef VKRT_THREADED_WALK_GLSL
#define VKRT_THREADED_WALK_GLSL
#include "leaf.glsl"

// 32 B: bmin, escape | bmax, leaf.
#define BVH_NODE_TEXELS 2u
GpuNode load_node(uint i) {
    uvec4 a = texelFetch(node_texels, int(BVH_NODE_TEXELS * i));
    uvec4 b = texelFetch(node_texels, int(BVH_NODE_TEXELS * i + 1u));
    return GpuNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}

// The multi-order layout's order for a ray of direction `dir` (r = ray_pre of it): that of its
// largest |direction| component (the shear axis kz) and its sign. CPU twin:
// accel::multi_order::ray_order.
uint ray_order(RayPre r, vec3 dir) {
    return 2u * uint(r.kz) + (dir[r.kz] < 0.0 ? 1u : 0u);
}

Hit traverse_threaded_from(uint start, RayPre r, float tmax, bool any_hit) {
    Hit hit = hit_none();
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    uint index = start < node_count() ? start : NODE_NONE;
    while (index != NODE_NONE) {
        GpuNode node = load_node(index);
        hit.nodes_visited++;
        float t_enter;
        if (!intersect_box(r, node.bmin, node.bmax, tmax, t_enter)) {
            index = node.escape;
            continue;
        }
        if ((node.leaf & count_mask) == 0u) {
            index++;
            continue;
        }
        if (test_leaf(node.leaf, r, tmax, hit, any_hit) && any_hit) return hit;
        index = node.escape;
    }
    return hit;
}

#endif
