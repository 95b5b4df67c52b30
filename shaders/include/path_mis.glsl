// The multiple importance sampling weights of the path tracer's estimators that meet at a
// vertex (Veach & Guibas 1995): one function per estimator, each weighing its own sample
// against the strategies that could have made the same path. The power heuristic for two
// strategies, the balance heuristic where light-vertex connections make three
// (docs/experiments/light-connections.md). Light through mirrors and the connections
// themselves weigh their samples in their own headers (mirror_light.glsl, light_connection.glsl).
#ifndef VKRT_PATH_MIS_GLSL
#define VKRT_PATH_MIS_GLSL
#include "path_state.glsl"
#include "sampling.glsl"

// The solid-angle density with which light sampling would have picked the emitter point of
// surface s (material m), reached along unit `dir` by a path `dist` long from where light
// sampling aims: its area density over the projected solid angle. Light sampling weighs an
// emitter by its emission factor, without the texture.
float emitter_hit_pdf(Surface s, GpuMaterial m, vec3 dir, float dist) {
    float cos_light = dot(s.ng, -dir);
    vec3 ke = HAS_TEXTURES ? load_material(s.material).emission : m.emission;
    return emitter_area_pdf(ke) * dist * dist / max(cos_light, 1e-12);
}

// Whether a BSDF-sampled ray that left the scene into the environment map is weighed against
// light sampling, which picks the map too (env_hit_weight then needs the map's density there).
bool env_hit_weighed(PathState ps, bool nee) {
    return nee && !ps.prev_delta;
}

// Its weight, given the density with which light sampling draws its direction (env_lookup).
float env_hit_weight(PathState ps, float env_density, bool nee) {
    if (env_hit_weighed(ps, nee)) return power_heuristic(ps.prev_pdf, frame.env_pick_pmf * env_density);
    return 1.0;
}

// A BSDF-sampled ray that hit emitter surface s (material m) at distance t: against light
// sampling from the bounce's vertex, against the light-vertex connection from the vertex
// before it, and, past a planar mirror, against light sampled through that mirror.
float emitter_hit_weight(PathState ps, Surface s, GpuMaterial m, vec3 dir, float t, bool nee) {
    float w = 1.0;
    if (nee && !ps.prev_delta) {
        float light_pdf = emitter_hit_pdf(s, m, dir, t);
        // The connection from the bounce's vertex, as a solid angle there like the
        // others: (cos_q / pi) cos / t^2 over bounce_arrive, times the light's density.
        float connect_pdf = 0.0;
        if (LIGHT_CONNECTIONS && ps.bounce_arrive > 0.0) connect_pdf = light_pdf * (dot(s.ng, -dir) / PI) * ps.bounce_cos / (t * t * ps.bounce_arrive);
        w = LIGHT_CONNECTIONS ? balance_heuristic3(ps.prev_pdf, light_pdf, connect_pdf) : power_heuristic(ps.prev_pdf, light_pdf);
    }
#ifdef MIRRORS
    // Light sampling through that mirror would have aimed at this point from the image
    // of the bounce's point: the whole path's length, this cosine.
    else if (nee && ps.mirror_pdf > 0.0) {
        float light_pdf = emitter_hit_pdf(s, m, dir, ps.mirror_dist + t);
        w = power_heuristic(ps.mirror_pdf, light_pdf / float(params.mirror_count));
    }
#endif
    return w;
}

// Light sample ls at surface s, whose BSDF (with the guide) would have sampled its direction
// with density bsdf_pdf: against that BSDF sample and, where `arrive_area` > 0 (the area density
// with which the path's last bounce reached s, from a vertex that made a light-vertex
// connection), against that connection. Delta lights (pdf 0) cannot be hit by BSDF sampling:
// their weight is 1.
float light_sample_weight(LightSample ls, Surface s, float bsdf_pdf, float arrive_area) {
    if (!(ls.pdf > 0.0)) return 1.0;
    // The connection's density for this light point and s, as a solid angle at s like the
    // other two: its area density over arrive_area's, (pA (cos_q / pi) cos_s / d^2) /
    // arrive_area, times light sampling's ls.pdf = pA d^2 / cos_q.
    float connect_pdf = 0.0;
    if (LIGHT_CONNECTIONS && arrive_area > 0.0 && ls.pa > 0.0) connect_pdf = (ls.pa / PI) * dot(s.ng, ls.wi) / arrive_area;
    // (Without connections the two-way form: the same arithmetic, the same bytes as before.)
    return LIGHT_CONNECTIONS ? balance_heuristic3(ls.pdf, bsdf_pdf, connect_pdf) : power_heuristic(ls.pdf, bsdf_pdf);
}

#endif
