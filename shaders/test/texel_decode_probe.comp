#version 460
// Runs every texel-buffer decoder of the integrators (load_node in the layout's
// traverse_<id>.glsl; load_triangle in bvh_bindings.glsl; load_shading ... load_uv in
// scene_bindings.glsl, and load_tangents; load_light_pick in path_bindings.glsl) and writes each decoded struct to a std430 array of that struct, so
// tests/texel_decode.rs can check that the shaders read back, field for field, what the host
// uploaded. Invocation i decodes element i of every array that has one. The node decoder is
// the layout's (a LAYOUT_* define picks it, as in the integrators' variants; BVH_NODE names its
// struct, from the generated bvh_node.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

#include "bvh_node.glsl"
#include "scene_bindings.glsl"
#include "path_bindings.glsl"
#include "traverse.glsl"

// Workgroup size: spec constants set per device; ids only, no defaults (host/gpu/workgroups.rs).
layout(local_size_x_id = SPEC_WORKGROUP_1D) in;

layout(std430, set = 0, binding = BINDING_DECODE_OUT + 0) writeonly buffer OutNodes { BVH_NODE out_nodes[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 1) writeonly buffer OutTriangles { GpuTriangle out_triangles[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 2) writeonly buffer OutShading { GpuShading out_shading[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 3) writeonly buffer OutMaterials { GpuMaterial out_materials[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 4) writeonly buffer OutLights { GpuLight out_lights[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 5) writeonly buffer OutEmitters { GpuEmitter out_emitters[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 6) writeonly buffer OutTextures { GpuTexture out_textures[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 7) writeonly buffer OutTexels { uint out_texels[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 8) writeonly buffer OutUvs { GpuUv out_uvs[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT + 9) writeonly buffer OutLightPicks { GpuLightPick out_light_picks[]; };
layout(std430, set = 0, binding = BINDING_DECODE_OUT_TANGENTS) writeonly buffer OutTangents { GpuTangents out_tangents[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    // Elements in a view: its texels over the texels per struct.
    if (i < uint(textureSize(node_texels)) / BVH_NODE_TEXELS) out_nodes[i] = load_node(i);
    if (i < uint(textureSize(triangle_texels)) / 3u) out_triangles[i] = load_triangle(i);
    if (i < uint(textureSize(shading_texels)) / 3u) out_shading[i] = load_shading(i);
    if (i < uint(textureSize(material_texels)) / 6u) out_materials[i] = load_material(i);
    if (i < uint(textureSize(light_texels)) / 3u) out_lights[i] = load_light(i);
    if (i < uint(textureSize(emitter_texels)) / 4u) out_emitters[i] = load_emitter(i);
    if (i < uint(textureSize(texture_texels))) out_textures[i] = load_texture(i);
    if (i < uint(textureSize(atlas_texels))) out_texels[i] = load_atlas_texel(i);
    if (i < uint(textureSize(uv_texels)) / 2u) out_uvs[i] = load_uv(i);
    if (i < uint(textureSize(light_pick_texels))) out_light_picks[i] = load_light_pick(i);
    if (i < uint(textureSize(tangent_texels)) / 3u) out_tangents[i] = load_tangents(i);
}
