// What the two-level walks (traverse_two_level*.glsl, one per layout of the levels) do alike at
// an instance: go into its object space, and make a hit in its mesh the scene's. CPU twins:
// accel::two_level::object_ray and InObject (host/accel/two_level.rs).
#ifndef VKRT_INSTANCE_WALK_GLSL
#define VKRT_INSTANCE_WALK_GLSL
#include "leaf.glsl"
#include "instance.glsl"

// What a walk carries while in an instance's mesh.
struct InstanceWalk {
    // The instance (Hit::instance).
    uint index;
    uint prim_base;
    bool mirrored;
};

// Enters instance `i` for the query (origin, dir, tmin, and `tmax0`, the query's own tmax): the
// ray in its object space, its direction `object_dir` not renormalised (so t, tmin and tmax keep
// their world meaning and one tmax serves both levels); what its hits need (`walk`); its mesh's
// shading data for the leaf tests (leaf_shading_base). Returns the instance.
GpuInstance enter_instance(uint i, vec3 origin, vec3 dir, float tmin, float tmax0, out RayPre r, out vec3 object_dir, out InstanceWalk walk) {
    GpuInstance inst = load_instance(i);
    object_dir = transform_dir(inst.world_to_object, dir);
    r = ray_pre(transform_point(inst.world_to_object, origin), object_dir, tmin, tmax0);
    walk = InstanceWalk(i, inst.prim_base, (inst.flags & INSTANCE_MIRRORED) != 0u);
    leaf_shading_base = inst.shading_base;
    return inst;
}

// Back in the top level (or done): the scene's own shading data again.
void leave_instance() {
    leaf_shading_base = 0u;
}

// A hit in the instance's mesh as the scene's: its primitive id among the placed copies, the
// instance, and its barycentrics in the placed triangle's vertex order (a mirroring instance
// swaps the second and third vertices).
void hit_in_world(inout Hit hit, InstanceWalk walk) {
    hit.prim += walk.prim_base;
    hit.instance = walk.index;
    hit.mirrored = walk.mirrored;
    if (walk.mirrored) {
        float u = hit.u;
        hit.u = hit.v;
        hit.v = u;
    }
}

#endif
