// The path tracer's materials, in the local shading frame (+z = shading normal on the side the
// ray came from, wo.z > 0). Lobes, from the MTL fields (scene::Material):
// - Lambert: Kd / pi, reflecting on both sides of the surface (the side the ray is on).
// - glossy (Ks > 0 on a material that is neither mirror nor dielectric): a GGX microfacet lobe
//   (Walter et al. 2007) with roughness alpha = sqrt(2 / (Ns + 2)) (their Blinn-Phong to
//   Beckmann mapping), Smith height-correlated shadowing, sampled by visible normals
//   (Heitz 2018, "Sampling the GGX distribution of visible normals", JCGT 7(4)).
// - mirror (illum 3, 5): a perfect reflection weighted by Ks.
// - dielectric (illum 4, 6, 7, 9): a smooth interface of index Ni, reflecting with the Fresnel
//   reflectance and refracting otherwise; untinted.
// - metallic-roughness (glTF 2.0 materials, MATERIAL_METALLIC_ROUGHNESS): the specification's
//   Appendix B, mix(dielectric_brdf, metal_brdf, metallic), with
//     metal_brdf      = GGX specular * Schlick Fresnel with f0 = base colour,
//     dielectric_brdf = fresnel_mix(ior 1.5: f0 = 0.04, Lambert(base colour), GGX specular),
//   i.e. f = (1 - metallic) (1 - F(0.04)) base / pi + F(mix(0.04, base, metallic)) D G2 /
//   (4 |n.wo| |n.wi|), Schlick's F (Schlick 1994) at wo.h = wi.h, so f is reciprocal. GGX
//   alpha = roughness^2 (at least MR_MIN_ALPHA), Smith height-correlated G2 and visible-normal
//   sampling as for the glossy lobe. The lobe is chosen by an estimate of its weight (Schlick
//   at wo.z, mr_spec_prob), and the density is the exact mixture of both lobes' densities.
//   Energy: the metal lobe loses, never gains (GGX with Smith shadowing); the dielectric's
//   fresnel_mix, as the specification defines it, is not energy conserving near grazing views
//   of smooth surfaces (the Lambert term is weighted by 1 - F at wo.h, not by what the
//   specular lobe reflects): tests/bsdf.rs states the albedo it measures.
// Energy: the specular lobe takes Ks and the Lambert lobe Kd * (1 - max(Ks)), so the albedo
// never exceeds 1; GGX with Smith shadowing loses, never gains, energy.
// Lobes the scene lacks are compiled out by the HAS_* specialization constants (features.glsl).
#ifndef VKRT_BSDF_GLSL
#define VKRT_BSDF_GLSL
#include "constants.glsl"
#include "features.glsl"
#include "fresnel.glsl"
#include "gpu_abi.glsl"
#include "math.glsl"
#include "sampling.glsl"

struct Lobes {
    vec3 kd;
    vec3 ks;
    float alpha;
    // Probability of sampling the specular (glossy or mirror) lobe instead of Lambert.
    float p_spec;
    bool mirror;
    bool dielectric;
    float ior;
    // Metallic-roughness: kd is then (1 - metallic) base colour, ks the Fresnel f0
    // mix(0.04, base, metallic).
    bool mr;
};

// GGX alpha of a metallic-roughness material with roughness 0: a near-mirror that the float
// arithmetic of D and of the visible-normal sampling still handles (D's peak is 1 / (pi a^2)).
const float MR_MIN_ALPHA = 1e-3;
// f0 of glTF's dielectric (ior 1.5): ((1.5 - 1) / (1.5 + 1))^2.
const float MR_DIELECTRIC_F0 = 0.04;

Lobes lobes_of(GpuMaterial m) {
    Lobes l;
    l.mr = HAS_METALLIC_ROUGHNESS && (m.flags & MATERIAL_METALLIC_ROUGHNESS) != 0u;
    if (l.mr) {
        vec3 base = clamp(m.diffuse, 0.0, 1.0);
        float metallic = clamp(m.metallic, 0.0, 1.0);
        float r = clamp(m.roughness, 0.0, 1.0);
        l.dielectric = false;
        l.mirror = false;
        l.ior = 1.5;
        l.kd = (1.0 - metallic) * base;
        l.ks = mix(vec3(MR_DIELECTRIC_F0), base, metallic);
        l.alpha = max(r * r, MR_MIN_ALPHA);
        // Depends on wo: mr_spec_prob.
        l.p_spec = 0.0;
        return l;
    }
    l.dielectric = HAS_DIELECTRIC && (m.flags & MATERIAL_DIELECTRIC) != 0u;
    l.mirror = HAS_MIRROR && !l.dielectric && (m.flags & MATERIAL_MIRROR) != 0u;
    l.ior = m.ior;
    l.ks = (l.dielectric || !HAS_GLOSSY) ? vec3(0.0) : clamp(m.specular, 0.0, 1.0);
    l.kd = l.dielectric ? vec3(0.0) : clamp(m.diffuse, 0.0, 1.0) * (1.0 - max3(l.ks));
    float ws = mean3(l.ks);
    float wd = mean3(l.kd);
    l.p_spec = HAS_GLOSSY && ws + wd > 0.0 ? ws / (ws + wd) : 0.0;
    l.alpha = clamp(sqrt(2.0 / (max(m.shininess, 0.0) + 2.0)), 1e-3, 1.0);
    return l;
}

