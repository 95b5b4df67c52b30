// Emission textures where light sampling needs them (lights.glsl); material_at (surface.glsl)
// applies the same texture at a hit.
#ifndef VKRT_EMISSION_GLSL
#define VKRT_EMISSION_GLSL
#include "features.glsl"
#include "scene_bindings.glsl"
#include "texture.glsl"

// The emitted radiance at barycentrics (u, v) of emissive primitive prim: its material's
// emission times the emission texture there, as material_at gives it. Light
// sampling picks emitters by the factor alone (prepare::scene_buffers), so with a texture the
// pick is less well matched to the power but the estimate stays unbiased.
vec3 emission_at(uint prim, float u, float v, vec3 factor) {
    vec3 e = factor;
    // A block on the constant, not an early return (see material_at).
    if (HAS_TEXTURES) {
        GpuMaterial m = load_material(load_shading(prim).material);
        if (m.emission_texture != TEXTURE_NONE) e *= texture_uv(m.emission_texture, uv_at(prim, u, v), true).rgb;
    }
    return e;
}

// An emitter's radiance at barycentrics b (b.y, b.z those of its second and third vertices) of
// its world triangle: a mirrored copy's has those two in the other order than its shading
// entry's (EMITTER_SWAPPED, prepare::mesh_shading).
vec3 emitter_emission(GpuEmitter em, vec3 b) {
    bool swapped = (em.flags & EMITTER_SWAPPED) != 0u;
    return emission_at(em.prim, swapped ? b.z : b.y, swapped ? b.y : b.z, em.radiance);
}

#endif
