#version 460
// Batch ray queries: one invocation per ray, closest or any hit, with traversal counters.
// The engine of `vkrt trace` and `vkrt bvh` and the GPU end of the agreement tests
// (host/query/ray_query.rs). Geometry only: no alpha test (no ALPHA_TEST define).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

#include "bvh_bindings.glsl"
#include "traverse.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_1D) in;

layout(std430, set = 0, binding = BINDING_RAYS) readonly buffer Rays { GpuRay rays[]; };
layout(std430, set = 0, binding = BINDING_HITS) writeonly buffer Hits { GpuHit hits[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.ray_count) return;
    GpuRay ray = rays[i];
    Hit h = trace_scene(ray.origin, ray.direction, ray.tmin, ray.tmax, push.any_hit != 0u, false);
    GpuHit out_hit;
    out_hit.t = h.t;
    out_hit.prim = h.prim;
    out_hit.u = h.u;
    out_hit.v = h.v;
    out_hit.nodes_visited = h.nodes_visited;
    out_hit.tris_tested = h.tris_tested;
    out_hit._pad0 = 0u;
    out_hit._pad1 = 0u;
    hits[i] = out_hit;
}
