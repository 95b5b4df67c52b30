// The textbook ray-box and ray-triangle tests, for the benchmark baseline only (intersect.glsl
// includes this file under PLAIN_INTERSECT, the `trace_plain` variant).
#ifndef VKRT_INTERSECT_PLAIN_GLSL
#define VKRT_INTERSECT_PLAIN_GLSL

// PLAIN_INTERSECT: the textbook tests, kept only to measure what robustness costs (the
// `trace_plain` variant, tools/bench/src/bin/robust_cost.rs). Not used for rendering: the slab test has no
// padding and divides 0 by 0 for axis-parallel rays on a slab plane; Möller & Trumbore 1997
// with an epsilon on the determinant lets rays slip between triangles that share an edge.
bool intersect_box(RayPre r, vec3 bmin, vec3 bmax, float tmax, out float t_enter) {
    vec3 t0 = (bmin - r.origin) * r.inv_dir;
    vec3 t1 = (bmax - r.origin) * r.inv_dir;
    vec3 near = min(t0, t1);
    vec3 far = max(t0, t1);
    t_enter = max(max(max(near.x, near.y), near.z), r.tmin);
    float t_exit = min(min(min(far.x, far.y), far.z), tmax);
    return t_enter <= t_exit;
}

bool intersect_triangle(RayPre r, vec3 v0, vec3 v1, vec3 v2, float tmax, out float t, out float u, out float v) {
    const float EPSILON = 1e-8;
    vec3 e1 = v1 - v0;
    vec3 e2 = v2 - v0;
    vec3 p = cross(r.dir, e2);
    float det = dot(e1, p);
    t = 0.0; u = 0.0; v = 0.0;
    if (abs(det) < EPSILON) return false;
    float inv_det = 1.0 / det;
    vec3 s = r.origin - v0;
    u = dot(s, p) * inv_det;
    if (u < 0.0 || u > 1.0) return false;
    vec3 q = cross(s, e1);
    v = dot(r.dir, q) * inv_det;
    if (v < 0.0 || u + v > 1.0) return false;
    t = dot(e2, q) * inv_det;
    return t > r.tmin && t < tmax;
}

#endif
