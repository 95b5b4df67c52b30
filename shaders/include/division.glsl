// Correctly rounded division on any Vulkan device: what the ray setup and the triangle test
// (intersect.glsl) divide with, so that the GPU's t and node counts equal the CPU twin's.
#ifndef VKRT_DIVISION_GLSL
#define VKRT_DIVISION_GLSL

#include "constants.glsl"

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
// padded slab test (intersect.glsl) assumes a rounded 1/d. `correct_quotient` takes the device's
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

#endif
