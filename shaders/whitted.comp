#version 460
// Whitted-style ray tracing (Whitted 1980): ambient + Blinn-Phong direct light with hard
// shadows, mirror reflection weighted by Ks, and Fresnel-weighted reflection and refraction
// through dielectrics. The recursive ray tree is walked with a small explicit stack.
// One invocation per pixel of a tile; each dispatch adds push.sample_count samples to accum.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

#include "scene_bindings.glsl"
#include "features.glsl"
#include "light_falloff.glsl"
#include "texture.glsl"
#include "environment.glsl"
#include "traverse.glsl"
#include "rng.glsl"
#include "camera.glsl"
#include "tile_region.glsl"
#include "offset.glsl"
#include "surface.glsl"
#include "math.glsl"
#include "fresnel.glsl"
#include "emission.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_X, local_size_y_id = SPEC_WORKGROUP_Y) in;

layout(std430, set = 0, binding = BINDING_ACCUM) buffer Accum { vec4 accum[]; };

// Barycentric sample points on an emissive triangle: the centroids of its four midpoint
// sub-triangles, each standing for a quarter of its area (WHITTED_EMITTER_SAMPLES = 4).
const vec3 EMITTER_SAMPLE_BARY[4] = vec3[4](
    vec3(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0),
    vec3(2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0),
    vec3(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0),
    vec3(1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0));

// glTF metallic-roughness materials in Whitted's terms (README, "Materials"):
// - diffuse Kd = base colour * (1 - metallic): metals have no diffuse term;
// - specular Ks = mix(0.04, base colour, metallic): the Fresnel f0 of the path tracer's BSDF
//   (bsdf.glsl) at normal incidence, for the Blinn-Phong highlight;
// - Ns from roughness by inverting the path tracer's MTL mapping alpha = sqrt(2 / (Ns + 2))
//   (Walter et al. 2007) with alpha = roughness^2: Ns = 2 / alpha^2 - 2, alpha at least
//   MR_MIN_ALPHA;
// - below WHITTED_MR_MIRROR_ROUGHNESS, also a mirror reflection weighted by Ks (a smooth
//   metal mirrors its base colour, a smooth dielectric reflects 4 %).
const float WHITTED_MR_MIRROR_ROUGHNESS = 0.2;
const float WHITTED_MR_MIN_ALPHA = 1e-3;

GpuMaterial whitted_material(GpuMaterial m) {
    if (!HAS_METALLIC_ROUGHNESS || (m.flags & MATERIAL_METALLIC_ROUGHNESS) == 0u) return m;
    vec3 base = clamp(m.diffuse, 0.0, 1.0);
    float metallic = clamp(m.metallic, 0.0, 1.0);
    float r = clamp(m.roughness, 0.0, 1.0);
    float a = max(r * r, WHITTED_MR_MIN_ALPHA);
    m.diffuse = base * (1.0 - metallic);
    m.specular = mix(vec3(0.04), base, metallic);
    m.shininess = 2.0 / (a * a) - 2.0;
    if (r < WHITTED_MR_MIRROR_ROUGHNESS) m.flags |= MATERIAL_MIRROR;
    return m;
}

// Blinn-Phong response to light arriving from unit direction l with "scaled irradiance" e
// (see scene::Light for the units of each light kind).
vec3 blinn_phong(GpuMaterial m, Surface s, vec3 view, vec3 l, vec3 e) {
    float n_dot_l = dot(s.ns, l);
    if (n_dot_l <= 0.0 || dot(s.ng, l) <= 0.0) return vec3(0.0);
    vec3 c = m.diffuse * n_dot_l;
    if (HAS_GLOSSY || HAS_METALLIC_ROUGHNESS) {
        vec3 h = normalize(l + view);
        c += m.specular * pow(max(dot(s.ns, h), 0.0), m.shininess);
    }
    return c * e;
}

