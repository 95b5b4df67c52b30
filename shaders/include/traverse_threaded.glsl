// Stackless walk of a threaded BVH2. CPU twin: cpu_trace::trace_threaded_from (host/layout/cpu_trace.rs).
//
// Nodes are in depth-first pre-order; a box hit on an interior node continues at the next
// node (its first child), anything else continues at the node's escape link (Smits 1998).
// Closest-hit queries shrink tmax to the best hit, so nodes that start beyond it are skipped.
#ifndef VKRT_TRAVERSE_THREADED_GLSL
#define VKRT_TRAVERSE_THREADED_GLSL

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
