//! Batch ray queries on the GPU: closest or any hit per ray, with traversal counters.
//! The GPU end of the agreement chain (tests/traversal.rs), the engine of `vkrt trace` and of
//! the layout comparisons in `vkrt bvh`.

use super::ray_order::{self, RayOrder};
use crate::accel::leaf::miss;
use crate::gpu::commands::submit_and_wait;
use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuHit, GpuPush, GpuRay};
use crate::pipeline::{shaders, BindingKind, ComputePipeline};
use crate::prepare::GpuBvh;
use anyhow::Result;
use ash::vk;

/// Rays per submission: bounded so no dispatch runs long (on lavapipe, 64k incoherent rays
/// through a 300k-triangle scene take well under a second).
pub const RAYS_PER_BATCH: usize = 1 << 16;

/// Rays sorted together when a batch is reordered ([`ray_order`]): on Conference's incoherent
/// rays, sorting within 64k-ray windows kept little of the gain, 256k most of it
/// (docs/experiments/ray-reordering.md). `vkrt trace` hands over 1M rays at a time.
pub const ORDER_WINDOW: usize = 1 << 20;

/// A ray-query pipeline for one uploaded scene (the `trace` variant for its layout) and its
/// ray and hit buffers; reusable for any number of [`RayQuery::trace`] calls.
pub struct RayQuery<'a> {
    ctx: &'a Context,
    /// None for a scene without triangles: every ray misses and nothing runs.
    gpu: Option<(ComputePipeline<'a>, Buffer<'a>, Buffer<'a>, GpuPush)>,
    /// The order rays are traced in (default [`RayOrder::Auto`]); hits always come back in
    /// the caller's order.
    pub order: RayOrder,
    /// Rays traced in sorted order so far.
    reordered: std::cell::Cell<u64>,
}

impl<'a> RayQuery<'a> {
    pub fn new(ctx: &'a Context, bvh: &GpuBvh) -> Result<Self> {
        Self::with_shader(ctx, bvh, shaders::Tracing::Trace.spirv(bvh.layout))
    }

    /// The same with another build of `trace.comp` for the BVH's layout (the benchmarks' plain
    /// intersection tests, `shaders::TRACE_PLAIN`, with the `bench` feature).
    pub fn with_shader(ctx: &'a Context, bvh: &GpuBvh, spv: &[u8]) -> Result<Self> {
        if bvh.triangle_count == 0 {
            return Ok(Self { ctx, gpu: None, order: RayOrder::default(), reordered: 0.into() });
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
        bvh.bind(&pipeline)?;
        pipeline.bind(BINDING_RAYS, &ray_buf)?;
        pipeline.bind(BINDING_HITS, &hit_buf)?;
        Ok(Self { ctx, gpu: Some((pipeline, ray_buf, hit_buf, bvh.push)), order: RayOrder::default(), reordered: 0.into() })
    }

    /// How many of the rays traced so far went in sorted order.
    pub fn rays_reordered(&self) -> u64 {
        self.reordered.get()
    }

    /// Traces `rays`, [`RAYS_PER_BATCH`] per submission, each window of [`ORDER_WINDOW`] rays
    /// in the order [`Self::order`] picks for it; one hit per ray, in the order of `rays`.
    pub fn trace(&self, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
        let Some((pipeline, ray_buf, hit_buf, scene)) = &self.gpu else {
            return Ok(vec![miss(); rays.len()]);
        };
        let mut hits = Vec::with_capacity(rays.len());
        let submit = |count: usize| {
            let push = GpuPush { ray_count: count as u32, any_hit: any_hit as u32, ..*scene };
            let groups = [(count as u32).div_ceil(WORKGROUP_SIZE_1D), 1, 1];
            submit_and_wait(self.ctx, "trace rays", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups))
        };
        for window in rays.chunks(ORDER_WINDOW) {
            let Some(order) = ray_order::plan(window, self.order) else {
                for chunk in window.chunks(RAYS_PER_BATCH) {
                    ray_buf.write(bytemuck::cast_slice(chunk))?;
                    submit(chunk.len())?;
                    hit_buf.read_into(chunk.len(), &mut hits)?;
                }
                continue;
            };
            self.reordered.set(self.reordered.get() + window.len() as u64);
            // Sorted: each submission takes the next rays of the order, gathered straight into
            // the ray buffer, and its hits go back to their rays' places.
            let start = hits.len();
            hits.resize(start + window.len(), miss());
            let placed = &mut hits[start..];
            for part in order.chunks(RAYS_PER_BATCH) {
                ray_buf.write_with(part.len(), |dst: &mut [GpuRay]| {
                    ray_order::parallel_zip(part, dst, |part, dst| {
                        for (d, &i) in dst.iter_mut().zip(part) {
                            *d = window[i as usize];
                        }
                    })
                })?;
                submit(part.len())?;
                hit_buf.read_with(part.len(), |src: &[GpuHit]| {
                    for (h, &i) in src.iter().zip(part) {
                        placed[i as usize] = *h;
                    }
                })?;
            }
        }
        Ok(hits)
    }
}

/// Traces `rays` through `bvh`; one hit per ray, in order.
pub fn trace_rays(ctx: &Context, bvh: &GpuBvh, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
    RayQuery::new(ctx, bvh)?.trace(rays, any_hit)
}
