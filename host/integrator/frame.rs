//! The per-render uniform every integrator shader reads (`GpuFrame`), and the scene bindings.

use super::RenderSettings;
use crate::layout::constants::*;
use crate::layout::GpuFrame;
use crate::pipeline::BindingKind;
use crate::scene::Scene;
use anyhow::{Context as _, Result};

/// The frame uniform for `scene` under `settings`. `max_depth` is stored as given: each
/// integrator clamps it to what its shader supports.
pub fn frame_for(scene: &Scene, settings: &RenderSettings, light_count: u32, emitter_count: u32) -> Result<GpuFrame> {
    let cam = scene.camera.frame().context("camera")?;
    Ok(GpuFrame {
        cam_origin: cam.origin.to_array(),
        tan_half_fov_y: cam.tan_half_fov_y,
        cam_forward: cam.forward.to_array(),
        aspect: settings.width as f32 / settings.height as f32,
        cam_right: cam.right.to_array(),
        width: settings.width,
        cam_up: cam.up.to_array(),
        height: settings.height,
        ambient: scene.ambient.to_array(),
        max_depth: settings.max_depth,
        light_count,
        emitter_count,
        seed: settings.seed,
        scene_scale: scene_scale(scene),
        sky_color: scene.sky.gpu().0,
        sky_texture: scene.sky.gpu().1,
    })
}

/// Largest |coordinate| of the scene bounds: the length scale for ray offsets.
pub fn scene_scale(scene: &Scene) -> f32 {
    let bounds = scene.bounds();
    if bounds.is_empty() { 1.0 } else { bounds.min.abs().max(bounds.max.abs()).max_element().max(f32::MIN_POSITIVE) }
}

/// The bindings every integrator shader uses: the scene's arrays are texel buffers
/// ([`super::gpu_scene::GpuScene::bind_scene`]).
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
    (BINDING_FRAME, BindingKind::Uniform),
    (BINDING_ACCUM, BindingKind::Storage),
];
