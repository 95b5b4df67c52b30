// The buffers the path tracer reads and writes besides the scene's.
#ifndef VKRT_PATH_BINDINGS_GLSL
#define VKRT_PATH_BINDINGS_GLSL

layout(std430, set = 0, binding = BINDING_LIGHT_PICKS) readonly buffer LightPicks { GpuLightPick light_picks[]; };
layout(std140, set = 0, binding = BINDING_PATH_PARAMS) uniform PathParams { GpuPathParams params; };
// rgb: radiance sum of the even-indexed samples; w unused.
layout(std430, set = 0, binding = BINDING_ACCUM_EVEN) buffer AccumEven { vec4 accum_even[]; };

#endif