// Ambient plus every light and emitter sample that sees s. The point lights and the emitter
// samples share one loop (index i < light_count: a light; after that, emitter sample
// i - light_count), so the shadow query is written once: lavapipe compiles every inlined copy
// of the traversal loop separately, and each copy costs a second or so of pipeline creation
// time (tools/bench/src/bin/pipeline_time.rs). Contributions are added in the same order as two loops would.
// Light kinds and emitters the scene lacks are compiled out by the specialization constants
// (features.glsl): their counts are then treated as 0 and their code is never reached.
vec3 direct_light(GpuMaterial m, Surface s, vec3 view) {
    vec3 result = frame.ambient * m.diffuse;
    vec3 origin = offset_ray(s.p, s.ng, frame.scene_scale);
    uint light_count = (HAS_POINT || HAS_DIRECTIONAL || HAS_SPOT || HAS_CONE) ? frame.light_count : 0u;
    uint emitter_count = HAS_EMITTERS ? frame.emitter_count : 0u;
    uint shadow_count = light_count + emitter_count * WHITTED_EMITTER_SAMPLES;
    for (uint i = 0u; i < shadow_count; i++) {
        vec3 l;
        vec3 e;
        vec3 span;
        float tmax;
        if (i < light_count) {
            GpuLight light = load_light(i);
            if ((!HAS_POINT && light.kind == LIGHT_POINT) || (!HAS_DIRECTIONAL && light.kind == LIGHT_DIRECTIONAL)
                || (!HAS_SPOT && light.kind == LIGHT_SPOT) || (!HAS_CONE && light.kind == LIGHT_CONE)) continue;
            if (HAS_DIRECTIONAL && light.kind == LIGHT_DIRECTIONAL) {
                l = light.direction;
                e = light.intensity;
                tmax = 1.0 / 0.0;
            } else {
                vec3 to_light = light.position - s.p;
                float d2 = dot(to_light, to_light);
                tmax = sqrt(d2);
                l = to_light / tmax;
                e = light.intensity / d2;
                if (HAS_SPOT && light.kind == LIGHT_SPOT) {
                    // intensity * 4 pi r^2 * cos / d^2, over pi (scene::Light).
                    e *= 4.0 * light.radius * light.radius * max(dot(light.direction, -l), 0.0);
                }
                if (HAS_CONE && light.kind == LIGHT_CONE) {
                    // As a point light, times the cone falloff (scene::Light; `radius` = cos_inner).
                    e *= cone_falloff(dot(light.direction, -l), light.radius, light.cos_outer);
                }
            }
            if (dot(s.ng, l) <= 0.0 || all(equal(e, vec3(0.0)))) continue;
            span = l;
        } else {
            uint j = i - light_count;
            GpuEmitter em = load_emitter(j / WHITTED_EMITTER_SAMPLES);
            vec3 en = emitter_normal(em);
            vec3 b = EMITTER_SAMPLE_BARY[j % WHITTED_EMITTER_SAMPLES];
            vec3 q = emitter_point(em, b);
            vec3 to_light = q - s.p;
            float d2 = dot(to_light, to_light);
            l = to_light * inversesqrt(d2);
            float cos_light = dot(en, -l);
            // Emitters emit from their front face only.
            if (cos_light <= 0.0 || dot(s.ng, l) <= 0.0) continue;
            // Radiance * area * cos / d^2 is the irradiance of this piece, over pi (scene::Light).
            e = emitter_emission(em, b) * (em.area / float(WHITTED_EMITTER_SAMPLES)) * cos_light / (PI * d2);
            // Shadow ray between the two offset points, so neither surface occludes itself.
            vec3 target = offset_ray(q, en, frame.scene_scale);
            span = target - origin;
            tmax = 1.0;
        }
        // Where finite, it ends at a point light or an emitter's point: points of the scene.
        if (occluded(origin, span, 0.0, tmax, !HAS_DIRECTIONAL || !isinf(tmax))) continue;
        result += blinn_phong(m, s, view, l, e);
    }
    return result;
}

