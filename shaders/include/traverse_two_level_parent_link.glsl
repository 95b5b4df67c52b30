// The two-level walk over instanced meshes with parent-link levels (the `_two_level_parent_link`
// build of every tracing shader: TWO_LEVEL with LAYOUT_PARENT_LINK): a parent-link top level over
// the instances' world boxes, whose leaves each name an instance, and a parent-link tree per mesh
// in object space, all in one node array of sibling pairs (each tree from an even index), each
// level walked by the state machine of traverse_parent_link.glsl (Hapala et al. 2011) from its
// root until the walk is done with that root. CPU twin: accel::two_level::trace_parent_link
// (host/accel/two_level.rs), which says why it is built so.
//
// Stackless with O(1) more state than the parent-link walk: at a top-level leaf the ray goes into
// the instance's object space (direction not renormalised: t, tmin and tmax keep their world
// meaning), walks the mesh's tree from its root with children ordered by the object-space
// direction, and when done with that root goes on in the top level at the node and state that
// follow the leaf, with the world ray again.
#ifndef VKRT_TRAVERSE_TWO_LEVEL_PARENT_LINK_GLSL
#define VKRT_TRAVERSE_TWO_LEVEL_PARENT_LINK_GLSL
#include "instance_walk.glsl"

// In a level rooted at `root`, the node after `current`, which the walk is done with (`node`: its
// entry), and the state it enters it in: the far sibling if `current` is the near child, else
// the parent. False at the root: the level is done. CPU twin: accel::two_level::next_in_level.
bool next_in_level(GpuParentNode node, inout uint current, out uint state, uint root, vec3 dir) {
    state = FROM_CHILD;
    if (current == root) return false;
    if (current == near_child(current & ~1u, node.parent & 3u, dir)) {
        current ^= 1u;
        state = FROM_SIBLING;
    } else {
        current = node.parent >> 4;
    }
    return true;
}

Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    const uint count_mask = (1u << LEAF_COUNT_BITS) - 1u;
    float tmax0 = tmax;
    RayPre world = ray_pre(origin, dir, tmin, tmax);
    RayPre r = world;
    vec3 level_dir = dir;
    Hit hit = hit_none();
    uint count = node_count();
    uint root = 0u;
    uint current = 0u;
    uint state = FROM_PARENT;
    // While in a mesh's tree: where the top level goes on after its leaf (resume_ok false: the
    // leaf was the top level's root), and what the instance's hits need.
    bool in_object = false;
    uint resume = 0u;
    uint resume_state = FROM_CHILD;
    bool resume_ok = false;
    InstanceWalk walk = InstanceWalk(0u, 0u, false);
    while (current < count) {
        GpuParentNode node = load_node(current);
        if (state != FROM_CHILD) {
            hit.nodes_visited++;
            float t_enter;
            bool entered = intersect_box(r, node.bmin, node.bmax, tmax, t_enter);
            if (entered && (node.leaf & count_mask) == 0u) {
                current = near_child(node.leaf >> LEAF_COUNT_BITS, (node.parent >> 2) & 3u, level_dir);
                state = FROM_PARENT;
                continue;
            }
            if (entered && !in_object) {
                resume = current;
                resume_ok = next_in_level(node, resume, resume_state, root, level_dir);
                root = enter_instance(node.leaf >> LEAF_COUNT_BITS, origin, dir, tmin, tmax0, r, level_dir, walk).root;
                current = root;
                state = FROM_PARENT;
                in_object = true;
                continue;
            }
            if (entered && test_leaf(node.leaf, r, tmax, hit, any_hit)) {
                hit_in_world(hit, walk);
                if (any_hit) {
                    leave_instance();
                    return hit;
                }
            }
        }
        // Done with this node (or back at it from a child): on to the next of its level, or out
        // of a mesh's tree to where the top level goes on.
        if (!next_in_level(node, current, state, root, level_dir)) {
            if (!in_object || !resume_ok) break;
            current = resume;
            state = resume_state;
            in_object = false;
            root = 0u;
            r = world;
            level_dir = dir;
            leave_instance();
        }
    }
    leave_instance();
    return hit;
}

#endif
