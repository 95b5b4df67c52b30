// Multi-order threaded BVH: six threaded orders, one per dominant ray axis and sign, each
// visiting children near-first. CPU twin: accel::multi_order::trace (host/accel/multi_order.rs).
#ifndef VKRT_TRAVERSE_MULTI_ORDER_GLSL
#define VKRT_TRAVERSE_MULTI_ORDER_GLSL
#include "threaded_walk.glsl"

Hit traverse(vec3 origin, vec3 dir, float tmin, float tmax, bool any_hit) {
    RayPre r = ray_pre(origin, dir, tmin, tmax);
    uint per_order = node_count() / 6u;
    return traverse_threaded_from(ray_order(r, dir) * per_order, r, tmax, any_hit);
}

#endif
