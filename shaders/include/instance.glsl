// A two-level BVH's instances (accel::two_level, GpuInstance): their texel buffer, the decode,
// and the transforms by their rows. Only the TWO_LEVEL builds include it.
#ifndef VKRT_INSTANCE_GLSL
#define VKRT_INSTANCE_GLSL
#include "bvh_bindings.glsl"

// GpuInstance, 112 B: three world-to-object rows, three object-to-world rows, then root,
// prim_base, flags, pad.
#define INSTANCE_TEXELS 7u
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
    inst._pad0 = 0u;
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

#endif
