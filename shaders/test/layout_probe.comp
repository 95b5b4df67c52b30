#version 460
// Declares every GPU struct and binding so tests/layout.rs can read their offsets, sizes,
// strides and binding numbers from one SPIR-V module. Never dispatched. Built once per BVH
// layout (host/pipeline/variants.rs), with that layout's node struct at BINDING_NODES
// (BVH_NODE, from the generated bvh_node.glsl).
#extension GL_GOOGLE_include_directive : require
// The BVH, scene and light-pick bindings are texel buffers in the real shaders; here they are
// struct arrays.
#define LAYOUT_PROBE

#include "bvh_node.glsl"
#include "scene_bindings.glsl"
#include "path_bindings.glsl"

layout(local_size_x = 1) in;

// These arrays are texel buffers in the shaders (bvh_bindings.glsl, scene_bindings.glsl,
// path_bindings.glsl), decoded field by field in std430 order; declared as blocks here only so
// their structs' offsets and strides can be read back.
layout(std430, set = 0, binding = BINDING_NODES) readonly buffer Nodes { BVH_NODE nodes[]; };
layout(std430, set = 0, binding = BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };
layout(std430, set = 0, binding = BINDING_SHADING) readonly buffer Shading { GpuShading shading[]; };
layout(std430, set = 0, binding = BINDING_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, set = 0, binding = BINDING_LIGHTS) readonly buffer Lights { GpuLight lights[]; };
layout(std430, set = 0, binding = BINDING_EMITTERS) readonly buffer Emitters { GpuEmitter emitters[]; };
layout(std430, set = 0, binding = BINDING_TEXTURES) readonly buffer Textures { GpuTexture textures[]; };
layout(std430, set = 0, binding = BINDING_TEXELS) readonly buffer Texels { uint texels[]; };
layout(std430, set = 0, binding = BINDING_UVS) readonly buffer Uvs { GpuUv uvs[]; };
layout(std430, set = 0, binding = BINDING_TANGENTS) readonly buffer Tangents { GpuTangents tangents[]; };
layout(std430, set = 0, binding = BINDING_LIGHT_PICKS) readonly buffer LightPicks { GpuLightPick light_picks[]; };
layout(std430, set = 0, binding = BINDING_MIRRORS) readonly buffer Mirrors { GpuMirror mirrors[]; };
layout(std430, set = 0, binding = BINDING_MIRROR_PLANES) readonly buffer MirrorPlanes { GpuMirrorPlane mirror_planes[]; };
layout(std430, set = 0, binding = BINDING_CASTERS) readonly buffer Casters { GpuCaster casters[]; };
layout(std430, set = 0, binding = BINDING_INSTANCES) readonly buffer Instances { GpuInstance instances[]; };

layout(std430, set = 0, binding = BINDING_ACCUM) buffer Accum { vec4 accum[]; };
layout(std430, set = 0, binding = BINDING_RAYS) readonly buffer Rays { GpuRay rays[]; };
layout(std430, set = 0, binding = BINDING_HITS) writeonly buffer Hits { GpuHit hits[]; };

void main() {
    // Touch every binding so the compiler keeps it.
    float s = float(nodes.length()) + triangles[0].v0.x + shading[0].n0.x + materials[0].diffuse.x
            + lights[0].position.x + emitters[0].v0.x + frame.cam_origin.x + rays[0].tmin
            + float(push.tile_x) + light_picks[0].pmf + float(params.max_depth)
            + float(textures[0].width) + float(texels[0]) + uvs[0].uv0.x + float(block_samples[0].x)
            + tangents[0].t0.x + mirrors[0].v0.x + float(mirror_planes[0].count) + casters[0].radius
            + list_triangles[0].v0.x + instances[0].world_to_object[2].w + float(instances[0].flags);
    accum[0] = vec4(s);
    hits[0].t = s;
    uvec2 w = uvec2(s);
    sum_even_r[0] = w; sum_even_g[0] = w; sum_even_b[0] = w;
    sum_odd_r[0] = w; sum_odd_g[0] = w; sum_odd_b[0] = w;
    sample_counts[0] = w;
    ray_counts[0] = uint(s);
    mirror_probe[0] = uint(s);
}
