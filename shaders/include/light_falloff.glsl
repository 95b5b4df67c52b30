// Angular falloff of the light kinds that need one, shared by both integrators.
#ifndef VKRT_LIGHT_FALLOFF_GLSL
#define VKRT_LIGHT_FALLOFF_GLSL

// The falloff of a cone (glTF spot) light at cosine cd from its axis: KHR_lights_punctual's
// README, "Inner and Outer Cone Angles", saturate(cd * scale + offset)^2 with
// scale = 1 / max(0.001, cos_inner - cos_outer) and offset = -cos_outer * scale.
// Mirrors scene::Light::cone_falloff.
float cone_falloff(float cd, float cos_inner, float cos_outer) {
    float scale = 1.0 / max(0.001, cos_inner - cos_outer);
    float a = clamp((cd - cos_outer) * scale, 0.0, 1.0);
    return a * a;
}

#endif
