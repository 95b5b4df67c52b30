//! The Whitted integrator's host side: frame settings, tiling, batches, read-back.

use super::gpu_scene::GpuScene;
use super::{Image, RenderSettings, RenderStats};
use crate::gpu::commands::submit_and_wait;
use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::layout::constants::*;
use crate::layout::{GpuFrame, GpuPush};
use crate::pipeline::{shaders, BindingKind, ComputePipeline};
use crate::scene::Scene;
use anyhow::{Context as _, Result};
use ash::vk;

/// The frame uniform for `scene` under `settings`.
pub fn frame_for(scene: &Scene, settings: &RenderSettings, light_count: u32, emitter_count: u32) -> Result<GpuFrame> {
    let cam = scene.camera.frame().context("camera")?;
    let bounds = scene.bounds();
    let scene_scale = if bounds.is_empty() { 1.0 } else { bounds.min.abs().max(bounds.max.abs()).max_element().max(f32::MIN_POSITIVE) };
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
        max_depth: settings.max_depth.clamp(1, WHITTED_STACK_SIZE - 1),
        light_count,
        emitter_count,
        seed: settings.seed,
        scene_scale,
    })
}

/// The bindings the integrator shaders use.
pub const INTEGRATOR_BINDINGS: &[(u32, BindingKind)] = &[
    (BINDING_NODES, BindingKind::Storage),
    (BINDING_TRIANGLES, BindingKind::Storage),
    (BINDING_SHADING, BindingKind::Storage),
    (BINDING_MATERIALS, BindingKind::Storage),
    (BINDING_LIGHTS, BindingKind::Storage),
    (BINDING_EMITTERS, BindingKind::Storage),
    (BINDING_FRAME, BindingKind::Uniform),
    (BINDING_ACCUM, BindingKind::Storage),
];

/// Renders `scene` (already on the GPU as `gpu`) with the Whitted integrator.
/// `progress(done, total)` is called after each submission.
pub fn render(
    ctx: &Context,
    scene: &Scene,
    gpu: &GpuScene,
    settings: &RenderSettings,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<(Image, RenderStats)> {
    if settings.width == 0 || settings.height == 0 {
        anyhow::bail!("image size {}x{} is empty", settings.width, settings.height);
    }
    let start = std::time::Instant::now();
    let pixels = settings.width as u64 * settings.height as u64;
    let mut stats = RenderStats::default();
    let mut image = Image::new(settings.width, settings.height);
    if gpu.triangle_count == 0 || settings.spp == 0 {
        // Nothing to hit: every ray escapes to a black background.
        stats.seconds = start.elapsed().as_secs_f64();
        return Ok((image, stats));
    }
    let frame = frame_for(scene, settings, gpu.light_count, gpu.emitter_count)?;
    let frame_buf = Buffer::new(ctx, "frame", std::mem::size_of::<GpuFrame>() as u64, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::Device)?;
    frame_buf.write(bytemuck::bytes_of(&frame))?;
    let accum = Buffer::new(ctx, "accumulation", pixels * 16, vk::BufferUsageFlags::STORAGE_BUFFER, MemoryLocation::Device)?;
    accum.clear()?;
    let spv = shaders::for_layout("whitted", gpu.layout)?;
    let pipeline = ComputePipeline::new(ctx, "whitted", spv, INTEGRATOR_BINDINGS, std::mem::size_of::<GpuPush>() as u32)?;
    for (binding, buffer) in [
        (BINDING_NODES, &gpu.nodes),
        (BINDING_TRIANGLES, &gpu.triangles),
        (BINDING_SHADING, &gpu.shading),
        (BINDING_MATERIALS, &gpu.materials),
        (BINDING_LIGHTS, &gpu.lights),
        (BINDING_EMITTERS, &gpu.emitters),
        (BINDING_FRAME, &frame_buf),
        (BINDING_ACCUM, &accum),
    ] {
        pipeline.bind(binding, buffer)?;
    }

    let tile = settings.tile_size.max(WORKGROUP_SIZE_X);
    let batch = settings.samples_per_batch.max(1);
    let tiles_x = settings.width.div_ceil(tile);
    let tiles_y = settings.height.div_ceil(tile);
    let batches = settings.spp.div_ceil(batch);
    let total = (tiles_x * tiles_y) as u64 * batches as u64;
    let mut done = 0u64;
    // Sample batches outermost, so that a long render refines the whole image evenly.
    for b in 0..batches {
        let sample_base = b * batch;
        let sample_count = batch.min(settings.spp - sample_base);
        for ty in 0..tiles_y {
            for tx in 0..tiles_x {
                let push = GpuPush {
                    tile_x: tx * tile,
                    tile_y: ty * tile,
                    sample_base,
                    sample_count,
                    total_spp: settings.spp,
                    ray_count: 0,
                    any_hit: 0,
                    _pad0: 0,
                };
                let w = tile.min(settings.width - push.tile_x);
                let h = tile.min(settings.height - push.tile_y);
                let groups = [w.div_ceil(WORKGROUP_SIZE_X), h.div_ceil(WORKGROUP_SIZE_Y), 1];
                submit_and_wait(ctx, "whitted tile", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups))?;
                stats.submissions += 1;
                done += 1;
                progress(done, total);
            }
        }
    }
    let sums: Vec<[f32; 4]> = accum.read_as(pixels as usize)?;
    let inv = 1.0 / settings.spp as f32;
    for (dst, s) in image.pixels.iter_mut().zip(&sums) {
        *dst = [s[0] * inv, s[1] * inv, s[2] * inv];
        stats.nonfinite_samples += s[3] as u64;
    }
    stats.seconds = start.elapsed().as_secs_f64();
    Ok((image, stats))
}
