// The traversal interface every tracing shader uses: trace_scene(), trace_closest() and
// occluded(), returning a Hit (leaf.glsl): the triangle list, then the BVH walk, traverse().
// The BVH layout behind the walk is the one the shader variant's LAYOUT_* define names: host/build.rs compiles each tracing shader once per layout in
// host/accel/kinds.rs and generates bvh_walk.glsl, which includes that layout's
// traverse_<id>.glsl. Each of those defines `Hit traverse(origin, dir, tmin, tmax, any_hit)` and
// names its CPU twin in its first lines.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL
#include "leaf.glsl"
#include "bvh_walk.glsl"
#include "triangle_list.glsl"

// The scene's closest hit (any_hit false) or any hit along origin + t*dir, tmin < t < tmax:
// the triangle list (triangle_list.glsl), then the BVH walk up to the list's hit; an any-hit
// query walks only if the list found nothing. Counters: the walk's nodes, both's triangles.
// `between`: the interval runs between two points of the scene (triangle_list.glsl: the list's
// walls are skipped). CPU twin: accel::FlatBvh::trace.
Hit trace_scene(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit, bool between) {
    Hit h;
    // A block on the specialization constant, not an early return: lavapipe would inline the
    // walk into the dead branch before removing it (docs/experiments/pipeline-creation-time.md).
    if (LIST_TRIANGLES > 0u) {
        h = trace_list(ray_pre(origin, dir, tmin, tmax), tmax, between);
        if (!(any_hit && h.prim != PRIM_NONE)) {
            // Up to the list's hit; tmax itself otherwise (min() might drop a NaN tmax).
            Hit walked = traverse(origin, dir, tmin, h.prim != PRIM_NONE ? h.t : tmax, any_hit);
            uint listed_tests = h.tris_tested;
            if (walked.prim != PRIM_NONE) h = walked;
            h.nodes_visited = walked.nodes_visited;
            h.tris_tested = listed_tests + walked.tris_tested;
        }
    } else {
        h = traverse(origin, dir, tmin, tmax, any_hit);
    }
    return h;
}

// Closest hit along origin + t*dir for tmin < t < tmax.
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return trace_scene(origin, dir, tmin, tmax, false, false);
}

// Shadow query: is anything opaque between origin + tmin*dir and origin + tmax*dir? `between`:
// both ends are points of the scene (surface points moved off their surface toward the side
// they are seen from, or a point light's position; host/accel/walls.rs), so the list's walls
// cannot be in the way; false for a ray that leaves the scene (a directional light, the
// environment map).
bool occluded(vec3 origin, vec3 dir, float tmin, float tmax, bool between) {
    return trace_scene(origin, dir, tmin, tmax, true, between).prim != PRIM_NONE;
}

#endif
