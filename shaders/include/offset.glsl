// Where secondary rays start: the hit point moved off the surface along the geometric normal
// by an amount that scales with the point's magnitude (Wächter & Binder, "A fast and robust
// method for avoiding self-intersection", Ray Tracing Gems ch. 6). Far from the origin the
// move is a fixed number of float ulps, so it stays valid at any scale; near the origin, where
// ulps get tiny, a small absolute step takes over.
#ifndef VKRT_OFFSET_GLSL
#define VKRT_OFFSET_GLSL

// Below OFFSET_ORIGIN * scale a coordinate moves by OFFSET_FLOAT_SCALE * scale * n instead of
// by ulps. The paper's constants assume a scene of unit size; `scale` (the scene's largest
// |coordinate|) makes them hold for millimetre parts and kilometre terrain alike.
const float OFFSET_ORIGIN = 1.0 / 32.0;
const float OFFSET_FLOAT_SCALE = 1.0 / 65536.0;
// Ulps to move per unit of normal component.
const float OFFSET_INT_SCALE = 256.0;

// `n` must be the unit geometric normal on the side the new ray leaves from.
vec3 offset_ray(vec3 p, vec3 n, float scale) {
    ivec3 of_i = ivec3(OFFSET_INT_SCALE * n);
    vec3 p_i = vec3(
        intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of_i.x : of_i.x)),
        intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of_i.y : of_i.y)),
        intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of_i.z : of_i.z)));
    return vec3(
        abs(p.x) < OFFSET_ORIGIN * scale ? p.x + OFFSET_FLOAT_SCALE * scale * n.x : p_i.x,
        abs(p.y) < OFFSET_ORIGIN * scale ? p.y + OFFSET_FLOAT_SCALE * scale * n.y : p_i.y,
        abs(p.z) < OFFSET_ORIGIN * scale ? p.z + OFFSET_FLOAT_SCALE * scale * n.z : p_i.z);
}

#endif
