// The threaded layout: the threaded walk (threaded_walk.glsl) from the root.
// CPU twin: accel::threaded::trace (host/accel/threaded.rs).
#ifndef VKRT_TRAVERSE_THREADED_GLSL
#define VKRT_TRAVERSE_THREADED_GLSL
#include "threaded_walk.glsl"

#ifdef TWO_LEVEL
// Instanced meshes under a top level (accel::two_level), the levels in the threaded or the
// multi-order layout: one build walks both, since the orders are data (the instances' and the
// push constants' nodes per order, 0 for one order).
#include "traverse_two_level.glsl"
#else
Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    return traverse_threaded_from(0u, ray_pre(origin, dir, tmin, tmax), tmax, any_hit);
}
#endif

#endif
