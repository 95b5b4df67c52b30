// Stackless walk of the wide (4-ary) BVH: each visit tests a node's four child boxes at once;
// going back up re-enters the parent, restricted to the slots after the one the walk came
// from. CPU twin: accel::wide::trace (host/accel/wide.rs), which documents the collapse, the slot
// order and the encoding.
#ifndef VKRT_TRAVERSE_WIDE_GLSL
#define VKRT_TRAVERSE_WIDE_GLSL
#include "leaf.glsl"

// Eight fetches, one per 16-byte row of GpuWideNode: six rows of child bounds, the child
// words, then parent and info.
#define BVH_NODE_TEXELS 8u
GpuWideNode load_node(uint i) {
    int base = int(BVH_NODE_TEXELS * i);
    vec4 min_x = uintBitsToFloat(texelFetch(node_texels, base));
    vec4 min_y = uintBitsToFloat(texelFetch(node_texels, base + 1));
    vec4 min_z = uintBitsToFloat(texelFetch(node_texels, base + 2));
    vec4 max_x = uintBitsToFloat(texelFetch(node_texels, base + 3));
    vec4 max_y = uintBitsToFloat(texelFetch(node_texels, base + 4));
    vec4 max_z = uintBitsToFloat(texelFetch(node_texels, base + 5));
    uvec4 children = texelFetch(node_texels, base + 6);
    uvec4 link = texelFetch(node_texels, base + 7);
    return GpuWideNode(min_x, min_y, min_z, max_x, max_y, max_z, children, link.x, link.y, 0u, 0u);
}

// Which of the four slots the ray enters within [tmin, tmax], with their entry distances:
// intersect_box for each slot, component for component, so the CPU twin's per-slot calls
// give the same bits.
uint wide_box_mask(RayPre r, GpuWideNode n, float tmax, out vec4 t_enter) {
    precise vec4 tx0 = (n.min_x - r.origin.x) * r.inv_dir.x;
    precise vec4 tx1 = (n.max_x - r.origin.x) * r.inv_dir.x;
    precise vec4 ty0 = (n.min_y - r.origin.y) * r.inv_dir.y;
    precise vec4 ty1 = (n.max_y - r.origin.y) * r.inv_dir.y;
    precise vec4 tz0 = (n.min_z - r.origin.z) * r.inv_dir.z;
    precise vec4 tz1 = (n.max_z - r.origin.z) * r.inv_dir.z;
    vec4 near = sel_max(sel_max(sel_min(tx0, tx1), sel_min(ty0, ty1)), sel_min(tz0, tz1));
    vec4 far = sel_min(sel_min(sel_max(tx0, tx1), sel_max(ty0, ty1)), sel_max(tz0, tz1));
    t_enter = sel_max(vec4(r.tmin), near);
    precise vec4 t_exit = sel_min(vec4(tmax), far) * SLAB_FAR_PAD;
    bvec4 entered = lessThanEqual(t_enter, t_exit);
    uint mask = (entered.x ? 1u : 0u) | (entered.y ? 2u : 0u) | (entered.z ? 4u : 0u) | (entered.w ? 8u : 0u);
    uint count = n.info & ((1u << WIDE_INFO_AXIS_SHIFT) - 1u);
    return mask & ((1u << count) - 1u);
}

// The node's slots still to visit after coming back from slot `from` (WIDE_NO_SLOT: all).
uint wide_slots_after(uint from, bool reverse) {
    if (from == WIDE_NO_SLOT) return 15u;
    return reverse ? (1u << from) - 1u : (14u << from) & 15u;
}

#ifdef TWO_LEVEL
// Instanced meshes under a top level (accel::two_level), both levels wide.
#include "traverse_two_level_wide.glsl"
#else
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    RayPre r = ray_pre(origin, dir, tmin, tmax);
    Hit hit = hit_none();
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    uint count = node_count();
    uint index = 0u;
    uint from = WIDE_NO_SLOT;
    // Each node is entered once from its parent and once back from each child; the bound only
    // guards a malformed array.
    uint steps = 2u * count + 1u;
    while (steps > 0u && index < count) {
        steps--;
        GpuWideNode node = load_node(index);
        hit.nodes_visited++;
        uint axis = (node.info >> WIDE_INFO_AXIS_SHIFT) & 3u;
        bool reverse = (axis == 0u ? dir.x : axis == 1u ? dir.y : dir.z) < 0.0;
        vec4 t_enter;
        uint mask = wide_box_mask(r, node, tmax, t_enter) & wide_slots_after(from, reverse);
        uint next = NODE_NONE;
        while (mask != 0u) {
            int slot = reverse ? findMSB(mask) : findLSB(mask);
            mask &= ~(1u << uint(slot));
            // A leaf of this node found a closer hit: the same answer as re-testing the box.
            // Selects, not a dynamic index: lavapipe would spill the vectors to memory for it.
            float t_slot = slot == 0 ? t_enter.x : slot == 1 ? t_enter.y : slot == 2 ? t_enter.z : t_enter.w;
            if (t_slot > tmax * SLAB_FAR_PAD) continue;
            uint child = slot == 0 ? node.children.x : slot == 1 ? node.children.y : slot == 2 ? node.children.z : node.children.w;
            if ((child & count_mask) == 0u) {
                next = child >> LEAF_COUNT_BITS;
                break;
            }
            if (test_leaf(child, r, tmax, hit, any_hit) && any_hit) return hit;
        }
        if (next != NODE_NONE) {
            index = next;
            from = WIDE_NO_SLOT;
            continue;
        }
        if (node.parent == NODE_NONE) break;
        from = (node.info >> WIDE_INFO_SLOT_SHIFT) & 3u;
        index = node.parent;
    }
    return hit;
}
#endif

#endif
