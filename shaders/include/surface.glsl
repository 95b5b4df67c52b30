// What a closest hit tells the shading code: position, normals, material.
#ifndef VKRT_SURFACE_GLSL
#define VKRT_SURFACE_GLSL
#include "scene_bindings.glsl"
#include "leaf.glsl"
#include "features.glsl"
#include "texture.glsl"

struct Surface {
    vec3 p;
    // Unit geometric normal, flipped to the side the ray came from.
    vec3 ng;
    // Unit shading normal (interpolated vertex normals) on the same side as ng.
    vec3 ns;
    // True if the ray hit the front (counter-clockwise) face.
    bool front;
    uint material;
};

Surface surface_at(Hit h, vec3 dir) {
    GpuTriangle tri = load_triangle(h.slot);
    GpuShading sh = load_shading(h.prim);
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
    return s;
}

// The material at a hit, its diffuse colour replaced by the texture's there if it has one.
GpuMaterial material_at(Hit h, Surface s) {
    GpuMaterial m = load_material(s.material);
    if (HAS_TEXTURES && m.diffuse_texture != TEXTURE_NONE) {
        m.diffuse = texture_uv(m.diffuse_texture, uv_at(h.prim, h.u, h.v), true).rgb;
    }
    return m;
}

#endif
