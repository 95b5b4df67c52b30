// Next-event estimation through planar mirrors: light that reaches a surface point by way of a
// flat mirror (lamp -> mirror -> point: a caustic on the walls around a mirror) is sampled by
// aiming at the lamp's image in the mirror, not left to BSDF sampling to find.
//
// The light a point x sees in a flat mirror is the light its mirror image x' (x reflected in
// the mirror's plane) sees directly: a light sample taken from x' gives the path x -> m -> y
// (m where the segment x'y crosses the plane) with the same solid-angle density at x, the same
// length and the same cosine at y. The sample counts if m lies on the mirror triangle and both
// segments are clear; it carries the mirror's Ks (no lobe choice: the path takes the mirror).
// The planar case of manifold next-event estimation (Hanika, Droske & Fascione 2015,
// "Manifold next event estimation"); prepare/mirrors.rs says which triangles qualify.
//
// The mirrors come in planes (one plane and material each, prepare/mirrors.rs): a plane is
// picked uniformly and the aimed-at point m counts if any of its triangles holds it, so
// overlapping or repeated triangles do not make a path likelier than the weights say.
//
// MIS: the same path can come from BSDF sampling at x (density p_bsdf(x) times the mirror
// lobe's probability p_spec at m) and from this estimator (1/mirror_count for the plane
// times the light sample's density): both sides weigh it by the power heuristic of those two
// (`radiance` on the BSDF side, where a path reaches an emitter right after a planar mirror
// that a non-delta bounce led to). Point, spot, cone and directional lights are aimed at too,
// with weight 1: no other estimator reaches a delta light by way of a delta mirror, so without
// this they would light nothing through mirrors (tests/mirrors.rs checks the analytic values;
// a directional light is aimed at along its direction from the image). The environment is left
// to BSDF sampling, which reaches it past a mirror. The path takes two more segments: `radiance`
// aims only where max_depth allows them. Measured: docs/experiments/mirror-light.md.
#ifndef VKRT_MIRROR_LIGHT_GLSL
#define VKRT_MIRROR_LIGHT_GLSL

// A point closer than this (times the scene's scale) to a mirror's plane does not aim through
// it: the mirror's own points (a mirror's Lambert lobe) and points on a coplanar floor would
// see themselves as their image, and float error would let the two shadow rays slip through
// the mirror (a spurious copy of the direct light). BSDF sampling cannot reach the mirror from
// its own plane either, so the two strategies still agree.
const float MIRROR_PLANE_MARGIN = 1e-4;

// True if m (on the plane of mr) lies on the triangle: the same side of all three edges.
// (A triangle of the plane lies in it to float precision: PLANE_TOLERANCE, prepare/mirrors.rs.)
bool on_mirror(vec3 m, GpuMirror mr) {
    vec3 n = cross(mr.v1 - mr.v0, mr.v2 - mr.v0);
    return dot(cross(mr.v1 - mr.v0, m - mr.v0), n) >= 0.0 && dot(cross(mr.v2 - mr.v1, m - mr.v1), n) >= 0.0
        && dot(cross(mr.v0 - mr.v2, m - mr.v2), n) >= 0.0;
}

// The light one uniformly picked mirror plane brings to surface s (lobes l, frame f, outgoing
// wo, bounce guide g, shadow rays from `origin`); `rays` counts the shadow rays traced.
vec3 light_through_mirror(Surface s, Lobes l, Onb f, vec3 wo, Guide g, vec3 origin, inout Sampler smp, inout uint rays) {
    uint count = params.mirror_count;
    float u_pick = sampler_1d(smp);
    vec2 u = sampler_2d(smp);
    GpuMirrorPlane plane = load_mirror_plane(min(uint(u_pick * float(count)), count - 1u));
    // The plane is its first triangle's.
    GpuMirror mr = load_mirror(plane.first);
    vec3 n = cross(mr.v1 - mr.v0, mr.v2 - mr.v0);
    float area2 = length(n);
    if (!(area2 > 0.0)) return vec3(0.0);
    n /= area2;
    // Work on the side of the plane that x is on.
    float dx = dot(s.p - mr.v0, n);
    if (dx < 0.0) {
        n = -n;
        dx = -dx;
    }
    if (!(dx > MIRROR_PLANE_MARGIN * frame.scene_scale)) return vec3(0.0);
    vec3 image = s.p - 2.0 * dx * n;
    LightSample ls;
    if (!sample_light(image, image, u, ls)) return vec3(0.0);
    // A directional light (delta, pdf 0) is at infinity along ls.wi; the environment (pdf > 0)
    // is left to BSDF sampling, which reaches it past the mirror.
    bool distant = isinf(ls.span_tmax);
    if (distant && ls.pdf > 0.0) return vec3(0.0);
    // The sampled point on the light (or the light's direction): on x's side of the mirror.
    vec3 y = distant ? vec3(0.0) : image + ls.span * ls.span_tmax;
    if ((distant ? dot(ls.wi, n) : dot(y - mr.v0, n)) <= 0.0) return vec3(0.0);
    // The direction from x to the mirror: the image ray reflected in the plane.
    vec3 dir = reflect(ls.wi, n);
    float dn = dot(dir, n);
    if (!(dn < 0.0)) return vec3(0.0);
    vec3 m = s.p + (dx / -dn) * dir;
    bool on = false;
    for (uint i = 0u; i < plane.count && !on; i++) on = on_mirror(m, i == 0u ? mr : load_mirror(plane.first + i));
    if (!on) return vec3(0.0);
    // Lambert and glossy reflect only: the mirror must be on the side the ray came from.
    if (dot(dir, s.ng) <= 0.0) return vec3(0.0);
    vec3 wi = to_local(f, dir);
    float bsdf_pdf;
    vec3 fr = bsdf_eval(l, wo, wi, bsdf_pdf);
    if (all(equal(fr, vec3(0.0)))) return vec3(0.0);
    // BSDF sampling's density, with the share aimed at casters (caster_guide.glsl).
    bsdf_pdf = guide_mix(g, bsdf_pdf, dir);
    Lobes ml = lobes_of(load_material(mr.material));
    vec3 m_off = offset_ray(m, n, frame.scene_scale);
    // The two shadow segments, x to the mirror point and on to the light, through one call
    // site: each `occluded` call is a whole inlined walk in the compiled shader, and lavapipe's
    // pipeline creation grows with every copy. The loop is kept rolled for the same reason.
    [[dont_unroll]] for (uint segment = 0u; segment < 2u; segment++) {
        bool first = segment == 0u;
        vec3 from = first ? origin : m_off;
        vec3 span = first ? m_off - origin : (distant ? ls.wi : y - m_off);
        float reach = first || !distant ? 1.0 : 1.0 / 0.0;
        rays++;
        // The first ends on the mirror; the second where the light sample's ray would.
        if (occluded(from, span, 0.0, reach, first || ends_in_scene(ls))) return vec3(0.0);
    }
    float pick = 1.0 / float(count);
    // BSDF sampling cannot reach a delta light (pdf 0) by way of a delta mirror: weight 1.
    float w = ls.pdf > 0.0 ? power_heuristic(pick * ls.pdf, bsdf_pdf * ml.p_spec) : 1.0;
    return fr * wi.z * ml.ks * ls.li_over_pdf * (w / pick);
}

#endif
