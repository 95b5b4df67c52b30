// Warps from the unit square to the shapes the path tracer samples, and the frame they live in.
#ifndef VKRT_SAMPLING_GLSL
#define VKRT_SAMPLING_GLSL

#include "math.glsl"

// The largest float below 1 (0x1.fffffep-1): where a rescaled sample must stay inside [0, 1).
const float ONE_MINUS_EPSILON = 0.99999994;

// An orthonormal basis around unit n (Duff et al. 2017, "Building an orthonormal basis,
// revisited", JCGT 6(1)): branchless and continuous except at n.z = 0's sign flip.
struct Onb {
    vec3 t;
    vec3 b;
    vec3 n;
};

Onb onb_from(vec3 n) {
    float sign = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sign + n.z);
    float b = n.x * n.y * a;
    Onb f;
    f.t = vec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.b = vec3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

vec3 to_local(Onb f, vec3 v) {
    return vec3(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

vec3 to_world(Onb f, vec3 v) {
    return v.x * f.t + v.y * f.b + v.z * f.n;
}

// The unit square onto the unit disc, keeping areas and strata compact (Shirley and Chiu 1997,
// "A low distortion map between disk and square"). CPU twin: scene::camera::concentric_disk.
vec2 concentric_disk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    vec2 d = vec2(0.0);
    if (o.x != 0.0 || o.y != 0.0) {
        float r;
        float phi;
        if (abs(o.x) > abs(o.y)) {
            r = o.x;
            phi = (PI / 4.0) * (o.y / o.x);
        } else {
            r = o.y;
            phi = (PI / 2.0) - (PI / 4.0) * (o.x / o.y);
        }
        d = r * vec2(cos(phi), sin(phi));
    }
    return d;
}

// Cosine-weighted hemisphere around +z, pdf cos(theta)/pi: Malley's method on the concentric
// disk map, which keeps strata compact for low-discrepancy input.
vec3 sample_cosine_hemisphere(vec2 u) {
    vec2 d = concentric_disk(u);
    return vec3(d, sqrt(max(0.0, 1.0 - dot(d, d))));
}

// Barycentrics of a uniform point on a triangle (Pharr, Jakob & Humphreys, pbrt 3rd ed. 13.6.5).
vec3 sample_triangle_bary(vec2 u) {
    float su = sqrt(u.x);
    float b1 = u.y * su;
    return vec3(1.0 - su, b1, su - b1);
}

// Veach's power heuristic with beta = 2 (Veach 1997, thesis, section 9.2.4): the weight of the
// strategy with density a when the other has density b.
float power_heuristic(float a, float b) {
    float a2 = a * a;
    float b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// The balance heuristic's weight of the first of three strategies (Veach 1997, section 9.2.2),
// for the light-vertex connections' three ways of making a path (light_connection.glsl). Not
// the power heuristic that weighs two strategies above: with the same rays, the balance
// heuristic gave cornell-measured 4-6 % less relMSE and ~1 % less HDR-FLIP at 16, 64 and 256
// spp (CornellBox-Original: level), as pbrt's bidirectional path tracer also weighs its
// connections (docs/experiments/light-connections.md, "Which heuristic"). Only the ratios b / a
// and c / a count, so a caller may pass them with a = 1: connect_light_vertex does, because the
// area densities themselves (products of 1e-20 and less in a large scene) underflow.
float balance_heuristic3(float a, float b, float c) {
    if (!(a > 0.0)) return 0.0;
    return 1.0 / (1.0 + b / a + c / a);
}

float mean3(vec3 v) {
    return (v.x + v.y + v.z) / 3.0;
}

float max3(vec3 v) {
    return max(v.x, max(v.y, v.z));
}

#endif
