// Diffuse bounces aimed at caustic casters: light that a curved glossy, mirror or glass object
// throws onto diffuse surfaces (lamp -> ball -> wall) comes to a wall point x through a small
// spot of the object, which a cosine-sampled bounce rarely hits: rare, bright paths, the
// fireflies that were most of the Sphere Cornell box's error. Light sampling cannot aim
// through a curved object in closed form (manifold walks, Hanika et al. 2015), but the bounce
// can be drawn from a mixture that knows where the casters are (prepare/casters.rs):
//   p(w) = (1 - share) p_bsdf(w) + share p_guide(w),
//   p_guide = (1 - spot_share) uniform(cone of the caster's bounding sphere)
//             + spot_share uniform(cone around the caster's mirror spot),
// the spot being where a mirror ball of that sphere would reflect the lights' centre towards x
// (a few fixed-point steps on the half-vector condition), widened by the lights' size and the
// lobe's spread. A one-sample mixture (Veach 1997, thesis, 9.2.2): the bounce's weight and its
// MIS weights against light sampling use the mixture's density, so the estimate is unbiased
// whatever the proposal; a proposal that aims badly only costs variance. Which caster a vertex
// aims at is drawn once per vertex, before light sampling, and both strategies' weights use
// the density given that choice (unbiased for each choice). Vertices with a Lambert lobe only
// (a mirror or glass vertex has no use for it); scenes without casters never enter this
// (params.caster_count 0: the same samples and bytes as before), and the aiming code is compiled
// only into the `path_casters` and `path_mirrors_casters` variants (define CASTERS), which the
// host runs for scenes with casters: elsewhere it cost ~25 ms of lavapipe pipeline creation
// (SPIR-V is parsed before specialization). Measured:
// docs/experiments/caster-guiding.md.
#ifndef VKRT_CASTER_GUIDE_GLSL
#define VKRT_CASTER_GUIDE_GLSL

// The share of a diffuse vertex's bounces aimed at a caster, and of those the share aimed at
// the spot (balls lit by emissive triangles). Sphere box, 64 spp, seeds 1-3 (caster-guiding.md):
// share 0.15 / 0.2 / 0.3 with spot 0.5 gave relMSE 3.4 / 3.3 / 3.6e-5 at 1.15 / 1.2 / 1.23x the
// time of none (1.5e-4); spot 0.3 / 0.5 / 0.7 / 0.85 at share 0.15: 3.9 / 3.4 / 3.1 / 3.0e-5.
const float GUIDE_SHARE = 0.15;
const float SPOT_SHARE = 0.7;
// Fixed-point steps towards the mirror spot (each: the ball's normal to the half vector of
// the directions to x and to the lights' centre), and the spot cone's widest half-angle.
const uint SPOT_STEPS = 4u;
const float SPOT_MAX_ANGLE = 0.5;

struct Guide {
    // Probability that the bounce is drawn from the guide (0: not here).
    float share;
    vec3 cone_axis;
    // 1 - cos(half-angle), kept apart for tiny cones.
    float cone_omc;
    vec3 spot_axis;
    float spot_omc;
    // Probability, among the guide's draws, of the spot cone (0: whole cone only).
    float spot_share;
};

Guide guide_none() {
    Guide g;
    g.share = 0.0;
    g.cone_axis = vec3(0.0, 0.0, 1.0);
    g.cone_omc = 0.0;
    g.spot_axis = vec3(0.0, 0.0, 1.0);
    g.spot_omc = 0.0;
    g.spot_share = 0.0;
    return g;
}

