// The scene buffers the integrators read besides the BVH.
#ifndef VKRT_SCENE_BINDINGS_GLSL
#define VKRT_SCENE_BINDINGS_GLSL
#include "bvh_bindings.glsl"

layout(std430, set = 0, binding = BINDING_SHADING) readonly buffer Shading { GpuShading shading[]; };
layout(std430, set = 0, binding = BINDING_MATERIALS) readonly buffer Materials { GpuMaterial materials[]; };
layout(std430, set = 0, binding = BINDING_LIGHTS) readonly buffer Lights { GpuLight lights[]; };
layout(std430, set = 0, binding = BINDING_EMITTERS) readonly buffer Emitters { GpuEmitter emitters[]; };
layout(std430, set = 0, binding = BINDING_TEXTURES) readonly buffer Textures { GpuTexture textures[]; };
layout(std430, set = 0, binding = BINDING_TEXELS) readonly buffer Texels { uint texels[]; };
layout(std430, set = 0, binding = BINDING_UVS) readonly buffer Uvs { GpuUv uvs[]; };
layout(std140, set = 0, binding = BINDING_FRAME) uniform Frame { GpuFrame frame; };

#endif
