// What a closest hit tells the shading code: position, normals, material.
#ifndef VKRT_SURFACE_GLSL
#define VKRT_SURFACE_GLSL
#include "scene_bindings.glsl"
#include "leaf.glsl"
#include "features.glsl"
#include "texture.glsl"
#ifdef TWO_LEVEL
#include "instance.glsl"
#endif

struct Surface {
    vec3 p;
    // Unit geometric normal, flipped to the side the ray came from.
    vec3 ng;
    // Unit shading normal (interpolated vertex normals) on the same side as ng.
    vec3 ns;
    // True if the ray hit the front (counter-clockwise) face.
    bool front;
    uint material;
    // Unit direction back along the ray (toward the viewer): the normal map's rule needs it.
    vec3 view;
};

// The hit triangle's shading data in the world and in the world triangle's vertex order (that
// of the hit's barycentrics): a two-level BVH's mesh entry (prepare::mesh_shading) turned out
// by the hit instance.
GpuShading shading_at(Hit h) {
    GpuShading sh = load_shading(h.shading);
#ifdef TWO_LEVEL
    GpuInstance inst = load_instance(h.instance);
    vec3 n1 = normal_to_world(inst, sh.n1);
    vec3 n2 = normal_to_world(inst, sh.n2);
    sh.n0 = normal_to_world(inst, sh.n0);
    sh.n1 = h.mirrored ? n2 : n1;
    sh.n2 = h.mirrored ? n1 : n2;
#endif
    return sh;
}

// The same for the vertex tangents: turned by the placement's linear part, the bitangent's
// handedness flipped by a mirror (as the glTF loader places them).
GpuTangents tangents_at(Hit h) {
    GpuTangents tg = load_tangents(h.shading);
#ifdef TWO_LEVEL
    GpuInstance inst = load_instance(h.instance);
    float w = h.mirrored ? -1.0 : 1.0;
    vec4 t0 = vec4(normalize_or_zero(transform_dir(inst.object_to_world, tg.t0.xyz)), w * tg.t0.w);
    vec4 t1 = vec4(normalize_or_zero(transform_dir(inst.object_to_world, tg.t1.xyz)), w * tg.t1.w);
    vec4 t2 = vec4(normalize_or_zero(transform_dir(inst.object_to_world, tg.t2.xyz)), w * tg.t2.w);
    tg.t0 = t0;
    tg.t1 = h.mirrored ? t2 : t1;
    tg.t2 = h.mirrored ? t1 : t2;
#endif
    return tg;
}

// Texture coordinates at the hit: a two-level BVH's mesh entry is in the mesh's vertex order.
vec2 hit_uv(Hit h) {
#ifdef TWO_LEVEL
    if (h.mirrored) return uv_at(h.shading, h.v, h.u);
#endif
    return uv_at(h.shading, h.u, h.v);
}

Surface surface_at(Hit h, vec3 dir) {
    GpuTriangle tri = load_triangle(h.slot);
#ifdef TWO_LEVEL
    // The instance's copy of the triangle, in the world and in the order of the vertices the
    // loader placed (a mirror swaps the second and third, as the hit's barycentrics are):
    // the expanded scene's triangle, to rounding (to the bit under a translation).
    GpuInstance inst = load_instance(h.instance);
    vec3 v1 = transform_point(inst.object_to_world, tri.v1);
    vec3 v2 = transform_point(inst.object_to_world, tri.v2);
    bool mirrored = (inst.flags & INSTANCE_MIRRORED) != 0u;
    tri.v0 = transform_point(inst.object_to_world, tri.v0);
    tri.v1 = mirrored ? v2 : v1;
    tri.v2 = mirrored ? v1 : v2;
#endif
    GpuShading sh = shading_at(h);
    Surface s;
    float w = 1.0 - h.u - h.v;
    // The barycentric point is on the triangle's plane to float precision, unlike origin + t*dir,
    // whose error grows with t; offset_ray() then needs only a few ulps.
    s.p = w * tri.v0 + h.u * tri.v1 + h.v * tri.v2;
    vec3 ng = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    s.front = dot(ng, dir) < 0.0;
    s.ng = s.front ? ng : -ng;
    vec3 ns = w * sh.n0 + h.u * sh.n1 + h.v * sh.n2;
    float len = length(ns);
    ns = (len > 0.0 && !isnan(len) && !isinf(len)) ? ns / len : s.ng;
    // Vertex normals of the back side point away from the viewer: flip them with the face.
    s.ns = dot(ns, s.ng) < 0.0 ? -ns : ns;
    s.material = sh.material;
    s.view = -normalize(dir);
    return s;
}

