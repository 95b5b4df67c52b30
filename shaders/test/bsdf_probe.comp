#version 460
// Runs the path tracer's BSDF code (shaders/include/bsdf.glsl) on test inputs so tests/bsdf.rs
// can check sampling against evaluation. Invocation i: material i / (PROBE_ANGLES * n),
// outgoing angle (i / n) % PROBE_ANGLES, where n = push.sample_count. Writes four vec4:
//   [wi, pdf from sampling (-1 if the sample failed)]
//   [pdf from bsdf_eval(wi), mean(weight), 1 if delta, 1 if the sample succeeded]
//   [u, bsdf_eval's pdf at u], u a uniform direction on the sphere
//   [f(wo, u), f(u, wo)]: both means over the channels, for reciprocity (0 if u.z <= 0).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require

#include "constants.glsl"
#include "gpu_abi.glsl"
#include "rng.glsl"
#include "sampling.glsl"
#include "bsdf.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_1D) in;
layout(std430, set = 0, binding = BINDING_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, set = 0, binding = BINDING_ACCUM) buffer Out { vec4 outv[]; };
layout(push_constant) uniform Push { GpuPush push; };

// cos(theta_o) of the outgoing directions tested.
const uint PROBE_ANGLES = 3u;
const float PROBE_COS[3] = float[3](0.95, 0.6, 0.2);

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint n = push.sample_count;
    uint material = i / (PROBE_ANGLES * n);
    if (material >= uint(materials.length())) return;
    float c = PROBE_COS[(i / n) % PROBE_ANGLES];
    vec3 wo = vec3(sqrt(1.0 - c * c), 0.0, c);
    Lobes l = lobes_of(materials[material]);
    Rng rng = rng_init(i, 0u, push.sample_base);
    float u_lobe = rng_next(rng);
    vec2 u = vec2(rng_next(rng), rng_next(rng));
    BsdfSample bs;
    bool ok = bsdf_sample(l, wo, true, u_lobe, u, bs);
    float pdf_eval;
    bsdf_eval(l, wo, bs.wi, pdf_eval);
    outv[4u * i] = vec4(bs.wi, ok ? bs.pdf : -1.0);
    outv[4u * i + 1u] = vec4(pdf_eval, ok ? mean3(bs.weight) : 0.0, bs.delta ? 1.0 : 0.0, ok ? 1.0 : 0.0);
    // A uniform direction: z uniform in [-1, 1], phi uniform (Archimedes).
    float z = 2.0 * rng_next(rng) - 1.0;
    float phi = 2.0 * PI * rng_next(rng);
    float r = sqrt(max(0.0, 1.0 - z * z));
    vec3 d = vec3(r * cos(phi), r * sin(phi), z);
    float pdf_u;
    vec3 f_ou = bsdf_eval(l, wo, d, pdf_u);
    outv[4u * i + 2u] = vec4(d, pdf_u);
    float pdf_r;
    vec3 f_uo = d.z > 0.0 ? bsdf_eval(l, d, wo, pdf_r) : vec3(0.0);
    outv[4u * i + 3u] = vec4(mean3(f_ou), mean3(f_uo), 0.0, 0.0);
}
