// The buffers the path tracer reads and writes besides the scene's.
#ifndef VKRT_PATH_BINDINGS_GLSL
#define VKRT_PATH_BINDINGS_GLSL
#include "constants.glsl"
#include "gpu_abi.glsl"

layout(std140, set = 0, binding = BINDING_PATH_PARAMS) uniform PathParams { GpuPathParams params; };
// The sums: one fixed-point u64 (low, high word) per pixel in each plane (constants.rs,
// BINDING_SUM_*; fixed_point.glsl adds to them), and per pixel (samples taken, dropped).
layout(std430, set = 0, binding = BINDING_SUM_EVEN_R) buffer SumEvenR { uvec2 sum_even_r[]; };
layout(std430, set = 0, binding = BINDING_SUM_EVEN_G) buffer SumEvenG { uvec2 sum_even_g[]; };
layout(std430, set = 0, binding = BINDING_SUM_EVEN_B) buffer SumEvenB { uvec2 sum_even_b[]; };
layout(std430, set = 0, binding = BINDING_SUM_ODD_R) buffer SumOddR { uvec2 sum_odd_r[]; };
layout(std430, set = 0, binding = BINDING_SUM_ODD_G) buffer SumOddG { uvec2 sum_odd_g[]; };
layout(std430, set = 0, binding = BINDING_SUM_ODD_B) buffer SumOddB { uvec2 sum_odd_b[]; };
layout(std430, set = 0, binding = BINDING_SAMPLE_COUNTS) buffer SampleCounts { uvec2 sample_counts[]; };
// Adaptive sampling: (first sample index, count) per block of params.adaptive pixels in a
// row, keyed as sample_key. Read once per invocation, so a storage buffer.
layout(std430, set = 0, binding = BINDING_BLOCK_SAMPLES) readonly buffer BlockSamples { uvec2 block_samples[]; };
// Rays traced per pixel (closest-hit and shadow rays), for the progress line's rays/s.
layout(std430, set = 0, binding = BINDING_RAY_COUNTS) buffer RayCounts { uint ray_counts[]; };
// Per pixel, the mirror lobe's probability at the camera ray's first hit, as float bits (0: the
// material's own choice): written by the probe pass, read once per sampling invocation
// (mirror_probe.glsl).
layout(std430, set = 0, binding = BINDING_MIRROR_PROBE) buffer MirrorProbe { uint mirror_probe[]; };

#ifndef LAYOUT_PROBE
// The light-selection table is read at a per-lane index: an RGBA32UI texel buffer, as the
// scene arrays (scene_bindings.glsl says why).
layout(set = 0, binding = BINDING_LIGHT_PICKS) uniform utextureBuffer light_pick_texels;

// 16 B: pmf, alias, threshold, alias_pmf.
GpuLightPick load_light_pick(uint i) {
    uvec4 a = texelFetch(light_pick_texels, int(i));
    return GpuLightPick(uintBitsToFloat(a.x), a.y, uintBitsToFloat(a.z), uintBitsToFloat(a.w));
}

// The planar mirrors (mirror_light.glsl), 48 B each: v0, material | v1 | v2.
layout(set = 0, binding = BINDING_MIRRORS) uniform utextureBuffer mirror_texels;

GpuMirror load_mirror(uint i) {
    uvec4 a = texelFetch(mirror_texels, int(3u * i));
    uvec4 b = texelFetch(mirror_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(mirror_texels, int(3u * i + 2u));
    return GpuMirror(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w, uintBitsToFloat(c.xyz), c.w);
}

// Their planes (one per plane and material), 16 B each: first, count.
layout(set = 0, binding = BINDING_MIRROR_PLANES) uniform utextureBuffer mirror_plane_texels;

GpuMirrorPlane load_mirror_plane(uint i) {
    uvec4 a = texelFetch(mirror_plane_texels, int(i));
    return GpuMirrorPlane(a.x, a.y, a.z, a.w);
}

// The caustic casters (caster_guide.glsl), 48 B each: center, radius | target, target_radius |
// spot_spread.
layout(set = 0, binding = BINDING_CASTERS) uniform utextureBuffer caster_texels;

GpuCaster load_caster(uint i) {
    uvec4 a = texelFetch(caster_texels, int(3u * i));
    uvec4 b = texelFetch(caster_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(caster_texels, int(3u * i + 2u));
    return GpuCaster(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                     uintBitsToFloat(c.x), c.y, c.z, c.w);
}
#endif

#endif
