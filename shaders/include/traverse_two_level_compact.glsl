// The two-level walk over instanced meshes with compact levels (the `_two_level_compact` build of
// every tracing shader: TWO_LEVEL with LAYOUT_COMPACT): a compact threaded top level over the
// instances' world boxes, its boxes cells of a grid over its root box (push.grid_origin,
// push.grid_scale; its push.top_nodes nodes from 0), whose leaves each name an instance, and a
// compact tree per mesh in object space, its boxes cells of a grid over the mesh's root box (the
// instance's grid_origin, grid_scale; its nodes from the instance's root to its node_end). Each
// level is the compact walk of traverse_compact.glsl. CPU twin: accel::two_level::trace_compact
// (host/accel/two_level.rs), which says why it is built so.
//
// Stackless with O(1) more state than the compact walk: at a top-level leaf the ray goes into the
// instance's object space (direction not renormalised: t, tmin and tmax keep their world
// meaning), walks the mesh's tree on the mesh's grid until its end, and goes on in the top level
// at the node after the leaf, on the top level's grid, with the world ray again.
#ifndef VKRT_TRAVERSE_TWO_LEVEL_COMPACT_GLSL
#define VKRT_TRAVERSE_TWO_LEVEL_COMPACT_GLSL
#include "instance_walk.glsl"

Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    float tmax0 = tmax;
    RayPre world = ray_pre(origin, dir, tmin, tmax);
    RayPre r = world;
    Hit hit = hit_none();
    uint index = 0u;
    uint end = min(push.top_nodes, node_count());
    vec3 grid_origin = push.grid_origin;
    vec3 grid_scale = push.grid_scale;
    // While in a mesh's tree: where the top level goes on, and what the instance's hits need.
    bool in_object = false;
    uint resume = 0u;
    InstanceWalk walk = InstanceWalk(0u, 0u, false);
    while (true) {
        if (index >= end) {
            if (!in_object) break;
            index = resume;
            end = min(push.top_nodes, node_count());
            grid_origin = push.grid_origin;
            grid_scale = push.grid_scale;
            r = world;
            in_object = false;
            leave_instance();
            continue;
        }
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
        uint word = node.link & ~COMPACT_LEAF_FLAG;
        if (!in_object) {
            vec3 object_dir;
            GpuInstance inst = enter_instance(word >> LEAF_COUNT_BITS, origin, dir, tmin, tmax0, r, object_dir, walk);
            resume = index + 1u;
            index = inst.root;
            end = min(inst.node_end, node_count());
            grid_origin = inst.grid_origin;
            grid_scale = inst.grid_scale;
            in_object = true;
            continue;
        }
        if (test_leaf(word, r, tmax, hit, any_hit)) {
            hit_in_world(hit, walk);
            if (any_hit) {
                leave_instance();
                return hit;
            }
        }
        index++;
    }
    return hit;
}

#endif
