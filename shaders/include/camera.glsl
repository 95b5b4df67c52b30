// The pinhole camera. CPU twin: CameraFrame::ray_direction (host/scene/camera.rs).
// (x, y) is an image position in pixels, (i + 0.5, j + 0.5) the centre of pixel (i, j); row 0 is the top.
#ifndef VKRT_CAMERA_GLSL
#define VKRT_CAMERA_GLSL
#include "gpu_abi.glsl"

vec3 camera_ray_direction(GpuFrame f, vec2 xy) {
    float ndc_x = (xy.x / float(f.width) * 2.0 - 1.0) * f.tan_half_fov_y * f.aspect;
    float ndc_y = (1.0 - xy.y / float(f.height) * 2.0) * f.tan_half_fov_y;
    return normalize(f.cam_forward + ndc_x * f.cam_right + ndc_y * f.cam_up);
}

#endif
