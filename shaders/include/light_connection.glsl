// Light-vertex connections (host/integrator/path/connections.rs says when and why): each
// sample starts one light subpath, a point y0 on an emissive triangle and the first surface y1
// its cosine-distributed ray hits, and every surface vertex x of the camera path is joined to
// y1 by a shadow ray: bidirectional path tracing's s = 2 strategy (Veach 1997, chapter 10).
// The path x -> y1 -> y0 can also come from x's bounce followed by light sampling at y1 or by
// y1's own bounce finding the light; the three are weighted by the balance heuristic over their
// area densities (Veach & Guibas 1995; sampling.glsl's balance_heuristic3 says why not the power
// heuristic), here and in path.comp's light sampling and emitter hits.
#ifndef VKRT_LIGHT_CONNECTION_GLSL
#define VKRT_LIGHT_CONNECTION_GLSL
#include "bsdf.glsl"
#include "caster_guide.glsl"
#include "lights.glsl"
#include "offset.glsl"
#include "sampler.glsl"
#include "sampling.glsl"
#include "surface.glsl"
#include "traverse.glsl"

// A build that aims bounces at caustic casters never connects (the guide's density is not in
// the connections' weights: integrator::path::connections, `unavailable`), and the host runs a
// lean mirror build only where the scene does not connect (`--connections on` in a mirror scene
// takes the full path_mirrors build), so their code is compiled out there: lavapipe parses all
// of the SPIR-V before specialization drops code. path_casters_lean 252 -> 194 kB, pipeline
// creation on CornellBox-Sphere ~0.115 -> ~0.097 s; path_mirrors_lean on CornellBox-Mirror
// ~0.19 -> ~0.17 s (docs/experiments/lean-variants.md). The host's constant is then unused;
// its twin of this condition is pipeline::shaders::PathShader::can_connect.
#if defined(CASTERS) || (defined(MIRRORS) && defined(LEAN))
const bool LIGHT_CONNECTIONS = false;
#else
layout(constant_id = SPEC_LIGHT_CONNECTIONS) const bool LIGHT_CONNECTIONS = true;
#endif

struct LightVertex {
    bool valid;
    vec3 p;
    // Geometric normal on the side the light came from, and the shading frame.
    vec3 ng;
    Onb f;
    // Toward y0, in the shading frame.
    vec3 wi;
    Lobes l;
    // Emitted radiance over the densities of y0 and of the ray's direction, Le pi / pA; the
    // geometry term between y0 and y1 cancels against the direction's density.
    vec3 beta;
    // Area density of y0 (light sampling's, with the emitter pick), the cosine at y0 and the
    // squared distance y0-y1, the geometric cosine at y1 toward y0.
    float pa;
    float cos0;
    float dist2;
    float cos_in;
};

// The sample's light vertex. Always draws its four numbers, so the camera path's numbers do
// not depend on where the light ray went.
LightVertex light_vertex(inout Sampler smp, inout uint rays) {
    LightVertex lv;
    lv.valid = false;
    vec2 ue = sampler_2d(smp);
    vec2 ud = sampler_2d(smp);
    if (!HAS_EMITTERS || params.pick_count == 0u) return lv;
    float pmf;
    uint j = pick_light(ue.x, pmf);
    // Connections start from emissive triangles only: the other lights' paths keep light
    // sampling's weights (next_event gives them no connection density).
    if (pmf <= 0.0 || j >= frame.emitter_count) return lv;
    GpuEmitter em = load_emitter(j);
    vec3 b = sample_triangle_bary(ue);
    vec3 q = emitter_point(em, b);
    vec3 en = emitter_normal(em);
    vec3 dl = sample_cosine_hemisphere(ud);
    if (dl.z <= 0.0) return lv;
    vec3 d = to_world(onb_from(en), dl);
    rays++;
    Hit h = trace_closest(offset_ray(q, en, frame.scene_scale), d, 0.0, 1.0 / 0.0);
    if (h.prim == PRIM_NONE) return lv;
    Surface s = surface_at(h, d);
    GpuMaterial m = material_at(h, s);
    Lobes l = lobes_of(m);
    if (!has_smooth_lobes(l)) return lv;
    lv.pa = emitter_area_pdf(em.radiance);
    lv.cos_in = abs(dot(s.ng, d));
    // A grazing hit carries nothing and would divide by zero below.
    lv.valid = lv.pa > 0.0 && lv.cos_in > 0.0;
    lv.p = s.p;
    lv.ng = s.ng;
    lv.f = onb_from(s.ns);
    lv.wi = to_local(lv.f, -d);
    lv.l = l;
    lv.beta = emitter_emission(em, b) * (PI / lv.pa);
    lv.cos0 = dl.z;
    lv.dist2 = h.t * h.t;
    return lv;
}

// The connection of camera vertex s (lobes l, frame f, toward the viewer wo, guide g, shadow
// rays from `origin`) to the light vertex, MIS-weighted; `rays` counts its shadow ray.
vec3 connect_light_vertex(LightVertex lv, Surface s, Lobes l, Onb f, vec3 wo, Guide g, vec3 origin, inout uint rays) {
    vec3 v = lv.p - s.p;
    float d2 = dot(v, v);
    if (!(d2 > 0.0)) return vec3(0.0);
    vec3 w = v * inversesqrt(d2);
    // Reflection at both ends: y1 on x's side, x on the side the light came to y1 from.
    float cos_y = dot(-w, lv.ng);
    if (dot(w, s.ng) <= 0.0 || cos_y <= 0.0) return vec3(0.0);
    vec3 wix = to_local(f, w);
    float pdf_x;
    vec3 fx = bsdf_eval(l, wo, wix, pdf_x);
    if (all(equal(fx, vec3(0.0)))) return vec3(0.0);
    pdf_x = guide_mix(g, pdf_x, w);
    float pdf_y;
    vec3 fy = bsdf_eval(lv.l, to_local(lv.f, -w), lv.wi, pdf_y);
    if (all(equal(fy, vec3(0.0)))) return vec3(0.0);
    // Area densities of the pair (y1, y0) under the three strategies, over the connection's
    // (y0 by light sampling, y1 by its ray: pA (cos0 / pi) cos_in / dist2): x's bounce to y1
    // (pdf_x cos_y / d2) then light sampling (pA), or then y1's bounce (pdf_y cos0 / dist2).
    // As ratios: the densities themselves underflow in a large scene.
    float p_x = pdf_x * cos_y / d2;
    float light_ratio = p_x * PI * (lv.dist2 / (lv.cos0 * lv.cos_in));
    float bounce_ratio = (p_x / lv.pa) * pdf_y * PI / lv.cos_in;
    float w_mis = balance_heuristic3(1.0, light_ratio, bounce_ratio);
    if (!(w_mis > 0.0)) return vec3(0.0);
    rays++;
    vec3 target = offset_ray(lv.p, lv.ng, frame.scene_scale);
    if (occluded(origin, target - origin, 0.0, 1.0, true)) return vec3(0.0);
    // f_x cos_x G f_y, with y1's cosines as the path tracer's light sampling there has them
    // (shading toward y0, geometric toward x; beta holds the geometric one toward y0): the
    // same measurement with shading normals as the other two strategies.
    return fx * wix.z * fy * (lv.wi.z * cos_y / (lv.cos_in * d2)) * lv.beta * w_mis;
}

#endif
