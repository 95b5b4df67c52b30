// Subgroup-coherent ("packet") walk of the threaded BVH2: the rays of one subgroup follow ONE
// node sequence, after Wald, Slusallek, Benthin & Wagner 2001, "Interactive rendering with
// coherent ray tracing" (there: 4-ray SSE packets, here: the subgroup's SIMD lanes).
// Experiment variant `trace_packet` only (BENCHMARKS.md, "Packet traversal experiment");
// per-ray CPU twin: cpu_trace::trace_threaded_from, whose hits it must equal (tests/packet.rs).
//
// Why: on lavapipe a subgroup is one SIMD vector; per-lane node indices make every node and
// triangle load a gather. Here `index` is subgroup-uniform (it only depends on subgroupAny
// and on loads at uniform addresses), so those loads can be scalar loads plus a broadcast.
//
// Exactness: the packet enters a node if ANY active lane's ray overlaps it, so every node a
// lane's own (threaded) walk would visit is visited, in the same depth-first pre-order. Each
// lane tests a leaf's triangles only when its own box test passed, with its own tmax, and keeps
// its own closest hit: the same hit as traverse_threaded_from.
// Any-hit: a lane with a hit is done (its box tests read as misses); the packet stops when all
// active lanes are done (subgroupAll).
//
// Counters: nodes_visited counts the packet's node visits (the same for every lane of the
// subgroup, at least the lane's own threaded count); tris_tested counts the triangles the lane
// itself tested.
//
// Needs GL_KHR_shader_subgroup_vote and _ballot (core Vulkan 1.1), enabled by the including shader because
// #extension must precede declarations.
#ifndef VKRT_TRAVERSE_PACKET_GLSL
#define VKRT_TRAVERSE_PACKET_GLSL

Hit traverse_packet_from(uint start, RayPre r, float tmax, bool any_hit) {
    Hit hit = hit_none();
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    // `start` comes from a uniform source in every caller (0 or a push constant).
    uint index = start < node_count() ? start : NODE_NONE;
    bool done = false;
    while (index != NODE_NONE) {
        GpuNode node = load_node(index);
        hit.nodes_visited++;
        float t_enter;
        bool overlap = !done && intersect_box(r, node.bmin, node.bmax, tmax, t_enter);
        bool leaf = (node.leaf & count_mask) != 0u;
        // Masked per lane: a lane tests the leaf only if its own box test passed. (Testing
        // the triangles in uniform control flow in every lane measured slower.)
        if (overlap && leaf && test_leaf(node.leaf, r, tmax, hit, any_hit) && any_hit) done = true;
        // Only in uniform control flow: the loop condition is uniform, no lane leaves early.
        if (any_hit && subgroupAll(done)) break;
        // subgroupBroadcastFirst states the uniformity for the compiler's divergence analysis.
        index = subgroupBroadcastFirst((subgroupAny(overlap) && !leaf) ? index + 1u : node.escape);
    }
    return hit;
}

#endif
