//! The Whitted integrator's host side (shaders/whitted.comp): frame settings, tiling, batches,
//! read-back.

use super::frame::{frame_for, INTEGRATOR_BINDINGS};
use super::tiles::{bind_all, dispatch_samples, tile_count};
use super::{Image, RenderSettings, RenderStats};
use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuFrame, GpuPush};
use crate::pipeline::shaders::Tracing;
use crate::pipeline::{BindingKind, ComputePipeline};
use crate::prepare::GpuScene;
use anyhow::{bail, Result};
use ash::vk;

/// The most rays per path: the ray tree lives on a fixed stack of `WHITTED_STACK_SIZE` entries
/// (whitted.comp), one of which the tree's root takes.
pub const MAX_DEPTH: u32 = WHITTED_STACK_SIZE - 1;

/// Renders `scene` with the Whitted integrator. `progress(done, total)` is called after each
/// submission.
pub fn render(ctx: &Context, scene: &GpuScene, settings: &RenderSettings, progress: &mut dyn FnMut(u64, u64)) -> Result<(Image, RenderStats)> {
    if settings.width == 0 || settings.height == 0 {
        bail!("image size {}x{} is empty", settings.width, settings.height);
    }
    if !(1..=MAX_DEPTH).contains(&settings.max_depth) {
        bail!(
            "the Whitted integrator traces 1 to {MAX_DEPTH} rays per path (its ray tree lives on a fixed stack); max depth {} is outside that",
            settings.max_depth
        );
    }
    let start = std::time::Instant::now();
    let pixels = settings.width as u64 * settings.height as u64;
    let mut stats = RenderStats::default();
    let mut image = Image::new(settings.width, settings.height);
    if scene.bvh.triangle_count == 0 || settings.spp == 0 {
        // Nothing to hit: every ray escapes to a black background.
        stats.seconds = start.elapsed().as_secs_f64();
        return Ok((image, stats));
    }
    let frame = frame_for(scene, settings)?;
    let frame_buf = Buffer::new(ctx, "frame", std::mem::size_of::<GpuFrame>() as u64, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::Device)?;
    frame_buf.write(bytemuck::bytes_of(&frame))?;
    let accum = Buffer::new(ctx, "accumulation", pixels * 16, vk::BufferUsageFlags::STORAGE_BUFFER, MemoryLocation::Device)?;
    accum.clear()?;
    let features = settings.features(&scene.info);
    let bindings: Vec<(u32, BindingKind)> =
        INTEGRATOR_BINDINGS.iter().chain(scene.bvh.instance_bindings()).copied().chain([(BINDING_ACCUM, BindingKind::Storage)]).collect();
    let pipeline = ComputePipeline::specialized(
        ctx,
        "whitted",
        scene.bvh.spirv(Tracing::Whitted)?,
        &bindings,
        std::mem::size_of::<GpuPush>() as u32,
        &[features.spec_constants(), scene.trace_spec_constants()].concat(),
    )?;
    stats.pipeline_seconds = pipeline.creation_seconds();
    stats.shader_origin = pipeline.origin().to_string();
    stats.shader = Tracing::Whitted.name();
    scene.bind(&pipeline)?;
    bind_all(&pipeline, &[(BINDING_FRAME, &frame_buf), (BINDING_ACCUM, &accum)])?;
    let batch = settings.samples_per_batch.max(1);
    let batches = settings.spp.div_ceil(batch);
    let total = tile_count(ctx, settings, 1) * batches as u64;
    let mut done = 0u64;
    // Sample batches outermost, so that a long render refines the whole image evenly.
    for b in 0..batches {
        let sample_base = b * batch;
        let sample_count = batch.min(settings.spp - sample_base);
        dispatch_samples(ctx, &scene.bvh.push, &pipeline, "whitted tile", settings, 1, sample_base, sample_count, settings.spp, &mut || {
            stats.submissions += 1;
            done += 1;
            progress(done, total);
        })?;
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
