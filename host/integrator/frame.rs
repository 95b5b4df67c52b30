//! The per-render uniform every integrator shader reads (`GpuFrame`), and the bindings every
//! integrator shader has.

use super::RenderSettings;
use crate::gpu_abi::constants::*;
use crate::gpu_abi::GpuFrame;
use crate::pipeline::BindingKind;
use crate::prepare::GpuScene;
use anyhow::Result;

/// The frame uniform for `scene` under `settings`. `max_depth` is stored as given: each
/// integrator checks it against what its shader supports.
pub fn frame_for(scene: &GpuScene, settings: &RenderSettings) -> Result<GpuFrame> {
    let info = &scene.info;
    let cam = info.camera()?;
    Ok(GpuFrame {
        cam_origin: cam.origin.to_array(),
        tan_half_fov_y: cam.tan_half_fov_y,
        cam_forward: cam.forward.to_array(),
        aspect: settings.width as f32 / settings.height as f32,
        cam_right: cam.right.to_array(),
        width: settings.width,
        cam_up: cam.up.to_array(),
        height: settings.height,
        // Whitted's ambient term, with an environment map's mean radiance in it (unshadowed:
        // what a Lambert surface under a uniform sky of that radiance reflects, times Kd). The
        // path tracer never reads it.
        ambient: scene.ambient.to_array(),
        max_depth: settings.max_depth,
        light_count: scene.light_count,
        emitter_count: scene.emitter_count,
        seed: settings.seed,
        scene_scale: info.scale,
        sky_color: info.sky_color,
        sky_texture: info.sky_texture,
        aperture_radius: cam.aperture_radius,
        focus_distance: cam.focus_distance,
        env_width: scene.env.width,
        env_height: scene.env.height,
        env_rotation_cos: scene.env.rotation_cos,
        env_rotation_sin: scene.env.rotation_sin,
        env_pick_pmf: scene.env_pick_pmf,
        env_compensation: scene.env.compensation,
    })
}

/// The bindings every integrator shader uses: the scene's arrays are texel buffers
/// ([`GpuScene::bind`]).
pub const INTEGRATOR_BINDINGS: &[(u32, BindingKind)] = &[
    (BINDING_NODES, BindingKind::Texels),
    (BINDING_TRIANGLES, BindingKind::Texels),
    (BINDING_SHADING, BindingKind::Texels),
    (BINDING_MATERIALS, BindingKind::Texels),
    (BINDING_LIGHTS, BindingKind::Texels),
    (BINDING_EMITTERS, BindingKind::Texels),
    (BINDING_TEXTURES, BindingKind::Texels),
    (BINDING_TEXELS, BindingKind::Texels),
    (BINDING_UVS, BindingKind::Texels),
    (BINDING_ENV_TEXELS, BindingKind::Texels),
    (BINDING_ENV_CDF, BindingKind::Texels),
    (BINDING_TANGENTS, BindingKind::Texels),
    (BINDING_FRAME, BindingKind::Uniform),
    (BINDING_TRIANGLE_LIST, BindingKind::Uniform),
];
