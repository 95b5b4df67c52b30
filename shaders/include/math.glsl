// Numbers the shaders share that are not host/shader constants (those are in the generated
// constants.glsl, from host/gpu_abi/constants.rs).
#ifndef VKRT_MATH_GLSL
#define VKRT_MATH_GLSL

const float PI = 3.14159265358979;

#endif
