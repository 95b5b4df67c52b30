// A two-level BVH's instances (accel::two_level, GpuInstance): their texel buffer, the decode,
// and the transforms by their rows. Only the TWO_LEVEL builds include it.
#ifndef VKRT_INSTANCE_GLSL
#define VKRT_INSTANCE_GLSL
#include "bvh_bindings.glsl"

// GpuInstance, 144 B: three world-to-object rows, three object-to-world rows, then root,
// prim_base, flags, shading_base; grid_origin, order_nodes; grid_scale, node_end.
#define INSTANCE_TEXELS 9u
layout(set = 0, binding = BINDING_INSTANCES) uniform utextureBuffer instance_texels;

GpuInstance load_instance(uint i) {
    GpuInstance inst;
    for (uint k = 0u; k < 3u; k++) {
        inst.world_to_object[k] = uintBitsToFloat(texelFetch(instance_texels, int(INSTANCE_TEXELS * i + k)));
        inst.object_to_world[k] = uintBitsToFloat(texelFetch(instance_texels, int(INSTANCE_TEXELS * i + 3u + k)));
    }
    uvec4 w = texelFetch(instance_texels, int(INSTANCE_TEXELS * i + 6u));
    inst.root = w.x;
    inst.prim_base = w.y;
    inst.flags = w.z;
    inst.shading_base = w.w;
    uvec4 x = texelFetch(instance_texels, int(INSTANCE_TEXELS * i + 7u));
    inst.grid_origin = uintBitsToFloat(x.xyz);
    inst.order_nodes = x.w;
    uvec4 y = texelFetch(instance_texels, int(INSTANCE_TEXELS * i + 8u));
    inst.grid_scale = uintBitsToFloat(y.xyz);
    inst.node_end = y.w;
    return inst;
}

// One row of a transform applied to (v, w), summed left to right and never fused into an fma
// (`precise`), as the CPU twin's accel::two_level::row_dot (and glam's transform_point3, with
// which the loaders place expanded copies).
float row_dot(vec4 row, vec3 v, float w) {
    precise float a = row.x * v.x;
    precise float b = row.y * v.y;
    precise float c = row.z * v.z;
    precise float d = row.w * w;
    precise float s = ((a + b) + c) + d;
    return s;
}

vec3 transform_point(vec4 rows[3], vec3 p) {
    return vec3(row_dot(rows[0], p, 1.0), row_dot(rows[1], p, 1.0), row_dot(rows[2], p, 1.0));
}

vec3 transform_dir(vec4 rows[3], vec3 d) {
    return vec3(row_dot(rows[0], d, 0.0), row_dot(rows[1], d, 0.0), row_dot(rows[2], d, 0.0));
}

// A unit vector, or zero where `v` has no direction (glam's normalize_or_zero, which the
// loaders normalise vertex normals with).
vec3 normalize_or_zero(vec3 v) {
    float len = length(v);
    return (len > 0.0 && !isinf(len)) ? v / len : vec3(0.0);
}

// An object-space normal in the world: by the inverse transpose of the placement's linear part,
// the transpose of the world-to-object rows' (as scene::instance::Placement places vertex
// normals), normalised.
vec3 normal_to_world(GpuInstance inst, vec3 n) {
    vec4 r0 = inst.world_to_object[0], r1 = inst.world_to_object[1], r2 = inst.world_to_object[2];
    return normalize_or_zero(vec3(r0.x * n.x + r1.x * n.y + r2.x * n.z, r0.y * n.x + r1.y * n.y + r2.y * n.z, r0.z * n.x + r1.z * n.y + r2.z * n.z));
}

#endif
