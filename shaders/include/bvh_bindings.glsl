// The BVH buffers every tracing shader reads. Binding numbers come from constants.glsl.
#ifndef VKRT_BVH_BINDINGS_GLSL
#define VKRT_BVH_BINDINGS_GLSL
#include "constants.glsl"
#include "layout.glsl"

layout(std430, set = 0, binding = BINDING_NODES) readonly buffer Nodes { GpuNode nodes[]; };
layout(std430, set = 0, binding = BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };

#endif
