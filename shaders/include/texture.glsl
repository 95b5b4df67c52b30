// Texture lookups in the texel atlas (host/prepare/texture_atlas.rs): bilinear filtering,
// repeat wrapping for surfaces, clamping for cube-map faces; colour texels decoded from sRGB
// as texel^2.2 before blending (the lab renderer's decode). Row 0 of a texture is the top row
// of its image file, and OBJ's v = 0 is the bottom of the image, hence the 1 - v.
#ifndef VKRT_TEXTURE_GLSL
#define VKRT_TEXTURE_GLSL
#include "scene_bindings.glsl"

vec4 texel_at(GpuTexture tex, uint x, uint y, bool srgb) {
    vec4 c = unpackUnorm4x8(load_atlas_texel(tex.offset + y * tex.width + x));
    if (srgb) c.rgb = pow(c.rgb, vec3(2.2));
    return c;
}

// Bilinear lookup at p, in texels (texel centres at +0.5). `wrap`: repeat, else clamp to edge.
vec4 texture_bilinear(uint index, vec2 p, bool wrap, bool srgb) {
    GpuTexture tex = load_texture(index);
    ivec2 size = ivec2(tex.width, tex.height);
    vec2 q = p - 0.5;
    vec2 base = floor(q);
    vec2 f = q - base;
    ivec2 i0 = ivec2(base);
    ivec2 i1 = i0 + 1;
    if (wrap) {
        // Positive modulo: q can be just below 0 at the left and top edges.
        i0 = ((i0 % size) + size) % size;
        i1 = ((i1 % size) + size) % size;
    } else {
        i0 = clamp(i0, ivec2(0), size - 1);
        i1 = clamp(i1, ivec2(0), size - 1);
    }
    vec4 c00 = texel_at(tex, uint(i0.x), uint(i0.y), srgb);
    vec4 c10 = texel_at(tex, uint(i1.x), uint(i0.y), srgb);
    vec4 c01 = texel_at(tex, uint(i0.x), uint(i1.y), srgb);
    vec4 c11 = texel_at(tex, uint(i1.x), uint(i1.y), srgb);
    return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

// A surface texture at texture coordinates uv (repeat wrapping: only the fraction counts).
vec4 texture_uv(uint index, vec2 uv, bool srgb) {
    GpuTexture tex = load_texture(index);
    vec2 st = vec2(fract(uv.x), 1.0 - fract(uv.y));
    return texture_bilinear(index, st * vec2(tex.width, tex.height), true, srgb);
}

// Texture coordinates at barycentrics (u, v) of primitive prim.
vec2 uv_at(uint prim, float u, float v) {
    GpuUv t = load_uv(prim);
    return (1.0 - u - v) * t.uv0 + u * t.uv1 + v * t.uv2;
}

// The sky seen along unit direction d: frame.sky_color, times the cube map's texel if there is
// one. Faces +x, -x, +y, -y, +z, -z follow OpenGL's cube-map rules (GL 4.6 spec, table 8.19):
// face coordinates (sc, tc) / |major axis|, with t measured down from the image's top row.
vec3 sky_radiance(vec3 d) {
    if (frame.sky_texture == TEXTURE_NONE) return frame.sky_color;
    vec3 a = abs(d);
    uint face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x > 0.0 ? 0u : 1u;
        ma = a.x;
        sc = d.x > 0.0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        face = d.y > 0.0 ? 2u : 3u;
        ma = a.y;
        sc = d.x;
        tc = d.y > 0.0 ? d.z : -d.z;
    } else {
        face = d.z > 0.0 ? 4u : 5u;
        ma = a.z;
        sc = d.z > 0.0 ? d.x : -d.x;
        tc = -d.y;
    }
    uint index = frame.sky_texture + face;
    GpuTexture tex = load_texture(index);
    vec2 st = 0.5 * (vec2(sc, tc) / max(ma, 1e-30) + 1.0);
    return frame.sky_color * texture_bilinear(index, st * vec2(tex.width, tex.height), false, true).rgb;
}

#endif
