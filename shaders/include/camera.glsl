// The camera: a pinhole, or a thin lens (PBRT 4th ed., section 5.2.3) when frame.aperture_radius
// is above 0. CPU twin: CameraFrame::ray_direction and CameraFrame::ray (host/scene/camera.rs).
// (x, y) is an image position in pixels, (i + 0.5, j + 0.5) the centre of pixel (i, j); row 0 is the top.
#ifndef VKRT_CAMERA_GLSL
#define VKRT_CAMERA_GLSL
#include "gpu_abi.glsl"
#include "sampling.glsl"

vec3 camera_ray_direction(GpuFrame f, vec2 xy) {
    float ndc_x = (xy.x / float(f.width) * 2.0 - 1.0) * f.tan_half_fov_y * f.aspect;
    float ndc_y = (1.0 - xy.y / float(f.height) * 2.0) * f.tan_half_fov_y;
    return normalize(f.cam_forward + ndc_x * f.cam_right + ndc_y * f.cam_up);
}

bool camera_has_lens(GpuFrame f) {
    return f.aperture_radius > 0.0;
}

// The thin-lens ray through image position xy from lens sample u in [0, 1)^2: it starts on the
// aperture disc and passes through the point where the pinhole ray meets the plane of focus
// (focus_distance along cam_forward), so that plane is sharp and everything else blurs.
// Callers draw u and call this only when camera_has_lens: a pinhole camera consumes no
// sample dimensions and renders exactly as before the lens existed.
void camera_lens_ray(GpuFrame f, vec2 xy, vec2 u, out vec3 origin, out vec3 dir) {
    vec3 d = camera_ray_direction(f, xy);
    vec3 focus = f.cam_origin + d * (f.focus_distance / dot(d, f.cam_forward));
    vec2 disc = concentric_disk(u) * f.aperture_radius;
    origin = f.cam_origin + disc.x * f.cam_right + disc.y * f.cam_up;
    dir = normalize(focus - origin);
}

#endif
