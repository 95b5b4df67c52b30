// Light selection and next-event estimation for the path tracer: pick an emitter by power from
// the alias table (prepare::light_table), then a point on it by area.
#ifndef VKRT_LIGHTS_GLSL
#define VKRT_LIGHTS_GLSL
#include "features.glsl"
#include "light_falloff.glsl"
#include "math.glsl"
#include "path_bindings.glsl"
#include "sampling.glsl"
#include "scene_bindings.glsl"
#include "environment.glsl"
#include "emission.glsl"

// Entry j of the table with probability load_light_pick(j).pmf (Vose 1991). u is consumed and
// given back rescaled to [0, 1) within the part of [0, 1) that chose j, so that the caller can
// reuse it: points drawn with it stay stratified over the union of the emitters instead of each
// emitter getting a random subset of the samples (Pharr, Jakob & Humphreys, PBRT 3rd ed.,
// section 13.3, "sample reuse").
uint pick_light(inout float u, out float pmf) {
    uint n = params.pick_count;
    float x = u * float(n);
    uint i = min(uint(x), n - 1u);
    GpuLightPick e = load_light_pick(i);
    float f = x - float(i);
    uint j;
    if (f < e.threshold) {
        j = i;
        u = f / e.threshold;
        pmf = e.pmf;
    } else {
        j = e.alias;
        u = (f - e.threshold) / (1.0 - e.threshold);
        pmf = e.alias_pmf;
    }
    u = min(u, ONE_MINUS_EPSILON);
    return j;
}

// Area density with which light sampling picks a point on an emissive triangle of radiance
// `ke`: its selection weight pi * area * mean(ke), over the total, over its area.
float emitter_area_pdf(vec3 ke) {
    return PI * mean3(ke) * params.inv_total_weight;
}

// A sampled light: direction, the radiance (or irradiance, for delta lights) arriving along it
// divided by the sampling density, the solid-angle density (0 for delta lights) and the
// shadow ray (origin + t * span for t in (0, span_tmax)).
struct LightSample {
    vec3 wi;
    vec3 li_over_pdf;
    float pdf;
    vec3 span;
    float span_tmax;
    float pa;
};

// Whether the sample's shadow ray ends at a point of the scene (an emitter's point, a point
// light's position) rather than leaving it (a directional light, the environment map): if so
// it skips the triangle list's walls (traverse.glsl). A constant where the scene has neither of
// the distant kinds, so that the walls' tests leave the compiled shadow ray altogether.
bool ends_in_scene(LightSample ls) {
    return !(HAS_DIRECTIONAL || HAS_ENVMAP) || !isinf(ls.span_tmax);
}

// Samples a light as seen from p (geometric normal ng on the side being lit, ray origin
// `origin`). Returns false if the light sample faces away or carries nothing.
bool sample_light(vec3 p, vec3 origin, vec2 u, out LightSample ls) {
    ls.wi = vec3(0.0, 0.0, 1.0);
    ls.li_over_pdf = vec3(0.0);
    ls.pdf = 0.0;
    ls.span = vec3(0.0);
    ls.span_tmax = 0.0;
    ls.pa = 0.0;
    if (params.pick_count == 0u) return false;
    float pmf;
    uint j = pick_light(u.x, pmf);
    if (pmf <= 0.0) return false;
    if (HAS_EMITTERS && j < frame.emitter_count) {
        GpuEmitter em = load_emitter(j);
        vec3 b = sample_triangle_bary(u);
        vec3 q = emitter_point(em, b);
        vec3 en = emitter_normal(em);
        vec3 to_light = q - p;
        float d2 = dot(to_light, to_light);
        ls.wi = to_light * inversesqrt(d2);
        float cos_light = dot(en, -ls.wi);
        // Emitters emit from their front face only.
        if (cos_light <= 0.0 || d2 <= 0.0) return false;
        ls.pa = emitter_area_pdf(em.radiance);
        ls.pdf = ls.pa * d2 / cos_light;
        ls.li_over_pdf = emitter_emission(em, b) / ls.pdf;
        // Between the two offset points, so that neither surface shadows itself.
        ls.span = offset_ray(q, en, frame.scene_scale) - origin;
        ls.span_tmax = 1.0;
        return true;
    }
    // The environment map is the table's last entry (prepare::GpuScene::set_environment).
    if (env_present() && j == params.pick_count - 1u) {
        float pdf;
        vec3 li;
        if (!env_sample(u, ls.wi, li, pdf)) return false;
        ls.pdf = pmf * pdf;
        ls.li_over_pdf = li / ls.pdf;
        ls.span = ls.wi;
        ls.span_tmax = 1.0 / 0.0;
        return any(greaterThan(ls.li_over_pdf, vec3(0.0)));
    }
    if (!(HAS_POINT || HAS_DIRECTIONAL || HAS_SPOT || HAS_CONE)) return false;
    GpuLight light = load_light(j - frame.emitter_count);
    if (HAS_DIRECTIONAL && light.kind == LIGHT_DIRECTIONAL) {
        // Irradiance `intensity` on a surface facing the light.
        ls.wi = light.direction;
        ls.li_over_pdf = light.intensity / pmf;
        ls.span = ls.wi;
        ls.span_tmax = 1.0 / 0.0;
        return true;
    }
    vec3 to_light = light.position - p;
    float d2 = dot(to_light, to_light);
    float dist = sqrt(d2);
    ls.wi = to_light / dist;
    // Radiant intensity toward p: `intensity` (point), intensity 4 pi r^2 max(0, cos) (spot) or
    // intensity times the cone falloff (cone; `radius` holds cos_inner).
    vec3 i = light.intensity;
    if (HAS_SPOT && light.kind == LIGHT_SPOT) i *= 4.0 * PI * light.radius * light.radius * max(dot(light.direction, -ls.wi), 0.0);
    if (HAS_CONE && light.kind == LIGHT_CONE) i *= cone_falloff(dot(light.direction, -ls.wi), light.radius, light.cos_outer);
    ls.li_over_pdf = i / (d2 * pmf);
    ls.span = ls.wi;
    ls.span_tmax = dist;
    return any(greaterThan(ls.li_over_pdf, vec3(0.0)));
}

#endif
