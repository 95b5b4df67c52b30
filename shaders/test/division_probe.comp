#version 460
// Runs division.glsl's div_rn so tests/division.rs can hold it to the CPU's IEEE division:
// element i holds (a, b) in x and y; the probe writes div_rn(a, b), the device's own a / b,
// and `correct_quotient` started from a quotient and a reciprocal put 2 ulps off either way
// (a device whose division is off, emulated on one whose is not). The test sets
// SPEC_CORRECT_DIVISION itself (on, even on lavapipe).
#extension GL_GOOGLE_include_directive : require

#include "constants.glsl"
#include "gpu_abi.glsl"
#include "division.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_1D) in;
layout(std430, set = 0, binding = BINDING_ACCUM) buffer Pairs { vec4 pairs[]; };
layout(push_constant) uniform Push { GpuPush push; };

void main() {
    // Three elements per invocation, one per component: every lane of the vec3 code is checked.
    uint i = gl_GlobalInvocationID.x * 3u;
    if (i >= push.ray_count) return;
    uint n = min(3u, push.ray_count - i);
    vec3 a = vec3(1.0), b = vec3(1.0);
    for (uint k = 0u; k < n; k++) { a[k] = pairs[i + k].x; b[k] = pairs[i + k].y; }
    precise vec3 own = a / b;
    precise vec3 y = 1.0 / b;
    uvec3 qb = floatBitsToUint(own), yb = floatBitsToUint(y);
    vec3 corrected = div_rn(a, b);
    vec3 up = correct_quotient(a, b, uintBitsToFloat(qb + 2u), uintBitsToFloat(yb - 2u));
    vec3 down = correct_quotient(a, b, uintBitsToFloat(qb - 2u), uintBitsToFloat(yb + 2u));
    for (uint k = 0u; k < n; k++) pairs[i + k] = vec4(corrected[k], own[k], up[k], down[k]);
}
