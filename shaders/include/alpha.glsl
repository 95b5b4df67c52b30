// Alpha cut-outs: traversal (traverse.glsl, test_leaf) asks alpha_passes() of each triangle
// it hits when this file is included before it, so that closest-hit and shadow queries of
// every BVH layout skip see-through texels. Shaders without it (trace.comp) see geometry only.
// Only materials flagged MATERIAL_ALPHA pay for a lookup, and scenes without cut-outs compile
// it away (HAS_ALPHA). Needs scene_bindings.glsl, features.glsl and texture.glsl.
#ifndef VKRT_ALPHA_GLSL
#define VKRT_ALPHA_GLSL

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
