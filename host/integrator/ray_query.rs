//! Batch ray queries on the GPU: closest or any hit per ray, with traversal counters.
//! The GPU end of the agreement chain (tests/traversal.rs), the engine of `vkrt trace` and of
//! the layout comparisons in `vkrt bvh`.

use super::gpu_scene::GpuScene;
use crate::gpu::commands::submit_and_wait;
use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::layout::constants::*;
use crate::layout::{GpuHit, GpuPush, GpuRay};
use crate::pipeline::{shaders, BindingKind, ComputePipeline};
use anyhow::Result;
use ash::vk;

/// Rays per submission: bounded so no dispatch runs long (on lavapipe, 64k incoherent rays
/// through a 300k-triangle scene take well under a second).
pub const RAYS_PER_BATCH: usize = 1 << 16;

/// A ray-query pipeline for one uploaded scene (the `trace` variant for its layout) and its
/// ray and hit buffers; reusable for any number of [`RayQuery::trace`] calls.
pub struct RayQuery<'a> {
    ctx: &'a Context,
    /// None for a scene without triangles: every ray misses and nothing runs.
    gpu: Option<(ComputePipeline<'a>, Buffer<'a>, Buffer<'a>, GpuPush)>,
}

impl<'a> RayQuery<'a> {
    pub fn new(ctx: &'a Context, gpu: &GpuScene) -> Result<Self> {
        Self::with_shader(ctx, gpu, shaders::for_layout("trace", gpu.layout)?)
    }

    /// The same with another `trace.comp` variant for the scene's layout (e.g. `trace_plain`).
    pub fn with_shader(ctx: &'a Context, gpu: &GpuScene, spv: &[u8]) -> Result<Self> {
        if gpu.triangle_count == 0 {
            return Ok(Self { ctx, gpu: None });
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let ray_buf = Buffer::new(ctx, "rays", (RAYS_PER_BATCH * std::mem::size_of::<GpuRay>()) as u64, storage, MemoryLocation::Device)?;
        let hit_buf = Buffer::new(ctx, "hits", (RAYS_PER_BATCH * std::mem::size_of::<GpuHit>()) as u64, storage, MemoryLocation::Device)?;
        let bindings = [
            (BINDING_NODES, BindingKind::Texels),
            (BINDING_TRIANGLES, BindingKind::Texels),
            (BINDING_RAYS, BindingKind::Storage),
            (BINDING_HITS, BindingKind::Storage),
        ];
        let pipeline = ComputePipeline::new(ctx, "trace", spv, &bindings, std::mem::size_of::<GpuPush>() as u32)?;
        gpu.bind_bvh(&pipeline)?;
        pipeline.bind(BINDING_RAYS, &ray_buf)?;
        pipeline.bind(BINDING_HITS, &hit_buf)?;
        Ok(Self { ctx, gpu: Some((pipeline, ray_buf, hit_buf, gpu.push())) })
    }

    /// Traces `rays`, [`RAYS_PER_BATCH`] per submission; one hit per ray, in order.
    pub fn trace(&self, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
        let Some((pipeline, ray_buf, hit_buf, scene)) = &self.gpu else {
            return Ok(vec![crate::layout::cpu_trace::miss(); rays.len()]);
        };
        let mut hits = Vec::with_capacity(rays.len());
        for chunk in rays.chunks(RAYS_PER_BATCH) {
            ray_buf.write(bytemuck::cast_slice(chunk))?;
            let push = GpuPush { ray_count: chunk.len() as u32, any_hit: any_hit as u32, ..*scene };
            let groups = [(chunk.len() as u32).div_ceil(WORKGROUP_SIZE_1D), 1, 1];
            submit_and_wait(self.ctx, "trace rays", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups))?;
            hits.extend(hit_buf.read_as::<GpuHit>(chunk.len())?);
        }
        Ok(hits)
    }
}

/// Traces `rays` against the scene; one hit per ray, in order.
pub fn trace_rays(ctx: &Context, gpu: &GpuScene, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
    RayQuery::new(ctx, gpu)?.trace(rays, any_hit)
}
