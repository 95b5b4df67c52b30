// Alpha cut-outs: the leaf test (leaf.glsl) asks alpha_passes() of each triangle it hits in
// shader variants built with ALPHA_TEST (the integrators'), so that closest-hit and shadow
// queries of every BVH layout skip see-through texels; trace.comp sees geometry only. Only
// materials flagged MATERIAL_ALPHA pay for a lookup, and scenes without cut-outs compile it
// away (HAS_ALPHA).
//
// A texel is see-through where its alpha is below the material's alpha_cutoff (0.2, the lab
// renderer's rule, for MTL and lab materials; glTF alphaCutoff for MASK). glTF BLEND
// (MATERIAL_BLEND) reads alpha as coverage instead:
// - in the path tracer (STOCHASTIC_ALPHA, a define of its variant), stochastic transparency
//   (Enderton et al. 2010, "Stochastic transparency"): a ray takes a triangle's texel as opaque
//   with probability alpha, drawn from a hash of the primitive and the ray. Closest-hit and
//   shadow rays alike, so the expected radiance is alpha times the surface's plus (1 - alpha)
//   times what lies behind it, and the expected shadow-ray visibility is the product of the
//   (1 - alpha) it passes: unbiased, like an any-hit shader's coverage test. Rays differ from
//   sample to sample, so each draw is fresh; the same ray sees the same answer (the same image
//   from the same seed);
// - in Whitted, which has no samples to average, a cut-out at 0.5 (what MASK with the default
//   alphaCutoff does).
#ifndef VKRT_ALPHA_GLSL
#define VKRT_ALPHA_GLSL
#include "scene_bindings.glsl"
#include "features.glsl"
#include "intersect.glsl"
#include "rng.glsl"
#include "texture.glsl"

// Whitted's cut-out for BLEND materials.
const float BLEND_AS_MASK_CUTOFF = 0.5;

// Uniform in [0, 1) from the primitive and the ray (origin and direction bits).
float coverage_draw(uint prim, RayPre r) {
    uvec3 o = floatBitsToUint(r.origin);
    uvec3 d = floatBitsToUint(r.dir);
    uint h = hash_pcg(prim ^ hash_pcg(o.x ^ hash_pcg(o.y ^ hash_pcg(o.z ^ hash_pcg(d.x ^ hash_pcg(d.y ^ hash_pcg(d.z)))))));
    return float(h >> 8u) * (1.0 / 16777216.0);
}

// True if the hit at barycentrics (u, v) of primitive prim is opaque for ray r.
bool alpha_passes(uint prim, float u, float v, RayPre r) {
    bool opaque = true;
    // A block on the constant, not an early return (see material_at in surface.glsl): this
    // runs in every inlined BVH walk.
    if (HAS_ALPHA) {
        GpuMaterial m = load_material(load_shading(prim).material);
        if ((m.flags & MATERIAL_ALPHA) != 0u) {
            float alpha = texture_uv(m.alpha_texture, uv_at(prim, u, v), false).a;
            if ((m.flags & MATERIAL_BLEND) != 0u) {
#ifdef STOCHASTIC_ALPHA
                opaque = coverage_draw(prim, r) < alpha;
#else
                opaque = alpha >= BLEND_AS_MASK_CUTOFF;
#endif
            } else {
                opaque = alpha >= m.alpha_cutoff;
            }
        }
    }
    return opaque;
}

#endif
