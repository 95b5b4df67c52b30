#version 460
// Progressive unidirectional path tracing (Kajiya 1986) with next-event estimation and
// multiple importance sampling (Veach & Guibas 1995; the power heuristic for two strategies, the
// balance heuristic for light-vertex connections' three), Russian roulette
// from params.rr_depth. One invocation per pixel of a tile; each dispatch adds
// push.sample_count samples to the running sums (even- and odd-indexed samples apart, in fixed
// point: exact and the same in any order), so a render is any number of short dispatches and
// any split of its samples (resumed runs, shards) sums to the same bytes.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings.glsl"
#include "path_bindings.glsl"
#include "fixed_point.glsl"
#include "features.glsl"
#include "texture.glsl"
#include "traverse.glsl"
#include "rng.glsl"
#include "sampler.glsl"
#include "camera.glsl"
#include "tile_region.glsl"
#include "offset.glsl"
#include "surface.glsl"
#include "sampling.glsl"
#include "bsdf.glsl"
#include "lights.glsl"
#include "caster_guide.glsl"
#include "light_connection.glsl"
#include "path_state.glsl"
#include "path_mis.glsl"
#ifdef MIRRORS
#include "mirror_probe.glsl"
#include "mirror_light.glsl"
#endif

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_X, local_size_y_id = SPEC_WORKGROUP_Y) in;


// Light sampling at surface s: one light, one point on it, weighted against BSDF sampling
// (mixed with the guide g, caster_guide.glsl) and, where `arrive_area` > 0 (the area density
// with which the path's last bounce reached s, from a vertex that made a light-vertex
// connection), against that connection (light_connection.glsl). `rays` counts the shadow ray
// if one is traced.
vec3 next_event(Surface s, Lobes l, Onb f, vec3 wo, Guide g, vec3 origin, inout Sampler smp, inout uint rays, float arrive_area) {
    vec2 u = sampler_2d(smp);
    LightSample ls;
    if (!sample_light(s.p, origin, u, ls)) return vec3(0.0);
    // Lambert and glossy reflect only: the light must be on the side the ray came from.
    if (dot(ls.wi, s.ng) <= 0.0) return vec3(0.0);
    vec3 wi = to_local(f, ls.wi);
    float bsdf_pdf;
    vec3 fr = bsdf_eval(l, wo, wi, bsdf_pdf);
    if (all(equal(fr, vec3(0.0)))) return vec3(0.0);
    bsdf_pdf = guide_mix(g, bsdf_pdf, ls.wi);
    rays++;
    if (occluded(origin, ls.span, 0.0, ls.span_tmax, ends_in_scene(ls))) return vec3(0.0);
    return fr * wi.z * ls.li_over_pdf * light_sample_weight(ls, s, bsdf_pdf, arrive_area);
}