// The guide at point x with lobes l: picks a caster (a sample dimension when there are
// several) and sets up its cones. Not at mirror or glass vertices, nor inside a caster's sphere.
#ifdef CASTERS
Guide guide_at(vec3 x, Lobes l, inout Sampler smp) {
    Guide g = guide_none();
    uint count = params.caster_count;
    if (count == 0u || l.mirror || l.dielectric || !(mean3(l.kd) > 0.0)) return g;
    uint k = count > 1u ? min(uint(sampler_1d(smp) * float(count)), count - 1u) : 0u;
    GpuCaster c = load_caster(k);
    vec3 d = c.center - x;
    float d2 = dot(d, d);
    float r2 = c.radius * c.radius;
    if (!(d2 > r2)) return g;
    float s2 = r2 / d2;
    // 1 - cos = sin^2 / (1 + cos), exact for the far, tiny cones where 1 - cos would cancel.
    g.cone_omc = s2 / (1.0 + sqrt(1.0 - s2));
    if (!(g.cone_omc > 0.0)) return g;
    g.cone_axis = d * inversesqrt(d2);
    g.share = GUIDE_SHARE;
    if (c.spot_spread < 0.0) return g;
    vec3 n = normalize(normalize(x - c.center) + normalize(c.target - c.center));
    for (uint i = 0u; i < SPOT_STEPS; i++) {
        vec3 sp = c.center + c.radius * n;
        n = normalize(normalize(x - sp) + normalize(c.target - sp));
    }
    vec3 sp = c.center + c.radius * n;
    // Normals that still reflect some of the lights towards x: half the lights' angular radius
    // seen from the spot, plus the lobe's spread; the spot they span, seen from x.
    float delta = 0.5 * c.target_radius / max(length(c.target - sp), 1e-6 * c.radius) + c.spot_spread;
    vec3 v = sp - x;
    float dist = length(v);
    float half_angle = min(c.radius * delta / dist, SPOT_MAX_ANGLE);
    float sh = sin(0.5 * half_angle);
    float omc = 2.0 * sh * sh;
    if (omc > 0.0 && dist > 0.0 && !any(isnan(v))) {
        g.spot_axis = v / dist;
        g.spot_omc = omc;
        g.spot_share = SPOT_SHARE;
    }
    return g;
}

#endif

// The guide's own density of world direction w (solid angle).
float guide_density(Guide g, vec3 w) {
    float p = 0.0;
    if (dot(w, g.cone_axis) >= 1.0 - g.cone_omc) p += (1.0 - g.spot_share) / (2.0 * PI * g.cone_omc);
    if (g.spot_share > 0.0 && dot(w, g.spot_axis) >= 1.0 - g.spot_omc) p += g.spot_share / (2.0 * PI * g.spot_omc);
    return p;
}

// The density of the whole bounce (BSDF sampling mixed with the guide) for world direction w
// whose BSDF-sampling density is bsdf_pdf.
float guide_mix(Guide g, float bsdf_pdf, vec3 w) {
    return g.share > 0.0 ? (1.0 - g.share) * bsdf_pdf + g.share * guide_density(g, w) : bsdf_pdf;
}

// A uniform direction in the cone around unit `axis` with 1 - cos(half-angle) = omc.
vec3 sample_in_cone(vec3 axis, float omc, vec2 u) {
    float t = u.x * omc;
    float ct = 1.0 - t;
    // sin^2 = (1 - cos)(1 + cos).
    float st = sqrt(max(0.0, t * (2.0 - t)));
    float phi = 2.0 * PI * u.y;
    return to_world(onb_from(axis), vec3(st * cos(phi), st * sin(phi), ct));
}

// bsdf_sample with the guide's share aimed: bs as bsdf_sample gives it (local frame f; density
// and weight the mixture's), wi the direction in world space.
bool guided_bsdf_sample(Guide g, Lobes l, Onb f, vec3 wo, bool front, float u_lobe, vec2 u, out BsdfSample bs, out vec3 wi) {
#ifdef CASTERS
    if (g.share > 0.0 && u_lobe < g.share) {
        float v = u_lobe / g.share;
        wi = v < g.spot_share ? sample_in_cone(g.spot_axis, g.spot_omc, u) : sample_in_cone(g.cone_axis, g.cone_omc, u);
        bs.wi = to_local(f, wi);
        bs.delta = false;
        bs.weight = vec3(0.0);
        bs.pdf = 0.0;
        if (bs.wi.z <= 0.0) return false;
        float pdf;
        vec3 fr = bsdf_eval(l, wo, bs.wi, pdf);
        bs.pdf = guide_mix(g, pdf, wi);
        if (!(bs.pdf > 0.0)) return false;
        bs.weight = fr * bs.wi.z / bs.pdf;
        return true;
    }
#endif
    if (g.share > 0.0) u_lobe = min((u_lobe - g.share) / (1.0 - g.share), ONE_MINUS_EPSILON);
    if (!bsdf_sample(l, wo, front, u_lobe, u, bs)) {
        wi = vec3(0.0);
        return false;
    }
    wi = to_world(f, bs.wi);
    if (g.share > 0.0 && !bs.delta) {
        float mixed = guide_mix(g, bs.pdf, wi);
        bs.weight *= bs.pdf / mixed;
        bs.pdf = mixed;
    }
    return true;
}

#endif
