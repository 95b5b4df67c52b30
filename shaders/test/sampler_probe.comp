#version 460
// Runs the path tracer's sampler (shaders/include/sampler.glsl) so tests/sampler.rs can check
// its stratification. Invocation i draws sample i % n of pixel i / n (n = push.sample_count,
// seed push.sample_base, kind push.ray_count; for SAMPLER_ZSOBOL the pixel is the Z-order
// cell and n the set size) and writes PROBE_PAIRS consecutive 2D draws, two per vec4.
#extension GL_GOOGLE_include_directive : require

#include "constants.glsl"
#include "gpu_abi.glsl"
#include "rng.glsl"
#include "sampler.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_1D) in;
layout(std430, set = 0, binding = BINDING_ACCUM) buffer Out { vec4 outv[]; };
layout(push_constant) uniform Push { GpuPush push; };

const uint PROBE_PAIRS = 4u;

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = push.sample_count;
    if (i >= n * push.total_spp) return;
    Sampler s = sampler_init(push.ray_count, i / n, i % n, push.sample_base, 1u, uint(findMSB(n)));
    for (uint p = 0u; p < PROBE_PAIRS; p += 2u) {
        vec2 a = sampler_2d(s);
        vec2 b = sampler_2d(s);
        outv[i * (PROBE_PAIRS / 2u) + p / 2u] = vec4(a, b);
    }
}