// The shading normal at hit h from the material's tangent-space normal map: the texel
// (2 c - 1) * (scale, scale, 1) in the frame (T, B, N) of the interpolated vertex normal N, the
// vertex tangent T made orthogonal to it and B = w cross(N, T) (glTF 2.0 specification,
// normalTexture; MikkTSpace's convention, host/scene/tangents.rs). Where the triangle has no
// tangent (zero), the interpolated normal stays.
//
// The rule that keeps light from leaking through the surface: the mapped normal, turned to the
// side of the face the ray is on, is bent back toward the geometric normal ng until it is at
// least NORMAL_MAP_MIN_COS above the geometric surface, and then toward the viewer until the
// viewer is at least as far above its tangent plane (bending toward the viewer, who is on
// ng's side, only raises the normal further above the surface). So wo.z > 0 in the shading
// frame, no sample is lost to a normal facing away, and the path tracer's rejection of
// reflections that cross the geometric surface (path.comp) and of lights behind it
// (next_event) does the rest: light arrives and leaves on the side the ray came from only.
// This is the simple end of what pbrt-v4 (NormalMap, then FaceForward) and Schüßler et al.
// 2017 ("Microfacet-based normal mapping for robust Monte Carlo path tracing") do; it does not
// restore the energy a tilted normal loses or gains.
const float NORMAL_MAP_MIN_COS = 0.01;

vec3 bend_above(vec3 n, vec3 axis) {
    float c = dot(n, axis);
    return c >= NORMAL_MAP_MIN_COS ? n : normalize(n + (NORMAL_MAP_MIN_COS - c) * axis);
}

vec3 normal_mapped(Hit h, Surface s, GpuMaterial m, vec2 uv) {
    GpuShading sh = shading_at(h);
    GpuTangents tg = tangents_at(h);
    float w = 1.0 - h.u - h.v;
    vec4 t4 = w * tg.t0 + h.u * tg.t1 + h.v * tg.t2;
    vec3 n = w * sh.n0 + h.u * sh.n1 + h.v * sh.n2;
    float nlen = length(n);
    // The file's side of the surface: the vertex normal as interpolated, else the front face's.
    n = nlen > 0.0 ? n / nlen : (s.front ? s.ng : -s.ng);
    vec3 t = t4.xyz - n * dot(n, t4.xyz);
    float tlen = length(t);
    if (!(tlen > 1e-8)) return s.ns;
    t /= tlen;
    vec3 b = (t4.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    vec3 c = texture_uv(m.normal_texture, uv, false).xyz * 2.0 - 1.0;
    c.xy *= m.normal_scale;
    vec3 mapped = c.x * t + c.y * b + c.z * n;
    float len = length(mapped);
    if (!(len > 0.0) || isinf(len)) return s.ns;
    mapped /= len;
    // Turned with the face, like the vertex normals (surface_at).
    if (!s.front) mapped = -mapped;
    return bend_above(bend_above(mapped, s.ng), s.view);
}

// The material at a hit with its textures applied: the diffuse (base) colour texture replaces
// Kd for MTL and lab materials (the lab renderer's rule) and multiplies the base colour factor
// for glTF metallic-roughness ones (glTF 2.0 specification, section 3.9.2); the
// metallic-roughness texture's blue channel scales metallic and its green roughness; the
// emission texture multiplies the emission. A normal map replaces s.ns (normal_mapped).
GpuMaterial material_at(Hit h, inout Surface s) {
    GpuMaterial m = load_material(s.material);
    // A block on the constant, not an early return: lavapipe drops an untaken block as it
    // translates, but translates an early return's dead remainder into every inlined copy
    // first (pipeline-creation-time.md).
    if (HAS_TEXTURES) {
        bool mr = HAS_METALLIC_ROUGHNESS && (m.flags & MATERIAL_METALLIC_ROUGHNESS) != 0u;
        if (m.diffuse_texture != TEXTURE_NONE) {
            vec3 c = texture_uv(m.diffuse_texture, hit_uv(h), true).rgb;
            m.diffuse = mr ? m.diffuse * c : c;
        }
        if (mr && m.metallic_roughness_texture != TEXTURE_NONE) {
            vec4 c = texture_uv(m.metallic_roughness_texture, hit_uv(h), false);
            m.metallic *= c.b;
            m.roughness *= c.g;
        }
        if (m.emission_texture != TEXTURE_NONE) {
            m.emission *= texture_uv(m.emission_texture, hit_uv(h), true).rgb;
        }
        if (HAS_NORMAL_MAP && (m.flags & MATERIAL_NORMAL_MAP) != 0u) {
            s.ns = normal_mapped(h, s, m, hit_uv(h));
        }
    }
    return m;
}

#endif