// The radiance along the camera ray (origin, dir); `rays` counts the rays traced for it.
// `first_p_spec` > 0: the mirror lobe's probability at the first hit (mirror_probe.glsl).
vec3 radiance(vec3 origin, vec3 dir, inout Sampler smp, inout uint rays, float first_p_spec) {
    PathState ps = path_start();
    bool nee = params.nee != 0u;
    LightVertex lv;
    lv.valid = false;
    if (LIGHT_CONNECTIONS && nee) lv = light_vertex(smp, rays);
    for (uint depth = 0u;; depth++) {
        rays++;
        Hit h = trace_closest(origin, dir, 0.0, 1.0 / 0.0);
        if (h.prim == PRIM_NONE) {
            if (env_present()) {
                float density;
                vec3 l = env_lookup(dir, env_hit_weighed(ps, nee), density);
                ps.result += ps.throughput * l * env_hit_weight(ps, density, nee);
            } else if (HAS_SKY) {
                // No light sampling picks the sky, so BSDF sampling gets it all (MIS weight 1).
                ps.result += ps.throughput * sky_radiance(dir);
            }
            break;
        }
        Surface s = surface_at(h, dir);
        GpuMaterial m = material_at(h, s);
        if (HAS_EMITTERS && s.front && (m.flags & MATERIAL_EMISSIVE) != 0u) {
            // dir is unit, so h.t is the distance.
            ps.result += ps.throughput * m.emission * emitter_hit_weight(ps, s, m, dir, h.t, nee);
        }
        // The next ray (or shadow ray) would be segment depth + 2 of the path.
        if (depth + 1u >= params.max_depth) break;
        Lobes l = lobes_of(m);
        // Before light sampling, whose MIS weight must use the same lobe probabilities.
        if (HAS_MIRROR && depth == 0u && first_p_spec > 0.0 && l.mirror && l.p_spec > 0.0 && l.p_spec < 1.0) {
            l.p_spec = min(l.p_spec, first_p_spec);
        }
        Onb f = onb_from(s.ns);
        vec3 wo = to_local(f, -dir);
        vec3 up = offset_ray(s.p, s.ng, frame.scene_scale);
        // Before light sampling, whose MIS weights must use the bounce's density with the guide.
#ifdef CASTERS
        Guide g = params.caster_count > 0u ? guide_at(s.p, l, smp) : guide_none();
#else
        Guide g = guide_none();
#endif
        // The area density with which the last bounce reached s, if the vertex it left made a
        // connection: a surface vertex (depth >= 1) bouncing by a non-delta lobe.
        float arrive = 0.0;
        if (LIGHT_CONNECTIONS && depth >= 1u && !ps.prev_delta) arrive = ps.prev_pdf * abs(dot(s.ng, dir)) / (h.t * h.t);
        if (nee && has_smooth_lobes(l)) {
            ps.result += ps.throughput * next_event(s, l, f, wo, g, up, smp, rays, arrive);
            // The path x ... s -> y1 -> y0 is segments depth + 2 and depth + 3.
            if (LIGHT_CONNECTIONS && lv.valid && depth + 2u < params.max_depth) ps.result += ps.throughput * connect_light_vertex(lv, s, l, f, wo, g, up, rays);
#ifdef MIRRORS
            // Its path x -> mirror -> light is segments depth + 2 and depth + 3.
            if (params.mirror_count > 0u && depth + 2u < params.max_depth) ps.result += ps.throughput * light_through_mirror(s, l, f, wo, g, up, smp, rays);
#endif
        }
        float u_lobe = sampler_1d(smp);
        vec2 u = sampler_2d(smp);
        BsdfSample bs;
        vec3 wi;
        if (!guided_bsdf_sample(g, l, f, wo, s.front, u_lobe, u, bs, wi)) break;
        // With shading normals a sample can cross the geometric surface: reflection must stay
        // on the ray's side and refraction must cross.
        bool crosses = dot(wi, s.ng) < 0.0;
        if (crosses != (bs.wi.z < 0.0)) break;
        ps.throughput *= bs.weight;
#ifdef MIRRORS
        bool planar = bs.delta && l.mirror && (m.flags & MATERIAL_PLANAR_MIRROR) != 0u && params.mirror_count > 0u;
        ps.mirror_pdf = planar && !ps.prev_delta ? ps.prev_pdf * l.p_spec : 0.0;
        ps.mirror_dist = h.t;
#endif
        if (LIGHT_CONNECTIONS) {
            ps.bounce_arrive = arrive;
            ps.bounce_cos = abs(dot(s.ng, wi));
        }
        ps.prev_pdf = bs.pdf;
        ps.prev_delta = bs.delta;
        origin = crosses ? offset_ray(s.p, -s.ng, frame.scene_scale) : up;
        dir = wi;
        if (depth + 1u >= params.rr_depth) {
            // Russian roulette (Arvo & Kirk 1990): survive with the square root of the
            // throughput's largest component, capped so that no path is certain to go on.
            // Surviving with the throughput itself (q = t, PBRT's and Mitsuba's choice) cuts
            // most paths at once at rr_depth (t is ~0.2 there in a white box), and their
            // boosted survivors cost more variance than the saved rays buy: on cornell-measured
            // sqrt(t) gave 12 % less relMSE per sample for ~7 % more time (docs/experiments/
            // russian-roulette.md). Either way a survivor's throughput t / q then tends to the
            // albedo a, and q to a: path lengths stay bounded alike.
            float q = min(sqrt(max3(ps.throughput)), 0.95);
            if (sampler_1d(smp) >= q) break;
            ps.throughput /= q;
        }
        if (max3(ps.throughput) <= 0.0) break;
    }
    return ps.result;
}

