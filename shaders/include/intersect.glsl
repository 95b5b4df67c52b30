// Ray-box and ray-triangle tests. CPU twin: host/accel/intersect.rs (same names).
#ifndef VKRT_INTERSECT_GLSL
#define VKRT_INTERSECT_GLSL

#include "constants.glsl"

// Ize 2013, "Robust BVH ray traversal": the far slab distance times 1 + 2*gamma(3) makes the
// float slab test conservative. Value: accel::intersect::SLAB_FAR_PAD.
const float SLAB_FAR_PAD = 1.0000003576278687;
const float FLOAT_MAX = 3.4028234663852886e38;

struct RayPre {
    vec3 origin;
    vec3 dir;
    vec3 inv_dir;
    float tmin;
    int kx;
    int ky;
    int kz;
    vec3 shear;
};

// p + e == a * b exactly (per component), with round-to-nearest products and sums only
// (Dekker 1971, "A floating-point technique for extending the available precision",
// Veltkamp's split). Vulkan rounds OpFMul and OpFAdd correctly but lets fma() be a product
// then a sum, so an exact residual cannot rely on it; `precise` keeps these from being fused.
void two_product(vec3 a, vec3 b, out vec3 p, out vec3 e) {
    precise vec3 ca = 4097.0 * a;
    precise vec3 ah = ca - (ca - a);
    precise vec3 al = a - ah;
    precise vec3 cb = 4097.0 * b;
    precise vec3 bh = cb - (cb - b);
    precise vec3 bl = b - bh;
    precise vec3 pp = a * b;
    precise vec3 ee = ((ah * bh - pp) + ah * bl + al * bh) + al * bl;
    p = pp;
    e = ee;
}

// a - q b, exact for q within a few ulps of a / b (the residual is then representable and
// a - p is exact by Sterbenz's lemma).
vec3 residual(vec3 a, vec3 q, vec3 b) {
    vec3 p, e;
    two_product(q, b, p, e);
    precise vec3 r = (a - p) - e;
    return r;
}

// Where the device's division may be off (SPEC_CORRECT_DIVISION: every device but lavapipe).
layout(constant_id = SPEC_CORRECT_DIVISION) const bool CORRECT_DIVISION = true;

// a / b correctly rounded, as the CPU twin divides. Vulkan lets a division be 2.5 ulp off, and
// NVIDIA's is: on an H200 the GPU's t and node counts then differed from the twin's, and Ize's
// padded slab test (below) assumes a rounded 1/d. `correct_quotient` takes the device's
// q ~ a / b and y ~ 1 / b: one residual correction q + r y (r exact: `residual`) brings q
// within a little over half an ulp (Markstein 1990, "Computation of elementary functions on
// the IBM RISC System/6000 processor", IBM J. Res. Dev. 34(1)), and the exact residual of that
// says whether the neighbour on its side is nearer: a / b is never exactly halfway, but can be
// within 2^-25 ulp of it (1 / b for b just under a power of two), where a second correction
// alone still rounds the wrong way. Checked bit for bit against the CPU by tests/division.rs,
// on lavapipe from quotients put 2 ulps off. Quotients, reciprocals and dividends outside
// [1e-18, 1e18] (zero, infinite, NaN, or where the split's low products would fall below the
// normal range, which a device may flush to zero) keep the device's own. Three quotients at a
// time: the ray setup's six are two calls. `div_rn` puts the correction in a block on the
// constant, not after an early return, which lavapipe would translate into every inlined BVH
// walk before dropping it (docs/experiments/pipeline-creation-time.md).
vec3 correct_quotient(vec3 a, vec3 b, vec3 q, vec3 y) {
    bvec3 ordinary = bvec3(uvec3(greaterThanEqual(abs(q), vec3(1e-18))) & uvec3(lessThanEqual(abs(q), vec3(1e18)))
        & uvec3(greaterThanEqual(abs(y), vec3(1e-18))) & uvec3(lessThanEqual(abs(y), vec3(1e18)))
        & uvec3(greaterThanEqual(abs(a), vec3(1e-18))));
    precise vec3 q1 = q + residual(a, q, b) * y;
    precise vec3 r1 = residual(a, q1, b);
    // The exact quotient q1 + r1 / b lies farther from zero than q1 when r1 / b has q1's sign;
    // q2 is q1's neighbour on that side, and it is the rounded quotient if the exact one is
    // past halfway to it: |r1| > |b| |q2 - q1| / 2 (exact: the gap is a power of two).
    bvec3 outward = equal(equal(greaterThan(r1, vec3(0.0)), greaterThan(b, vec3(0.0))), greaterThan(q1, vec3(0.0)));
    uvec3 bits = floatBitsToUint(q1);
    precise vec3 q2 = uintBitsToFloat(mix(bits - 1u, bits + 1u, outward));
    precise vec3 half_gap = abs(b) * abs(q2 - q1) * 0.5;
    return mix(q, mix(q1, q2, greaterThan(abs(r1), half_gap)), ordinary);
}

vec3 div_rn(vec3 a, vec3 b) {
    precise vec3 q = a / b;
    if (CORRECT_DIVISION) {
        precise vec3 y = 1.0 / b;
        q = correct_quotient(a, b, q, y);
    }
    return q;
}

float div_rn(float a, float b) {
    return div_rn(vec3(a), vec3(b)).x;
}

// 1/d, with 0 mapped to the largest float of the same sign: an origin on a slab plane then
// gives 0 * MAX = 0 instead of 0 * inf = NaN, and the slab counts as entered.
vec3 safe_reciprocal(vec3 d) {
    vec3 signed_max = mix(vec3(FLOAT_MAX), vec3(-FLOAT_MAX), notEqual(floatBitsToUint(d) >> 31, uvec3(0u)));
    return mix(div_rn(vec3(1.0), d), signed_max, equal(d, vec3(0.0)));
}

