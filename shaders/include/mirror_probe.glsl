// The mirror probe: per pixel, which lobe the camera ray's first hit should favour when it is a
// mirror over a Lambert (or glossy) lobe, decided once per run by tracing the pixel centre's
// camera ray and its mirror reflection.
//
// Why: `lobes_of` picks a lobe by albedo, so a mirror of Ks 0.95 over Kd 0.01 (the Mirror Cornell
// box's tall box: Lambert albedo 5e-4) takes its Lambert lobe once in ~1900 samples. Where the
// mirror reflects the black outside of an open scene, the mirror lobe brings exactly nothing and
// all the pixel's light comes through the Lambert lobe: at 64-256 spp most pixels there never
// sample it and a few get a bright speck. relMSE (with its +0.01) hardly sees that region;
// HDR-FLIP does (docs/experiments/mirror-probe.md: FLIP -12 % / -17 % / -24 % at 16 / 64 / 256
// spp on that box, relMSE and time unchanged). Where
// the probe sees the reflection escape, the first hit takes the mirror lobe with probability
// MIRROR_PROBE_P_SPEC instead, so most samples go to the Lambert lobe.
//
// Unbiased: the lobe probability may be any function of the pixel (which fixes the camera ray's
// first hit up to its jitter) as long as every lobe that can contribute keeps a non-zero
// probability, and both the lobe choice and the light sample's MIS weight use the same one
// (`radiance` replaces `Lobes::p_spec` before either). The probe only decides how samples are
// spent: a sample whose jittered reflection does hit something takes the mirror with weight
// 1 / MIRROR_PROBE_P_SPEC. Deterministic, so resumed runs and shards recompute the same values.
//
// One pass per run (`GpuPush::probe`), not per sample: the same decision taken at every mirror
// hit inside the path loop (tried-and-not-kept.md, "A mirror's reflection traced first") cost
// 8-11 % of the render time on lavapipe, for a third walk inlined into the loop and a hit
// carried across iterations; two rays per pixel once per run are lost in the timing noise.
// Compiled only into the `path_mirrors` variant (MIRRORS, host/pipeline/variants.rs),
// which scenes with mirror materials use: the extra walk made lavapipe's pipeline creation
// ~16 ms longer for every scene (77 -> 93 ms median, cornell-measured), since SPIR-V is parsed
// whole before specialization constants can drop code.
#ifndef VKRT_MIRROR_PROBE_GLSL
#define VKRT_MIRROR_PROBE_GLSL

// The mirror lobe's probability where its reflection escapes: low enough that most samples
// take the Lambert lobe, high enough that samples whose jitter does see something in the
// mirror stay within a weight of 4 (0.03125 and 0.125 gave the same FLIP and relMSE).
const float MIRROR_PROBE_P_SPEC = 0.25;

// The value for `pixel`: MIRROR_PROBE_P_SPEC as float bits, or 0 (the material's own choice).
// `rays` counts the rays traced. The camera ray and the reflection share one walk call site
// (each call site is a whole inlined walk in the compiled shader).
uint mirror_probe_value(uvec2 pixel, inout uint rays) {
    // A sky or an environment map lights the escaping reflection. (A black sky is no sky: the
    // sky feature is off for one, and the all-features shader must choose as the specialised.)
    bool sky = HAS_SKY && (frame.sky_texture != TEXTURE_NONE || max3(frame.sky_color) > 0.0);
    if (!HAS_MIRROR || sky || env_present()) return 0u;
    vec3 origin = frame.cam_origin;
    vec3 dir = camera_ray_direction(frame, vec2(pixel) + 0.5);
    for (uint segment = 0u; segment < 2u; segment++) {
        rays++;
        Hit h = trace_closest(origin, dir, 0.0, 1.0 / 0.0);
        if (segment == 1u) return h.prim == PRIM_NONE ? floatBitsToUint(MIRROR_PROBE_P_SPEC) : 0u;
        if (h.prim == PRIM_NONE) return 0u;
        Surface s = surface_at(h, dir);
        GpuMaterial m = material_at(h, s);
        Lobes l = lobes_of(m);
        if (!l.mirror || l.p_spec <= MIRROR_PROBE_P_SPEC || l.p_spec >= 1.0) return 0u;
        Onb f = onb_from(s.ns);
        vec3 wo = to_local(f, -dir);
        dir = to_world(f, vec3(-wo.x, -wo.y, wo.z));
        // A reflection that crosses the geometric surface ends the path (`radiance`): nothing
        // comes through the mirror lobe there either.
        if (dot(dir, s.ng) < 0.0) return floatBitsToUint(MIRROR_PROBE_P_SPEC);
        origin = offset_ray(s.p, s.ng, frame.scene_scale);
    }
    return 0u;
}

#endif