// True if some lobe is not a Dirac delta, so that light sampling can help.
bool has_smooth_lobes(Lobes l) {
    // Schlick's grazing term reflects even with a black base colour.
    if (HAS_METALLIC_ROUGHNESS && l.mr) return true;
    return !l.dielectric && (l.p_spec < 1.0 || !l.mirror) && (mean3(l.kd) + mean3(l.ks) > 0.0);
}

float ggx_d(vec3 h, float a) {
    float a2 = a * a;
    float d = h.z * h.z * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's Lambda for GGX (Heitz 2014, "Understanding the masking-shadowing function", eq. 72).
float ggx_lambda(vec3 w, float a) {
    float c2 = w.z * w.z;
    float t2 = max(0.0, 1.0 - c2) / max(c2, 1e-12);
    return 0.5 * (sqrt(1.0 + a * a * t2) - 1.0);
}

// Density of wi when h is drawn from the visible normals seen from wo: D_wo(h) / (4 wo.h)
// with D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z (Heitz 2018, eq. 3 and 17).
float ggx_pdf(vec3 wo, vec3 h, float a) {
    return ggx_d(h, a) / ((1.0 + ggx_lambda(wo, a)) * 4.0 * wo.z);
}

float pow5(float x) {
    float x2 = x * x;
    return x2 * x2 * x;
}

// Probability of sampling the metallic-roughness material's specular lobe at wo: the lobes'
// weights estimated by Schlick's Fresnel at wo.z (the specular lobe reflects about F, the
// Lambert one about (1 - F(0.04)) (1 - metallic) base).
float mr_spec_prob(Lobes l, vec3 wo) {
    float s = pow5(1.0 - clamp(wo.z, 0.0, 1.0));
    float ws = mean3(l.ks + (1.0 - l.ks) * s);
    float wd = mean3(l.kd) * (1.0 - (MR_DIELECTRIC_F0 + (1.0 - MR_DIELECTRIC_F0) * s));
    return ws + wd > 0.0 ? ws / (ws + wd) : 1.0;
}

// f and the mixture density of the metallic-roughness material, for wo.z > 0 and wi.z > 0.
vec3 mr_eval(Lobes l, vec3 wo, vec3 wi, out float pdf) {
    vec3 h = normalize(wo + wi);
    float s = pow5(1.0 - clamp(dot(wo, h), 0.0, 1.0));
    vec3 f_spec = l.ks + (1.0 - l.ks) * s;
    float f_diel = MR_DIELECTRIC_F0 + (1.0 - MR_DIELECTRIC_F0) * s;
    float g2 = 1.0 / (1.0 + ggx_lambda(wo, l.alpha) + ggx_lambda(wi, l.alpha));
    float d = ggx_d(h, l.alpha);
    float p_spec = mr_spec_prob(l, wo);
    pdf = (1.0 - p_spec) * wi.z / PI + p_spec * ggx_pdf(wo, h, l.alpha);
    return (1.0 - f_diel) * l.kd / PI + f_spec * (d * g2 / (4.0 * wo.z * wi.z));
}

// f(wo, wi) and its sampling density (solid angle) over the non-delta lobes, for wo.z > 0.
vec3 bsdf_eval(Lobes l, vec3 wo, vec3 wi, out float pdf) {
    pdf = 0.0;
    if (l.dielectric || wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    if (HAS_METALLIC_ROUGHNESS && l.mr) return mr_eval(l, wo, wi, pdf);
    vec3 f = l.kd / PI;
    pdf = (1.0 - l.p_spec) * wi.z / PI;
    if (HAS_GLOSSY && !l.mirror && l.p_spec > 0.0) {
        vec3 h = normalize(wo + wi);
        float g2 = 1.0 / (1.0 + ggx_lambda(wo, l.alpha) + ggx_lambda(wi, l.alpha));
        f += l.ks * ggx_d(h, l.alpha) * g2 / (4.0 * wo.z * wi.z);
        pdf += l.p_spec * ggx_pdf(wo, h, l.alpha);
    }
    return f;
}

// A visible normal of GGX seen from wo (Heitz 2018, listing 1, isotropic).
vec3 sample_ggx_visible_normal(vec3 wo, float a, vec2 u) {
    vec3 vh = normalize(vec3(a * wo.x, a * wo.y, wo.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u.x);
    float phi = 2.0 * PI * u.y;
    float p1 = r * cos(phi);
    float p2 = r * sin(phi);
    float s = 0.5 * (1.0 + vh.z);
    p2 = (1.0 - s) * sqrt(max(0.0, 1.0 - p1 * p1)) + s * p2;
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    return normalize(vec3(a * nh.x, a * nh.y, max(1e-6, nh.z)));
}

struct BsdfSample {
    vec3 wi;
    // f cos / pdf: what the path throughput is multiplied by.
    vec3 weight;
    // Solid-angle density of wi over the non-delta lobes (0 for a delta lobe).
    float pdf;
    bool delta;
};

// Draws wi from the metallic-roughness mixture: the specular lobe by visible normals, else
// Lambert; the density is the whole mixture's (mr_eval), so MIS with light sampling sees the
// same density for a direction however it was drawn.
bool mr_sample(Lobes l, vec3 wo, float u_lobe, vec2 u, out BsdfSample bs) {
    bs.delta = false;
    if (u_lobe < mr_spec_prob(l, wo)) {
        bs.wi = reflect(-wo, sample_ggx_visible_normal(wo, l.alpha, u));
    } else {
        bs.wi = sample_cosine_hemisphere(u);
    }
    if (bs.wi.z <= 0.0) return false;
    vec3 f = mr_eval(l, wo, bs.wi, bs.pdf);
    if (!(bs.pdf > 0.0)) return false;
    bs.weight = f * bs.wi.z / bs.pdf;
    return true;
}

// Draws wi for wo (wo.z > 0). `front`: wo is on the front (outside) side, for dielectrics.
// Returns false when the sample carries no energy.
bool bsdf_sample(Lobes l, vec3 wo, bool front, float u_lobe, vec2 u, out BsdfSample bs) {
    bs.wi = vec3(0.0, 0.0, 1.0);
    bs.weight = vec3(0.0);
    bs.pdf = 0.0;
    bs.delta = true;
    if (wo.z <= 0.0) return false;
    if (HAS_METALLIC_ROUGHNESS && l.mr) return mr_sample(l, wo, u_lobe, u, bs);
    if (HAS_DIELECTRIC && l.dielectric) {
        float eta = front ? 1.0 / l.ior : l.ior;
        float cos_t;
        float f = fresnel_dielectric(wo.z, eta, cos_t);
        if (u_lobe < f) {
            bs.wi = vec3(-wo.x, -wo.y, wo.z);
            bs.weight = vec3(1.0);
        } else {
            bs.wi = normalize(vec3(-eta * wo.x, -eta * wo.y, -cos_t));
            // Radiance is compressed by (n_t / n_i)^2 when it crosses into the denser side
            // (Veach 1997, section 5.2): the camera-side estimate scales by eta^2.
            bs.weight = vec3(eta * eta);
        }
        return true;
    }
    bool spec = HAS_GLOSSY && u_lobe < l.p_spec;
    if (HAS_MIRROR && spec && l.mirror) {
        bs.wi = vec3(-wo.x, -wo.y, wo.z);
        bs.weight = l.ks / l.p_spec;
        return true;
    }
    bs.delta = false;
    float lobe_pdf;
    if (spec) {
        vec3 h = sample_ggx_visible_normal(wo, l.alpha, u);
        bs.wi = reflect(-wo, h);
        lobe_pdf = l.p_spec * ggx_pdf(wo, h, l.alpha);
    } else {
        bs.wi = sample_cosine_hemisphere(u);
        lobe_pdf = (1.0 - l.p_spec) * bs.wi.z / PI;
    }
    if (bs.wi.z <= 0.0 || lobe_pdf <= 0.0) return false;
    // The mixture's density: this lobe's, from how wi was drawn, plus the other lobe's.
    // tests/bsdf.rs checks it against bsdf_eval's, computed from wi alone.
    float other = spec ? (1.0 - l.p_spec) * bs.wi.z / PI
                       : (HAS_GLOSSY && !l.mirror && l.p_spec > 0.0 ? l.p_spec * ggx_pdf(wo, normalize(wo + bs.wi), l.alpha) : 0.0);
    bs.pdf = lobe_pdf + other;
    float pdf_eval;
    vec3 f = bsdf_eval(l, wo, bs.wi, pdf_eval);
    if (bs.pdf <= 0.0) return false;
    bs.weight = f * bs.wi.z / bs.pdf;
    return true;
}

#endif