RayPre ray_pre(vec3 origin, vec3 dir, float tmin, float tmax) {
    RayPre r;
    r.origin = origin;
    r.dir = dir;
#ifdef PLAIN_INTERSECT
    r.inv_dir = 1.0 / dir;
    r.tmin = tmin;
#else
    r.inv_dir = safe_reciprocal(dir);
    // A ray with a NaN anywhere must miss at the root. The select min/max of the slab test may
    // drop a NaN operand, and a zero direction component makes a far slab distance overflow to
    // infinity, so such a ray could enter most boxes. Instead it gets origin 0 and inverse
    // direction 0 (every slab distance is then 0, so t_exit <= 0) and tmin = +inf (t_enter =
    // +inf): the first box test fails, whatever tmax is.
    bool nan_ray = any(isnan(origin)) || any(isnan(dir)) || isnan(tmin) || isnan(tmax);
    r.tmin = nan_ray ? 1.0 / 0.0 : tmin;
    r.origin = nan_ray ? vec3(0.0) : origin;
    r.inv_dir = nan_ray ? vec3(0.0) : r.inv_dir;
#endif
    vec3 a = abs(dir);
    r.kz = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    // Swapping kx and ky when the dominant component is negative keeps the winding
    // (Woop, Benthin & Wald 2013, sec. 3).
    if (dir[r.kz] < 0.0) { int t = r.kx; r.kx = r.ky; r.ky = t; }
    r.shear = div_rn(vec3(dir[r.kx], dir[r.ky], 1.0), vec3(dir[r.kz]));
    return r;
}

#ifndef PLAIN_INTERSECT
// Minimum and maximum as compare-and-select: one vminps/vmaxps each on x86. GLSL's min() and
// max() must return the non-NaN operand, which lavapipe compiles to a min, an unordered
// compare and a masked move: the slab test's 14 min/max took ~20 of the ~130 instructions of
// a traversal step, and the path tracer ran ~5 % faster without them (docs/experiments/
// per-step-cost.md). With a NaN operand these return b. CPU twin: accel::intersect::sel_min/max.
float sel_min(float a, float b) { return a < b ? a : b; }
float sel_max(float a, float b) { return a > b ? a : b; }
vec3 sel_min(vec3 a, vec3 b) { return mix(b, a, lessThan(a, b)); }
vec3 sel_max(vec3 a, vec3 b) { return mix(b, a, greaterThan(a, b)); }
vec4 sel_min(vec4 a, vec4 b) { return mix(b, a, lessThan(a, b)); }
vec4 sel_max(vec4 a, vec4 b) { return mix(b, a, greaterThan(a, b)); }

// Entry distance if the ray overlaps the box within [tmin, tmax], else -1 with `hit` false.
// Boxes are finite (the loaders drop triangles with a non-finite vertex), and a NaN ray misses
// every box (ray_pre).
bool intersect_box(RayPre r, vec3 bmin, vec3 bmax, float tmax, out float t_enter) {
    precise vec3 t0 = (bmin - r.origin) * r.inv_dir;
    precise vec3 t1 = (bmax - r.origin) * r.inv_dir;
    vec3 near = sel_min(t0, t1);
    vec3 far = sel_max(t0, t1);
    t_enter = sel_max(r.tmin, sel_max(sel_max(near.x, near.y), near.z));
    precise float t_exit = sel_min(tmax, sel_min(sel_min(far.x, far.y), far.z)) * SLAB_FAR_PAD;
    return t_enter <= t_exit;
}

// Watertight ray/triangle test (Woop, Benthin & Wald 2013, JCGT 2(1)). `precise` forbids
// fused multiply-add, so the edge functions of a shared edge are exact negations of each other
// and no ray passes between two triangles; an edge value of exactly 0 is inside for both.
// On a hit with tmin < t < tmax: returns true, t, and the barycentrics (u, v) of v1 and v2.
bool intersect_triangle(RayPre r, vec3 v0, vec3 v1, vec3 v2, float tmax, out float t, out float u, out float v) {
    precise vec3 a = v0 - r.origin;
    precise vec3 b = v1 - r.origin;
    precise vec3 c = v2 - r.origin;
    precise float ax = a[r.kx] - r.shear.x * a[r.kz];
    precise float ay = a[r.ky] - r.shear.y * a[r.kz];
    precise float bx = b[r.kx] - r.shear.x * b[r.kz];
    precise float by = b[r.ky] - r.shear.y * b[r.kz];
    precise float cx = c[r.kx] - r.shear.x * c[r.kz];
    precise float cy = c[r.ky] - r.shear.y * c[r.kz];
    precise float e0 = cx * by - cy * bx;
    precise float e1 = ax * cy - ay * cx;
    precise float e2 = bx * ay - by * ax;
    t = 0.0; u = 0.0; v = 0.0;
    if ((e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0)) return false;
    precise float det = e0 + e1 + e2;
    if (det == 0.0 || isnan(det)) return false;
    precise float az = r.shear.z * a[r.kz];
    precise float bz = r.shear.z * b[r.kz];
    precise float cz = r.shear.z * c[r.kz];
    precise float t_scaled = e0 * az + e1 * bz + e2 * cz;
    precise float inv_det = div_rn(1.0, det);
    t = t_scaled * inv_det;
    if (!(t > r.tmin && t < tmax)) return false;
    u = e1 * inv_det;
    v = e2 * inv_det;
    return true;
}

#else
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

#endif
