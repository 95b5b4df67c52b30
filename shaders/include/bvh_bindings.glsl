// The BVH arrays every tracing shader reads, and the push constants.
//
// Nodes and triangles are bound as RGBA32UI uniform texel buffers and read with texelFetch,
// not as storage buffers, because on lavapipe that is what the loads cost (BENCHMARKS.md,
// "Loads on lavapipe"):
// - Mesa 25's gallivm (lp_bld_nir_soa.c, emit_load_mem) loads a storage buffer at a per-lane
//   index one lane and one dword at a time, each behind a branch on the lane mask and another
//   on the bounds check: 64 branchy scalar loads for one 32-byte node across 8 lanes.
// - A texel fetch of a 4 x 32-bit format loads each lane's 16 bytes with one vector load and
//   transposes them (lp_bld_format_soa.c): 2 loads per lane per node.
// - Loads through buffer device addresses become hardware gathers, one per component, which
//   the profile showed as the hottest instructions of both trace and path shaders.
// On GPUs texel fetches go through the texture cache, a fine path for read-only data.
// The decode assumes the std430 layouts of GpuNode / GpuParentNode (32 B: bmin, link, bmax,
// leaf), GpuCompactNode (16 B: four words), GpuWideNode (128 B: eight vec4-sized rows) and
// GpuTriangle (48 B: v0, prim, v1, pad, v2, pad);
// tests/layout.rs pins them, tests/texel_decode.rs checks the decode field by field, and the
// GPU agreement tests (tests/traversal.rs) would see any misread field.
// Needs GL_EXT_samplerless_texture_functions (enabled by each .comp).
#ifndef VKRT_BVH_BINDINGS_GLSL
#define VKRT_BVH_BINDINGS_GLSL
#include "constants.glsl"
#include "layout.glsl"

layout(push_constant) uniform Push { GpuPush push; };

// The node type depends on the layout (see traverse.glsl): 32 bytes (2 texels), 16 bytes
// (1 texel) for the compact layout, 128 bytes (8 texels) for the wide one.
#if defined(LAYOUT_PARENT_LINK)
#define BVH_NODE GpuParentNode
#define BVH_NODE_TEXELS 2u
#elif defined(LAYOUT_COMPACT)
#define BVH_NODE GpuCompactNode
#define BVH_NODE_TEXELS 1u
#elif defined(LAYOUT_WIDE)
#define BVH_NODE GpuWideNode
#define BVH_NODE_TEXELS 8u
#else
#define BVH_NODE GpuNode
#define BVH_NODE_TEXELS 2u
#endif

// The layout probe declares these bindings as struct arrays instead, to check their layout.
#ifndef LAYOUT_PROBE
// Texture (not sampler) buffers: a combined sampler of a buffer is deprecated in SPIR-V and
// the validation layers warn about it.
layout(set = 0, binding = BINDING_NODES) uniform utextureBuffer node_texels;
layout(set = 0, binding = BINDING_TRIANGLES) uniform utextureBuffer triangle_texels;

uint node_count() { return push.node_count; }

#if defined(LAYOUT_COMPACT)
BVH_NODE load_node(uint i) {
    uvec4 a = texelFetch(node_texels, int(i));
    return BVH_NODE(a.x, a.y, a.z, a.w);
}
#elif defined(LAYOUT_WIDE)
// Eight fetches, one per 16-byte row of GpuWideNode: six rows of child bounds, the child
// words, then parent and info.
BVH_NODE load_node(uint i) {
    int base = int(BVH_NODE_TEXELS * i);
    vec4 min_x = uintBitsToFloat(texelFetch(node_texels, base));
    vec4 min_y = uintBitsToFloat(texelFetch(node_texels, base + 1));
    vec4 min_z = uintBitsToFloat(texelFetch(node_texels, base + 2));
    vec4 max_x = uintBitsToFloat(texelFetch(node_texels, base + 3));
    vec4 max_y = uintBitsToFloat(texelFetch(node_texels, base + 4));
    vec4 max_z = uintBitsToFloat(texelFetch(node_texels, base + 5));
    uvec4 children = texelFetch(node_texels, base + 6);
    uvec4 link = texelFetch(node_texels, base + 7);
    return BVH_NODE(min_x, min_y, min_z, max_x, max_y, max_z, children, link.x, link.y, 0u, 0u);
}
#else
BVH_NODE load_node(uint i) {
    uvec4 a = texelFetch(node_texels, int(BVH_NODE_TEXELS * i));
    uvec4 b = texelFetch(node_texels, int(BVH_NODE_TEXELS * i + 1u));
    return BVH_NODE(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w);
}
#endif

GpuTriangle load_triangle(uint i) {
    uvec4 a = texelFetch(triangle_texels, int(3u * i));
    uvec4 b = texelFetch(triangle_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(triangle_texels, int(3u * i + 2u));
    return GpuTriangle(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), 0u, uintBitsToFloat(c.xyz), 0u);
}
#endif

#endif
