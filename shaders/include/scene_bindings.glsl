// The scene arrays the integrators read besides the BVH, and the frame uniform.
//
// The arrays are uniform texel buffers read with texelFetch, like the BVH's and for the same
// reason (bvh_bindings.glsl; docs/experiments/texel-buffer-loads.md): lavapipe loads a storage
// buffer at a per-lane index one lane and one dword at a time behind branches, a texel fetch
// with one vector load per lane. The structs are RGBA32UI texels, and each load_* decodes one
// from consecutive texels in the std430 field order of gpu_abi.glsl (float fields bit-cast,
// padding read as 0). tests/layout.rs checks that order against Rust through the layout probe,
// which declares these bindings as struct arrays; tests/texel_decode.rs runs every load_* on
// uploaded arrays and checks each field. The texture atlas's texels are R32UI, one packed RGBA8
// texel each as before: `unpackUnorm4x8` still decodes them, bit for bit (an RGBA8 view would
// leave the unorm conversion to the driver).
// A fetch none of whose fields the caller reads is dead code once inlined, and compilers drop it.
// Needs GL_EXT_samplerless_texture_functions (enabled by each .comp).
#ifndef VKRT_SCENE_BINDINGS_GLSL
#define VKRT_SCENE_BINDINGS_GLSL
#include "bvh_bindings.glsl"

layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { GpuFrame frame; };

#ifndef LAYOUT_PROBE
layout(set = 0, binding = BINDING_SHADING) uniform utextureBuffer shading_texels;
layout(set = 0, binding = BINDING_MATERIALS) uniform utextureBuffer material_texels;
layout(set = 0, binding = BINDING_LIGHTS) uniform utextureBuffer light_texels;
layout(set = 0, binding = BINDING_EMITTERS) uniform utextureBuffer emitter_texels;
layout(set = 0, binding = BINDING_TEXTURES) uniform utextureBuffer texture_texels;
layout(set = 0, binding = BINDING_TEXELS) uniform utextureBuffer atlas_texels;
layout(set = 0, binding = BINDING_UVS) uniform utextureBuffer uv_texels;
// The environment map: RGBA32F radiance as bits, and its sampling CDFs (environment.glsl).
layout(set = 0, binding = BINDING_ENV_TEXELS) uniform utextureBuffer env_texels;
layout(set = 0, binding = BINDING_ENV_CDF) uniform utextureBuffer env_cdf_texels;
layout(set = 0, binding = BINDING_TANGENTS) uniform utextureBuffer tangent_texels;

// 48 B: n0, material | n1, pad | n2, pad.
GpuShading load_shading(uint i) {
    uvec4 a = texelFetch(shading_texels, int(3u * i));
    uvec4 b = texelFetch(shading_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(shading_texels, int(3u * i + 2u));
    return GpuShading(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), 0u, uintBitsToFloat(c.xyz), 0u);
}

// 96 B: diffuse, flags | specular, shininess | emission, ior
//     | diffuse_texture, alpha_texture, emission_texture, alpha_cutoff
//     | metallic, roughness, metallic_roughness_texture, normal_scale | normal_texture, pad x3.
GpuMaterial load_material(uint i) {
    uvec4 a = texelFetch(material_texels, int(6u * i));
    uvec4 b = texelFetch(material_texels, int(6u * i + 1u));
    uvec4 c = texelFetch(material_texels, int(6u * i + 2u));
    uvec4 d = texelFetch(material_texels, int(6u * i + 3u));
    uvec4 e = texelFetch(material_texels, int(6u * i + 4u));
    uvec4 f = texelFetch(material_texels, int(6u * i + 5u));
    return GpuMaterial(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                       uintBitsToFloat(c.xyz), uintBitsToFloat(c.w), d.x, d.y, d.z, uintBitsToFloat(d.w),
                       uintBitsToFloat(e.x), uintBitsToFloat(e.y), e.z, uintBitsToFloat(e.w), f.x, 0u, 0u, 0u);
}

// 48 B: position, kind | direction, radius | intensity, pad.
GpuLight load_light(uint i) {
    uvec4 a = texelFetch(light_texels, int(3u * i));
    uvec4 b = texelFetch(light_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(light_texels, int(3u * i + 2u));
    return GpuLight(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w), uintBitsToFloat(c.xyz), uintBitsToFloat(c.w));
}

// 64 B: v0, prim | v1, area | v2, pad | radiance, pad.
GpuEmitter load_emitter(uint i) {
    uvec4 a = texelFetch(emitter_texels, int(4u * i));
    uvec4 b = texelFetch(emitter_texels, int(4u * i + 1u));
    uvec4 c = texelFetch(emitter_texels, int(4u * i + 2u));
    uvec4 d = texelFetch(emitter_texels, int(4u * i + 3u));
    return GpuEmitter(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), uintBitsToFloat(b.w),
                      uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz), 0u);
}

// The point of emitter `em` at barycentrics b, and its unit normal: the side it emits from.
vec3 emitter_point(GpuEmitter em, vec3 b) {
    return b.x * em.v0 + b.y * em.v1 + b.z * em.v2;
}
vec3 emitter_normal(GpuEmitter em) {
    return normalize(cross(em.v1 - em.v0, em.v2 - em.v0));
}

// 16 B: offset, width, height, pad.
GpuTexture load_texture(uint i) {
    uvec4 a = texelFetch(texture_texels, int(i));
    return GpuTexture(a.x, a.y, a.z, 0u);
}

// Texel i of the atlas: packed RGBA8, red in the low byte.
uint load_atlas_texel(uint i) {
    return texelFetch(atlas_texels, int(i)).x;
}

// 32 B: uv0, uv1 | uv2, pad, pad.
GpuUv load_uv(uint i) {
    uvec4 a = texelFetch(uv_texels, int(2u * i));
    uvec4 b = texelFetch(uv_texels, int(2u * i + 1u));
    return GpuUv(uintBitsToFloat(a.xy), uintBitsToFloat(a.zw), uintBitsToFloat(b.xy), 0u, 0u);
}

// 48 B: t0 | t1 | t2.
GpuTangents load_tangents(uint i) {
    uvec4 a = texelFetch(tangent_texels, int(3u * i));
    uvec4 b = texelFetch(tangent_texels, int(3u * i + 1u));
    uvec4 c = texelFetch(tangent_texels, int(3u * i + 2u));
    return GpuTangents(uintBitsToFloat(a), uintBitsToFloat(b), uintBitsToFloat(c));
}
#endif

#endif
