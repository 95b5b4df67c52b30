// Stackless walk of the compact threaded BVH: the threaded walk (traverse_threaded.glsl) over
// 16-byte nodes whose boxes are 16-bit cells of a grid over the scene (push.grid_origin,
// push.grid_scale). CPU twin: accel::compact::trace (host/accel/compact.rs), which also explains the
// encoding and why the decoded boxes are conservative.
#ifndef VKRT_TRAVERSE_COMPACT_GLSL
#define VKRT_TRAVERSE_COMPACT_GLSL
#include "leaf.glsl"

// 16 B: one texel.
#define BVH_NODE_TEXELS 1u
GpuCompactNode load_node(uint i) {
    uvec4 a = texelFetch(node_texels, int(i));
    return GpuCompactNode(a.x, a.y, a.z, a.w);
}

// Corners of cells q of the grid (origin, scale): a product and a sum, never fused (`precise`),
// exactly as QuantGrid::decode computes them.
vec3 decode_cells(uvec3 q, vec3 origin, vec3 scale) {
    precise vec3 corner = origin + vec3(q) * scale;
    return corner;
}

// Whether the ray enters the node's box, decoded on the grid (origin, scale), within
// [tmin, tmax]. CPU twin: accel::compact::enters.
bool compact_box_hit(GpuCompactNode node, vec3 origin, vec3 scale, RayPre r, float tmax) {
    const uint cell_mask = (1u << COMPACT_CELL_BITS) - 1u;
    vec3 bmin = decode_cells(uvec3(node.min_xy & cell_mask, node.min_xy >> COMPACT_CELL_BITS, node.min_z_max_x & cell_mask), origin, scale);
    vec3 bmax = decode_cells(uvec3(node.min_z_max_x >> COMPACT_CELL_BITS, node.max_yz & cell_mask, node.max_yz >> COMPACT_CELL_BITS), origin, scale);
    float t_enter;
    return intersect_box(r, bmin, bmax, tmax, t_enter);
}

#ifdef TWO_LEVEL
// Instanced meshes under a top level (accel::two_level), both levels compact.
#include "traverse_two_level_compact.glsl"
#else
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    RayPre r = ray_pre(origin, dir, tmin, tmax);
    Hit hit = hit_none();
    uint count = node_count();
    // The grid read once, before the loop: lavapipe reads each word of a push constant as a
    // bounds-checked scalar load and a broadcast (six for the grid), and a read inside the loop
    // comes after the node's texel fetch, an opaque call that LLVM must assume may write the
    // push constants, so it stayed in every step (docs/experiments/per-step-cost.md).
    vec3 grid_origin = push.grid_origin;
    vec3 grid_scale = push.grid_scale;
    uint index = 0u;
    while (index < count) {
        GpuCompactNode node = load_node(index);
        hit.nodes_visited++;
        bool leaf = (node.link & COMPACT_LEAF_FLAG) != 0u;
        if (!compact_box_hit(node, grid_origin, grid_scale, r, tmax)) {
            // A leaf's escape is the next node in pre-order.
            index = leaf ? index + 1u : node.link;
            continue;
        }
        if (!leaf) {
            index++;
            continue;
        }
        if (test_leaf(node.link & ~COMPACT_LEAF_FLAG, r, tmax, hit, any_hit) && any_hit) return hit;
        index++;
    }
    return hit;
}
#endif

#endif
