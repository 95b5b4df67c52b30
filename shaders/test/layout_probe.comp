#version 460
// Declares every GPU struct and binding so tests/layout.rs can read their offsets, sizes,
// strides and binding numbers from one SPIR-V module. Never dispatched.
#extension GL_GOOGLE_include_directive : require
// The BVH bindings are texel buffers in the real shaders; here they are struct arrays.
#define LAYOUT_PROBE

#include "scene_bindings.glsl"
#include "path_bindings.glsl"

layout(local_size_x = 1) in;

// The BVH arrays are texel buffers in the shaders (bvh_bindings.glsl); declared as blocks here
// only so their structs' offsets and strides can be read back.
layout(std430, set = 0, binding = BINDING_NODES) readonly buffer Nodes { BVH_NODE nodes[]; };
layout(std430, set = 0, binding = BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };

layout(std430, set = 0, binding = BINDING_ACCUM) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = BINDING_RAYS) readonly buffer Rays { GpuRay rays[]; };
layout(std430, set = 0, binding = BINDING_HITS) writeonly buffer Hits { GpuHit hits[]; };

void main() {
    // Touch every binding so the compiler keeps it.
#ifdef LAYOUT_COMPACT
    float node_value = float(nodes[0].link);
#else
    float node_value = nodes[0].bmin.x;
#endif
    float s = node_value + triangles[0].v0.x + shading[0].n0.x + materials[0].diffuse.x
            + lights[0].position.x + emitters[0].v0.x + frame.cam_origin.x + rays[0].tmin
            + float(push.tile_x) + light_picks[0].pmf + float(params.max_depth)
            + float(textures[0].width) + float(texels[0]) + uvs[0].uv0.x;
    accum[0] = vec4(s);
    hits[0].t = s;
    accum_even[0] = vec4(s);
}
