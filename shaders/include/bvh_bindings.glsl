// The BVH buffers every tracing shader reads. Binding numbers come from constants.glsl.
#ifndef VKRT_BVH_BINDINGS_GLSL
#define VKRT_BVH_BINDINGS_GLSL
#include "constants.glsl"
#include "layout.glsl"

// The node type depends on the layout (see traverse.glsl); both are 32 bytes.
#if defined(LAYOUT_PARENT_LINK)
layout(std430, set = 0, binding = BINDING_NODES) readonly buffer Nodes { GpuParentNode nodes[]; };
#else
layout(std430, set = 0, binding = BINDING_NODES) readonly buffer Nodes { GpuNode nodes[]; };
#endif
layout(std430, set = 0, binding = BINDING_TRIANGLES) readonly buffer Triangles { GpuTriangle triangles[]; };

#endif
