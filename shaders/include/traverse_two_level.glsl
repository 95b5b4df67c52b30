// The two-level walk over instanced meshes (the `_two_level` build of every tracing shader,
// TWO_LEVEL): a threaded top level over the instances' world boxes, whose leaves each name an
// instance, and a threaded tree per mesh in object space, all in one node array; each level in
// one order (the threaded layout) or in the multi-order layout's six, of which the ray takes
// the top level's for its world direction and a mesh's for its object-space direction.
// CPU twin: accel::two_level::trace (host/accel/two_level.rs), which says why it is built so.
//
// Stackless with O(1) more state than the threaded walk: at a top-level leaf the ray goes into
// the instance's object space (direction not renormalised: t, tmin and tmax keep their world
// meaning, so one tmax serves both levels), walks the mesh's tree from its root, and where that
// tree's escape links end (NODE_NONE) goes on in the top level at the leaf's escape link with
// the world ray again.
#ifndef VKRT_TRAVERSE_TWO_LEVEL_GLSL
#define VKRT_TRAVERSE_TWO_LEVEL_GLSL
#include "threaded_walk.glsl"
#include "instance_walk.glsl"

Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    float tmax0 = tmax;
    RayPre world = ray_pre(origin, dir, tmin, tmax);
    RayPre r = world;
    Hit hit = hit_none();
    // push.top_order_nodes and a GpuInstance's order_nodes are 0 where a level has one order.
    uint index = node_count() > 0u ? push.top_order_nodes * ray_order(world, dir) : NODE_NONE;
    // While in a mesh's tree: where the top level goes on, and what the instance's hits need.
    bool in_object = false;
    uint resume = NODE_NONE;
    InstanceWalk walk = InstanceWalk(0u, 0u, false);
    while (true) {
        if (index == NODE_NONE) {
            if (!in_object) break;
            index = resume;
            in_object = false;
            r = world;
            leave_instance();
            continue;
        }
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
        if (!in_object) {
            vec3 object_dir;
            GpuInstance inst = enter_instance(node.leaf >> LEAF_COUNT_BITS, origin, dir, tmin, tmax0, r, object_dir, walk);
            resume = node.escape;
            index = inst.root + inst.order_nodes * ray_order(r, object_dir);
            in_object = true;
            continue;
        }
        if (test_leaf(node.leaf, r, tmax, hit, any_hit)) {
            hit_in_world(hit, walk);
            if (any_hit) {
                leave_instance();
                return hit;
            }
        }
        index = node.escape;
    }
    return hit;
}

#endif
