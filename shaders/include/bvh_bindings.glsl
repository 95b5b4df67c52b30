// The BVH arrays every tracing shader reads, and the push constants that locate them.
//
// Nodes and triangles are read through buffer device addresses (Vulkan 1.2) as 64-bit words,
// not through storage-buffer bindings, because on lavapipe that is what the loads cost:
// - Mesa 25's gallivm (lp_bld_nir_soa.c, emit_load_mem) loads a storage buffer at a per-lane
//   index one lane and one dword at a time, each behind a branch on the lane mask and another
//   on the bounds check; a load through an address (emit_load_global) is one masked gather
//   per component instead.
// - A gather costs about the same per instruction whatever the element width, so a 32-byte
//   node read as four 64-bit words takes four gathers, not eight.
// Measured on Conference (BENCHMARKS.md, "Loads on lavapipe"). On GPUs both are plain loads.
// The decode below assumes the std430 layouts of GpuNode / GpuParentNode (32 B: bmin, link,
// bmax, leaf) and GpuTriangle (48 B: v0, prim, v1, pad, v2, pad); tests/layout.rs pins both,
// and the GPU agreement tests (tests/traversal.rs) would see any misread field.
// Needs GL_EXT_buffer_reference, GL_EXT_buffer_reference_uvec2 and
// GL_EXT_shader_explicit_arithmetic_types_int64 (enabled by each .comp but the layout probe).
#ifndef VKRT_BVH_BINDINGS_GLSL
#define VKRT_BVH_BINDINGS_GLSL
#include "constants.glsl"
#include "layout.glsl"

layout(push_constant) uniform Push { GpuPush push; };

// The node type depends on the layout (see traverse.glsl); both are 32 bytes.
#if defined(LAYOUT_PARENT_LINK)
#define BVH_NODE GpuParentNode
#else
#define BVH_NODE GpuNode
#endif

// The layout probe (read by naga, which has no physical pointers) stops here.
#ifndef LAYOUT_PROBE
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer BvhNodeWords { u64vec4 words[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer BvhTriangleWords { u64vec2 words[]; };

uint node_count() { return push.node_count; }

BVH_NODE load_node(uint i) {
    u64vec4 w = BvhNodeWords(push.nodes_address).words[i];
    uvec2 a = unpackUint2x32(w.x), b = unpackUint2x32(w.y), c = unpackUint2x32(w.z), d = unpackUint2x32(w.w);
    return BVH_NODE(uintBitsToFloat(uvec3(a, b.x)), b.y, uintBitsToFloat(uvec3(c, d.x)), d.y);
}

GpuTriangle load_triangle(uint i) {
    BvhTriangleWords t = BvhTriangleWords(push.triangles_address);
    u64vec2 p = t.words[3u * i], q = t.words[3u * i + 1u], r = t.words[3u * i + 2u];
    uvec2 a = unpackUint2x32(p.x), b = unpackUint2x32(p.y);
    uvec2 c = unpackUint2x32(q.x), d = unpackUint2x32(q.y);
    uvec2 e = unpackUint2x32(r.x), f = unpackUint2x32(r.y);
    return GpuTriangle(uintBitsToFloat(uvec3(a, b.x)), b.y, uintBitsToFloat(uvec3(c, d.x)), 0u,
                       uintBitsToFloat(uvec3(e, f.x)), 0u);
}
#endif

#endif
