// Unsigned 64-bit fixed-point numbers as (low, high) 32-bit words, without shaderInt64: the
// path tracer's exact, order-free sums (constants.rs, ACCUM_FRACTION_BITS).
#ifndef VKRT_FIXED_POINT_GLSL
#define VKRT_FIXED_POINT_GLSL
#include "constants.glsl"

const float FIXED_SCALE = float(1u << ACCUM_FRACTION_BITS);
const float TWO_32 = 4294967296.0;

// round(c 2^ACCUM_FRACTION_BITS) for 0 <= c < 2^ACCUM_MAX_SAMPLE_LOG2. Every step is exact in
// f32 (scaling by powers of two, and x - hi 2^32 keeps only bits x has), so the words are a
// function of c alone, the same on every device that computed the same c.
uvec2 to_fixed(float c) {
    float x = floor(c * FIXED_SCALE + 0.5);
    float hi = floor(x * (1.0 / TWO_32));
    return uvec2(uint(x - hi * TWO_32), uint(hi));
}

uvec2 add_fixed(uvec2 a, uvec2 b) {
    uint carry;
    uint lo = uaddCarry(a.x, b.x, carry);
    return uvec2(lo, a.y + b.y + carry);
}

// The three channels of a sum, kept as words while a dispatch adds its samples.
struct Fixed3 {
    uvec2 r;
    uvec2 g;
    uvec2 b;
};

Fixed3 fixed3_zero() {
    return Fixed3(uvec2(0u), uvec2(0u), uvec2(0u));
}

Fixed3 add_fixed3(Fixed3 a, vec3 c) {
    return Fixed3(add_fixed(a.r, to_fixed(c.r)), add_fixed(a.g, to_fixed(c.g)), add_fixed(a.b, to_fixed(c.b)));
}

#endif
