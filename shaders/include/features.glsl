// What the scene uses, as specialization constants (ids SPEC_* in host/gpu_abi/constants.rs,
// values from host/prepare/features.rs). Each defaults to true, so a pipeline made without
// specialization info is the all-features shader; a false one lets the driver's compiler fold
// the branch away, so a scene pays only for what it uses.
#ifndef VKRT_FEATURES_GLSL
#define VKRT_FEATURES_GLSL
#include "constants.glsl"

layout(constant_id = SPEC_HAS_MIRROR) const bool HAS_MIRROR = true;
layout(constant_id = SPEC_HAS_GLOSSY) const bool HAS_GLOSSY = true;
layout(constant_id = SPEC_HAS_EMITTERS) const bool HAS_EMITTERS = true;
#ifdef LEAN
// The lean variants (host/pipeline/variants.rs), for scenes whose only features are the three
// above (Lambert, glossy and mirror materials without textures, lit by emissive triangles):
// the rest are compile-time false, so glslang drops their code and lavapipe, which parses
// the SPIR-V before specialization can drop anything, never sees it (pipeline creation on the
// Cornell boxes 20-50 ms shorter: docs/experiments/lean-variants.md).
const bool HAS_TEXTURES = false;
const bool HAS_ALPHA = false;
const bool HAS_DIELECTRIC = false;
const bool HAS_POINT = false;
const bool HAS_DIRECTIONAL = false;
const bool HAS_SPOT = false;
const bool HAS_SKY = false;
const bool HAS_ENVMAP = false;
const bool HAS_METALLIC_ROUGHNESS = false;
const bool HAS_NORMAL_MAP = false;
const bool HAS_CONE = false;
#else
layout(constant_id = SPEC_HAS_TEXTURES) const bool HAS_TEXTURES = true;
layout(constant_id = SPEC_HAS_ALPHA) const bool HAS_ALPHA = true;
layout(constant_id = SPEC_HAS_DIELECTRIC) const bool HAS_DIELECTRIC = true;
layout(constant_id = SPEC_HAS_POINT) const bool HAS_POINT = true;
layout(constant_id = SPEC_HAS_DIRECTIONAL) const bool HAS_DIRECTIONAL = true;
layout(constant_id = SPEC_HAS_SPOT) const bool HAS_SPOT = true;
layout(constant_id = SPEC_HAS_SKY) const bool HAS_SKY = true;
layout(constant_id = SPEC_HAS_ENVMAP) const bool HAS_ENVMAP = true;
layout(constant_id = SPEC_HAS_METALLIC_ROUGHNESS) const bool HAS_METALLIC_ROUGHNESS = true;
layout(constant_id = SPEC_HAS_NORMAL_MAP) const bool HAS_NORMAL_MAP = true;
layout(constant_id = SPEC_HAS_CONE) const bool HAS_CONE = true;
#endif

#endif
