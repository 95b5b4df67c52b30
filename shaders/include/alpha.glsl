// Alpha cut-outs: the leaf test (leaf.glsl) asks alpha_passes() of each triangle it hits in
// shader variants built with ALPHA_TEST (the integrators'), so that closest-hit and shadow
// queries of every BVH layout skip see-through texels; trace.comp sees geometry only. Only
// materials flagged MATERIAL_ALPHA pay for a lookup, and scenes without cut-outs compile it
// away (HAS_ALPHA).
#ifndef VKRT_ALPHA_GLSL
#define VKRT_ALPHA_GLSL
#include "scene_bindings.glsl"
#include "features.glsl"
#include "texture.glsl"

// Alpha below this is see-through (the lab renderer's rule).
const float ALPHA_CUTOFF = 0.2;

// True if the hit at barycentrics (u, v) of primitive prim is opaque.
bool alpha_passes(uint prim, float u, float v) {
    if (!HAS_ALPHA) return true;
    GpuMaterial m = load_material(load_shading(prim).material);
    if ((m.flags & MATERIAL_ALPHA) == 0u) return true;
    return texture_uv(m.alpha_texture, uv_at(prim, u, v), false).a >= ALPHA_CUTOFF;
}

#endif
