// The two-level walk over instanced meshes with wide levels (the `_two_level_wide` build of every
// tracing shader: TWO_LEVEL with LAYOUT_WIDE): a wide top level over the instances' world boxes,
// whose leaf slots each name an instance, and a wide tree per mesh in object space, all in one
// node array, each level walked by the wide walk of traverse_wide.glsl from its root until it
// would go up from it (a root has no parent). CPU twin: accel::two_level::trace_wide
// (host/accel/two_level.rs), which says why it is built so.
//
// Stackless with O(1) more state than the wide walk: at a top-level leaf slot the ray goes into
// the instance's object space (direction not renormalised: t, tmin and tmax keep their world
// meaning), walks the mesh's tree with slots ordered by the object-space direction, and then
// comes back to the top-level node restricted to the slots after the instance's, with the world
// ray again: the way the wide walk comes back from a child.
#ifndef VKRT_TRAVERSE_TWO_LEVEL_WIDE_GLSL
#define VKRT_TRAVERSE_TWO_LEVEL_WIDE_GLSL
#include "instance_walk.glsl"

Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    float tmax0 = tmax;
    RayPre world = ray_pre(origin, dir, tmin, tmax);
    RayPre r = world;
    vec3 level_dir = dir;
    Hit hit = hit_none();
    uint count = node_count();
    uint index = 0u;
    uint from = WIDE_NO_SLOT;
    // While in a mesh's tree: the top-level node and slot to come back to, and what the
    // instance's hits need.
    bool in_object = false;
    uint resume = 0u;
    uint resume_from = WIDE_NO_SLOT;
    InstanceWalk walk = InstanceWalk(0u, 0u, false);
    while (index < count) {
        GpuWideNode node = load_node(index);
        hit.nodes_visited++;
        // The wide walk's visit (traverse_wide.glsl), written out: a function for the slot
        // loop made lavapipe's code 10-20 % slower.
        uint axis = (node.info >> WIDE_INFO_AXIS_SHIFT) & 3u;
        bool reverse = (axis == 0u ? level_dir.x : axis == 1u ? level_dir.y : level_dir.z) < 0.0;
        vec4 t_enter;
        uint mask = wide_box_mask(r, node, tmax, t_enter) & wide_slots_after(from, reverse);
        uint next = NODE_NONE;
        while (mask != 0u) {
            int slot = reverse ? findMSB(mask) : findLSB(mask);
            mask &= ~(1u << uint(slot));
            // Selects, not a dynamic index: lavapipe would spill the vectors to memory for it.
            float t_slot = slot == 0 ? t_enter.x : slot == 1 ? t_enter.y : slot == 2 ? t_enter.z : t_enter.w;
            if (t_slot > tmax * SLAB_FAR_PAD) continue;
            uint child = slot == 0 ? node.children.x : slot == 1 ? node.children.y : slot == 2 ? node.children.z : node.children.w;
            if ((child & count_mask) == 0u) {
                next = child >> LEAF_COUNT_BITS;
                break;
            }
            if (!in_object) {
                resume = index;
                resume_from = uint(slot);
                next = enter_instance(child >> LEAF_COUNT_BITS, origin, dir, tmin, tmax0, r, level_dir, walk).root;
                in_object = true;
                break;
            }
            if (test_leaf(child, r, tmax, hit, any_hit)) {
                hit_in_world(hit, walk);
                if (any_hit) {
                    leave_instance();
                    return hit;
                }
            }
        }
        if (next != NODE_NONE) {
            index = next;
            from = WIDE_NO_SLOT;
            continue;
        }
        if (node.parent != NODE_NONE) {
            from = (node.info >> WIDE_INFO_SLOT_SHIFT) & 3u;
            index = node.parent;
            continue;
        }
        // Up from a root: the walk is done, or the mesh's tree is and the top level goes on.
        if (!in_object) break;
        index = resume;
        from = resume_from;
        in_object = false;
        r = world;
        level_dir = dir;
        leave_instance();
    }
    leave_instance();
    return hit;
}

#endif