// The adaptive allocation block of `pixel` (integrator::path::adaptive::BlockGrid): with
// scattered coherence the square its group is dealt over, else its run of params.adaptive
// pixels in a row. Blocks are whole coherence blocks, so no two share sample numbers.
uint adaptive_block_key(uvec2 pixel) {
    uint bits = params.coherence_block_bits;
    if (bits == 0u) return sample_key(pixel, frame.width, params.adaptive);
    return coherence_block_index(pixel, frame.width, bits);
}

void main() {
    uvec2 slot = tile_slot();
    uint key;
    uvec2 pixel = coherent_pixel(slot, frame.width, params.coherence, params.coherence_block_bits, frame.seed,
                                 params.sampler_kind == SAMPLER_ZSOBOL, key);
    if (pixel.x >= frame.width || pixel.y >= frame.height) return;
    uint index = pixel.y * frame.width + pixel.x;
    uint rays = 0u;
    // The mirror probe's pass and value (MIRRORS: the path_mirrors variant, for scenes with
    // mirror materials); 0: every first hit picks its lobe by albedo.
    float first_p_spec = 0.0;
#ifdef MIRRORS
    if (push.probe != 0u) {
        mirror_probe[index] = mirror_probe_value(pixel, rays);
        ray_counts[index] += rays;
        return;
    }
    if (HAS_MIRROR) first_p_spec = uintBitsToFloat(mirror_probe[index]);
#endif
    uvec2 samples = uvec2(push.sample_base, push.sample_count);
    // Adaptive: the block's own range; blocks are whole coherence blocks, keyed alike.
    if (params.adaptive != 0u) samples = block_samples[adaptive_block_key(pixel)];
    Fixed3 even = fixed3_zero();
    Fixed3 odd = fixed3_zero();
    uint dropped = 0u;
    for (uint k = 0u; k < samples.y; k++) {
        uint sample_index = samples.x + k;
        Sampler smp = sampler_init(params.sampler_kind, key, sample_index, frame.seed, params.sample_rate, params.zsobol_log2);
        vec2 xy = vec2(pixel) + sampler_pixel(smp);
        vec3 origin = frame.cam_origin;
        vec3 dir;
        if (camera_has_lens(frame)) camera_lens_ray(frame, xy, sampler_2d(smp), origin, dir);
        else dir = camera_ray_direction(frame, xy);
        vec3 c = radiance(origin, dir, smp, rays, first_p_spec);
        // NaN, Inf and samples past the fixed-point range never enter the sums: count them.
        // (Radiance is never negative; max() only keeps a -0.0 from the conversion.)
        if (any(isnan(c)) || any(isinf(c)) || max3(c) >= exp2(float(ACCUM_MAX_SAMPLE_LOG2))) {
            dropped += 1u;
        } else if ((sample_index & 1u) == 0u) {
            even = add_fixed3(even, max(c, vec3(0.0)));
        } else {
            odd = add_fixed3(odd, max(c, vec3(0.0)));
        }
    }
    sum_even_r[index] = add_fixed(sum_even_r[index], even.r);
    sum_even_g[index] = add_fixed(sum_even_g[index], even.g);
    sum_even_b[index] = add_fixed(sum_even_b[index], even.b);
    sum_odd_r[index] = add_fixed(sum_odd_r[index], odd.r);
    sum_odd_g[index] = add_fixed(sum_odd_g[index], odd.g);
    sum_odd_b[index] = add_fixed(sum_odd_b[index], odd.b);
    sample_counts[index] += uvec2(samples.y, dropped);
    ray_counts[index] += rays;
}
