// The BVH arrays every tracing shader reads, and the push constants. Each layout's node decode
// (`load_node`) is in its traverse_<id>.glsl.
//
// Nodes and triangles are bound as RGBA32UI uniform texel buffers and read with texelFetch,
// not as storage buffers, because on lavapipe that is what the loads cost (docs/experiments/
// texel-buffer-loads.md):
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
#include "gpu_abi.glsl"

layout(push_constant) uniform Push { GpuPush push; };

// The triangle list (triangle_list.glsl, host/accel/triangle_list.rs): a uniform block, not a
// texel buffer, since its loop is unrolled and every read is at a constant offset. std140:
// GpuTriangle is three 16-byte rows, so the array's stride is its std430 size (48 B).
layout(set = 0, binding = BINDING_TRIANGLE_LIST, std140) uniform TriangleList {
    GpuTriangle list_triangles[MAX_LIST_TRIANGLES];
};

// The layout probe declares these bindings as struct arrays instead, to check their layout.
#ifndef LAYOUT_PROBE
// Texture (not sampler) buffers: a combined sampler of a buffer is deprecated in SPIR-V and
// the validation layers warn about it.
layout(set = 0, binding = BINDING_NODES) uniform utextureBuffer node_texels;
layout(set = 0, binding = BINDING_TRIANGLES) uniform utextureBuffer triangle_texels;

uint node_count() { return push.node_count; }

GpuTriangle load_triangle(uint i) {
    uvec4 a = texelFetch(triangle_texels, int(3u * i));
    uvec4 b = texelFetch(triangle_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(triangle_texels, int(3u * i + 2u));
    return GpuTriangle(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), 0u);
}
#endif

#endif