struct Task {
    vec3 origin;
    vec3 dir;
    vec3 weight;
    uint depth;
};

vec3 whitted(vec3 origin, vec3 dir) {
    Task stack[WHITTED_STACK_SIZE];
    uint sp = 0u;
    stack[sp++] = Task(origin, dir, vec3(1.0), 0u);
    vec3 color = vec3(0.0);
    while (sp > 0u) {
        Task task = stack[--sp];
        Hit h = trace_closest(task.origin, task.dir, 0.0, 1.0 / 0.0);
        if (h.prim == PRIM_NONE) {
            if (env_present()) color += task.weight * env_radiance(task.dir);
            else if (HAS_SKY) color += task.weight * sky_radiance(task.dir);
            continue;
        }
        Surface s = surface_at(h, task.dir);
        GpuMaterial m = whitted_material(material_at(h, s));
        vec3 view = -task.dir;
        if (HAS_EMITTERS && s.front) color += task.weight * m.emission;
        color += task.weight * direct_light(m, s, view);
        // A path of max_depth rays ends here; the stack holds at most one task per level plus
        // one sibling, so max_depth < WHITTED_STACK_SIZE (clamped on the host) cannot overflow.
        if (task.depth + 1u >= frame.max_depth) continue;
        vec3 reflected = reflect(task.dir, s.ns);
        if (dot(reflected, s.ng) <= 0.0) reflected = reflect(task.dir, s.ng);
        if (HAS_DIELECTRIC && (m.flags & MATERIAL_DIELECTRIC) != 0u) {
            float eta = s.front ? 1.0 / m.ior : m.ior;
            float cos_i = dot(view, s.ns);
            float cos_t;
            float f = fresnel_dielectric(cos_i, eta, cos_t);
            vec3 refracted = eta * task.dir + (eta * cos_i - cos_t) * s.ns;
            stack[sp++] = Task(offset_ray(s.p, s.ng, frame.scene_scale), reflected, task.weight * f, task.depth + 1u);
            if (f < 1.0 && dot(refracted, s.ng) < 0.0) {
                stack[sp++] = Task(offset_ray(s.p, -s.ng, frame.scene_scale), normalize(refracted),
                                   task.weight * (1.0 - f), task.depth + 1u);
            }
        } else if ((HAS_MIRROR || HAS_METALLIC_ROUGHNESS) && (m.flags & MATERIAL_MIRROR) != 0u) {
            stack[sp++] = Task(offset_ray(s.p, s.ng, frame.scene_scale), reflected, task.weight * m.specular, task.depth + 1u);
        }
    }
    return color;
}

void main() {
    uvec2 pixel = tile_slot();
    if (pixel.x >= frame.width || pixel.y >= frame.height) return;
    uint index = pixel.y * frame.width + pixel.x;
    vec3 sum = vec3(0.0);
    float dropped = 0.0;
    for (uint k = 0u; k < push.sample_count; k++) {
        uint sample_index = push.sample_base + k;
        vec2 jitter = vec2(0.5);
        // One sample per pixel looks through the pixel's centre and the lens's centre (a thin
        // lens then renders as a pinhole); more jitter both.
        vec2 lens = vec2(0.5);
        if (push.total_spp > 1u) {
            Rng rng = rng_init(index, sample_index, frame.seed);
            jitter = vec2(rng_next(rng), rng_next(rng));
            if (camera_has_lens(frame)) lens = vec2(rng_next(rng), rng_next(rng));
        }
        vec3 origin = frame.cam_origin;
        vec3 dir;
        if (camera_has_lens(frame)) camera_lens_ray(frame, vec2(pixel) + jitter, lens, origin, dir);
        else dir = camera_ray_direction(frame, vec2(pixel) + jitter);
        vec3 c = whitted(origin, dir);
        // NaN and Inf never enter the accumulation buffer: count them instead.
        if (any(isnan(c)) || any(isinf(c))) dropped += 1.0;
        else sum += c;
    }
    accum[index] += vec4(sum, dropped);
}
