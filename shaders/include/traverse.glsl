// The traversal interface every tracing shader uses: traverse(), trace_closest() and occluded(),
// returning a Hit (leaf.glsl). The BVH layout behind them is the one the shader variant's
// LAYOUT_* define names: host/build.rs compiles each tracing shader once per layout in
// host/accel/kinds.rs and generates bvh_walk.glsl, which includes that layout's
// traverse_<id>.glsl. Each of those defines `Hit traverse(origin, dir, tmin, tmax, any_hit)` and
// names its CPU twin in its first lines.
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL
#include "leaf.glsl"
#include "bvh_walk.glsl"

// Closest hit along origin + t*dir for tmin < t < tmax.
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax) {
    return traverse(origin, dir, tmin, tmax, false);
}

// Shadow query: is anything opaque between origin + tmin*dir and origin + tmax*dir?
bool occluded(vec3 origin, vec3 dir, float tmin, float tmax) {
    return traverse(origin, dir, tmin, tmax, true).prim != PRIM_NONE;
}

#endif
