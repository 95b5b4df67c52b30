// Parent-linked BVH2 walked by the stackless state machine of Hapala et al. 2011, "Efficient
// stack-less BVH traversal for ray tracing". CPU twin: accel::parent_link::trace
// (host/accel/parent_link.rs), which documents the encoding. Siblings are pairs (2k, 2k+1),
// so a sibling is index ^ 1; the even child is the near one for a direction >= 0 on the
// node's split axis.
#ifndef VKRT_TRAVERSE_PARENT_LINK_GLSL
#define VKRT_TRAVERSE_PARENT_LINK_GLSL
#include "leaf.glsl"

// 32 B: bmin, parent | bmax, leaf.
#define BVH_NODE_TEXELS 2u
GpuParentNode load_node(uint i) {
    uvec4 a = texelFetch(node_texels, int(BVH_NODE_TEXELS * i));
    uvec4 b = texelFetch(node_texels, int(BVH_NODE_TEXELS * i + 1u));
    return GpuParentNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}

const uint FROM_PARENT = 0u;
const uint FROM_SIBLING = 1u;
const uint FROM_CHILD = 2u;

uint near_child(uint even, uint axis, vec3 dir) {
    return dir[axis] >= 0.0 ? even : even + 1u;
}

#ifdef TWO_LEVEL
// Instanced meshes under a top level (accel::two_level), both levels parent-linked.
#include "traverse_two_level_parent_link.glsl"
#else
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    RayPre r = ray_pre(origin, dir, tmin, tmax);
    Hit hit = hit_none();
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    uint count = node_count();
    if (count == 0u) return hit;
    GpuParentNode root = load_node(0);
    hit.nodes_visited++;
    float t_enter;
    if (!intersect_box(r, root.bmin, root.bmax, tmax, t_enter)) return hit;
    if ((root.leaf & count_mask) != 0u) {
        test_leaf(root.leaf, r, tmax, hit, any_hit);
        return hit;
    }
    uint current = near_child(root.leaf >> LEAF_COUNT_BITS, (root.parent >> 2) & 3u, dir);
    uint state = FROM_PARENT;
    // Each node is entered at most three times; the bound only guards a malformed array.
    uint steps = 3u * count + 3u;
    while (steps > 0u) {
        steps--;
        if (current >= count) break;
        GpuParentNode node = load_node(current);
        uint parent = node.parent >> 4;
        if (state == FROM_CHILD) {
            if (current == 0u) break;
            if (current == near_child(current & ~1u, node.parent & 3u, dir)) {
                current ^= 1u;
                state = FROM_SIBLING;
            } else {
                current = parent;
            }
            continue;
        }
        hit.nodes_visited++;
        bool entered = intersect_box(r, node.bmin, node.bmax, tmax, t_enter);
        if (entered && (node.leaf & count_mask) == 0u) {
            current = near_child(node.leaf >> LEAF_COUNT_BITS, (node.parent >> 2) & 3u, dir);
            state = FROM_PARENT;
            continue;
        }
        if (entered && test_leaf(node.leaf, r, tmax, hit, any_hit) && any_hit) return hit;
        // Done with this node: the far sibling is next if this was the near one, else go up.
        if (state == FROM_PARENT) {
            current ^= 1u;
            state = FROM_SIBLING;
        } else {
            current = parent;
            state = FROM_CHILD;
        }
    }
    return hit;
}
#endif

#endif
