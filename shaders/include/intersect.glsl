// Ray-box and ray-triangle tests. CPU twin: host/accel/intersect.rs (same names). The correctly
// rounded division they use is division.glsl's; the benchmark's textbook tests (PLAIN_INTERSECT)
// are intersect_plain.glsl's.
#ifndef VKRT_INTERSECT_GLSL
#define VKRT_INTERSECT_GLSL

#include "constants.glsl"
#include "division.glsl"

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
#include "intersect_plain.glsl"
#endif

#endif
