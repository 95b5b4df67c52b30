//! Batch ray queries on the GPU: closest or any hit per ray, with traversal counters.
//! The GPU end of the agreement chain (tests/traversal.rs), the engine of `vkrt trace` and of
//! the layout comparisons in `vkrt bvh`.

use super::ray_order::{self, RayOrder};
use crate::accel::leaf::miss;
use crate::gpu::commands::compute_barrier;
use crate::gpu::{Buffer, Context, GpuTimer, MemoryLocation, Ticket, IN_FLIGHT};
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuHit, GpuPush, GpuRay};
use crate::pipeline::{shaders, BindingKind, ComputePipeline};
use crate::prepare::GpuBvh;
use anyhow::Result;
use ash::vk;
use std::mem::size_of;

/// Rays per submission: bounded so no dispatch runs long (on lavapipe, 64k incoherent rays
/// through a 300k-triangle scene take well under a second).
pub const RAYS_PER_BATCH: usize = 1 << 16;

/// Rays sorted together when a batch is reordered ([`ray_order`]): on Conference's incoherent
/// rays, sorting within 64k-ray windows kept little of the gain, 256k most of it
/// (docs/experiments/ray-reordering.md). `vkrt trace` hands over 1M rays at a time.
pub const ORDER_WINDOW: usize = 1 << 20;

/// One submission's buffers, bound to a descriptor set of their own so the next batch can be
/// written while this one runs. On a [`HostAccess::Staged`](crate::gpu::HostAccess) device the
/// host fills `rays_up` and reads `hits_down`, copied in the same command buffer as the
/// dispatch, and under `MappedWrites` (uncached, over a BAR) it reads `hits_down`; elsewhere it
/// uses `rays` and `hits` in place.
struct Slot<'a> {
    rays: Buffer<'a>,
    hits: Buffer<'a>,
    rays_up: Option<Buffer<'a>>,
    hits_down: Option<Buffer<'a>>,
}

impl<'a> Slot<'a> {
    fn new(ctx: &'a Context) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let (ray_bytes, hit_bytes) = ((RAYS_PER_BATCH * size_of::<GpuRay>()) as u64, (RAYS_PER_BATCH * size_of::<GpuHit>()) as u64);
        let rays = Buffer::new(ctx, "rays", ray_bytes, storage, MemoryLocation::Device)?;
        let hits = Buffer::new(ctx, "hits", hit_bytes, storage, MemoryLocation::Device)?;
        let rays_up =
            (!rays.is_mapped()).then(|| Buffer::new(ctx, "rays (upload)", ray_bytes, vk::BufferUsageFlags::empty(), MemoryLocation::Upload)).transpose()?;
        let hits_down = (!hits.reads_in_place())
            .then(|| Buffer::new(ctx, "hits (read-back)", hit_bytes, vk::BufferUsageFlags::empty(), MemoryLocation::Readback))
            .transpose()?;
        Ok(Self { rays, hits, rays_up, hits_down })
    }

    /// The buffer the host writes rays into.
    fn rays_in(&self) -> &Buffer<'a> {
        self.rays_up.as_ref().unwrap_or(&self.rays)
    }

    /// The buffer the host reads hits from.
    fn hits_out(&self) -> &Buffer<'a> {
        self.hits_down.as_ref().unwrap_or(&self.hits)
    }
}

/// Rays of [`RayQuery::warm_up`] (`vkrt bvh` warmed up with as many camera rays before it).
pub const WARM_UP_RAYS: usize = 1024;

/// The GPU side of a [`RayQuery`].
struct QueryGpu<'a> {
    pipeline: ComputePipeline<'a>,
    slots: Vec<Slot<'a>>,
    scene: GpuPush,
    /// Times each slot's dispatch on the device, if the queue has timestamps.
    timer: Option<GpuTimer<'a>>,
}

/// A ray-query pipeline for one uploaded scene (the `trace` variant for its layout) and its
/// ray and hit buffers; reusable for any number of [`RayQuery::trace`] calls.
pub struct RayQuery<'a> {
    ctx: &'a Context,
    /// None for a scene without triangles: every ray misses and nothing runs.
    gpu: Option<QueryGpu<'a>>,
    /// The order rays are traced in (default [`RayOrder::Auto`]); hits always come back in
    /// the caller's order.
    pub order: RayOrder,
    /// Rays traced in sorted order so far.
    reordered: std::cell::Cell<u64>,
    /// Seconds the device spent in trace dispatches so far (timestamps), if it has them.
    device_seconds: std::cell::Cell<Option<f64>>,
}

/// Where a batch's hits go: rays `start..` of the input in order, or the rays `part` names
/// (indices into the window that starts at `base`).
enum Placement<'o> {
    Given { start: usize, count: usize },
    Sorted { base: usize, part: &'o [u32] },
}

impl Placement<'_> {
    fn count(&self) -> usize {
        match self {
            Placement::Given { count, .. } => *count,
            Placement::Sorted { part, .. } => part.len(),
        }
    }
}

impl<'a> RayQuery<'a> {
    /// Queries walking `bvh` with the product's `trace.comp` for its layout (`trace_two_level_<id>`,
    /// its TWO_LEVEL build, for a two-level BVH).
    pub fn new(ctx: &'a Context, bvh: &GpuBvh) -> Result<Self> {
        let spv = bvh.spirv(shaders::Tracing::Trace)?;
        Self::with_shader(ctx, bvh, spv)
    }

    /// The same with another build of `trace.comp` for the BVH's layout (the benchmarks' plain
    /// intersection tests, `shaders::TRACE_PLAIN`, with the `bench` feature).
    pub fn with_shader(ctx: &'a Context, bvh: &GpuBvh, spv: &[u8]) -> Result<Self> {
        if bvh.triangle_count == 0 {
            return Ok(Self { ctx, gpu: None, order: RayOrder::default(), reordered: 0.into(), device_seconds: None.into() });
        }
        let mut bindings = vec![
            (BINDING_NODES, BindingKind::Texels),
            (BINDING_TRIANGLES, BindingKind::Texels),
            (BINDING_TRIANGLE_LIST, BindingKind::Uniform),
            (BINDING_RAYS, BindingKind::Storage),
            (BINDING_HITS, BindingKind::Storage),
        ];
        bindings.extend_from_slice(bvh.instance_bindings());
        let pipeline = ComputePipeline::specialized(ctx, "trace", spv, &bindings, size_of::<GpuPush>() as u32, &bvh.spec_constants())?;
        bvh.bind(&pipeline)?;
        let slots = (0..IN_FLIGHT).map(|_| Slot::new(ctx)).collect::<Result<Vec<_>>>()?;
        for (set, slot) in slots.iter().enumerate() {
            pipeline.bind_in(set, BINDING_RAYS, &slot.rays)?;
            pipeline.bind_in(set, BINDING_HITS, &slot.hits)?;
        }
        let timer = GpuTimer::new(ctx, IN_FLIGHT as u32)?;
        let device_seconds = timer.as_ref().map(|_| 0.0).into();
        let gpu = QueryGpu { pipeline, slots, scene: bvh.push, timer };
        Ok(Self { ctx, gpu: Some(gpu), order: RayOrder::default(), reordered: 0.into(), device_seconds })
    }

    /// Traces [`WARM_UP_RAYS`] rays of length 0, neither timed nor counted. lavapipe turns a
    /// compute shader into machine code at its first dispatch, so without this the first
    /// batch's times, host and device alike, held the compile: the first `vkrt trace` of a
    /// layout reported 0.78 M rays/s against 7.9 M warm (issue 45). More than one ray, so that
    /// the batch buffers' first pages are touched too.
    pub fn warm_up(&self) -> Result<()> {
        let ray = GpuRay { origin: [0.0; 3], tmin: 0.0, direction: [0.0, 0.0, 1.0], tmax: 0.0 };
        self.trace(&[ray; WARM_UP_RAYS], false)?;
        if self.device_seconds.get().is_some() {
            self.device_seconds.set(Some(0.0));
        }
        self.reordered.set(0);
        Ok(())
    }

    /// How many of the rays traced so far went in sorted order.
    pub fn rays_reordered(&self) -> u64 {
        self.reordered.get()
    }

    /// Seconds the device spent tracing so far, by its timestamps (None without them, or for a
    /// scene without triangles): the traversal alone, without upload, sorting and read-back.
    pub fn device_seconds(&self) -> Option<f64> {
        self.device_seconds.get()
    }

    /// Traces `rays`, [`RAYS_PER_BATCH`] per submission, each window of [`ORDER_WINDOW`] rays
    /// in the order [`Self::order`] picks for it; one hit per ray, in the order of `rays`.
    /// [`IN_FLIGHT`] batches are under way at once: while the device traces one, the host
    /// reads the hits of the one before and writes the rays of the next.
    pub fn trace(&self, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
        let Some(gpu) = &self.gpu else {
            return Ok(vec![miss(); rays.len()]);
        };
        let mut hits = vec![miss(); rays.len()];
        let mut batch = 0usize;
        for (w, window) in rays.chunks(ORDER_WINDOW).enumerate() {
            let base = w * ORDER_WINDOW;
            let order = ray_order::plan(window, self.order);
            if order.is_some() {
                self.reordered.set(self.reordered.get() + window.len() as u64);
            }
            let placements: Vec<Placement> = match &order {
                None => (0..window.len())
                    .step_by(RAYS_PER_BATCH)
                    .map(|i| Placement::Given { start: base + i, count: RAYS_PER_BATCH.min(window.len() - i) })
                    .collect(),
                Some(order) => order.chunks(RAYS_PER_BATCH).map(|part| Placement::Sorted { base, part }).collect(),
            };
            // Per slot: the batch in flight in it, if any.
            let mut pending: Vec<Option<(Ticket, Placement)>> = (0..gpu.slots.len()).map(|_| None).collect();
            for placement in placements {
                let s = batch % gpu.slots.len();
                batch += 1;
                let slot = &gpu.slots[s];
                let after = match pending[s].take() {
                    Some((ticket, done)) => {
                        collect(slot, ticket, &done, &mut hits)?;
                        self.add_device_time(gpu, s)?;
                        ticket
                    }
                    None => 0,
                };
                let count = placement.count();
                slot.rays_in().write_after(after, count, |dst: &mut [GpuRay]| match &placement {
                    Placement::Given { start, count } => dst.copy_from_slice(&rays[*start..start + count]),
                    Placement::Sorted { base, part } => ray_order::parallel_zip(part, dst, |part, dst| {
                        for (d, &i) in dst.iter_mut().zip(part) {
                            *d = rays[base + i as usize];
                        }
                    }),
                })?;
                let ticket = self.submit(gpu, s, count, any_hit)?;
                pending[s] = Some((ticket, placement));
            }
            // The window's order is dropped here: collect what still points into it.
            for (s, p) in pending.iter_mut().enumerate() {
                if let Some((ticket, done)) = p.take() {
                    collect(&gpu.slots[s], ticket, &done, &mut hits)?;
                    self.add_device_time(gpu, s)?;
                }
            }
        }
        Ok(hits)
    }

    /// Adds slot `s`'s last dispatch time (its submission is done) to `device_seconds`.
    fn add_device_time(&self, gpu: &QueryGpu, s: usize) -> Result<()> {
        if let (Some(timer), Some(total)) = (&gpu.timer, self.device_seconds.get()) {
            self.device_seconds.set(Some(total + timer.seconds(s as u32)?));
        }
        Ok(())
    }

    /// Submits the trace of the `count` rays in slot `s`, with its staging copies if any.
    fn submit(&self, gpu: &QueryGpu, s: usize, count: usize, any_hit: bool) -> Result<Ticket> {
        let slot = &gpu.slots[s];
        let push = GpuPush { ray_count: count as u32, any_hit: any_hit as u32, ..gpu.scene };
        let groups = [(count as u32).div_ceil(self.ctx.workgroups.d1), 1, 1];
        let dev = &self.ctx.device;
        let staged = slot.rays_up.as_ref().map_or(0, |_| count * size_of::<GpuRay>()) + slot.hits_down.as_ref().map_or(0, |_| count * size_of::<GpuHit>());
        if staged > 0 {
            self.ctx.note_staged(staged as u64);
        }
        self.ctx.submit("trace rays", |cmd| {
            // SAFETY: `cmd` is recording; the copies stay inside the buffers (RAYS_PER_BATCH).
            unsafe {
                if let Some(up) = &slot.rays_up {
                    let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: (count * size_of::<GpuRay>()) as u64 }];
                    dev.cmd_copy_buffer(cmd, up.buffer, slot.rays.buffer, &region);
                    compute_barrier(self.ctx, cmd);
                }
                if let Some(t) = &gpu.timer {
                    t.record_begin(cmd, s as u32);
                }
                gpu.pipeline.record_dispatch_in(cmd, s, bytemuck::bytes_of(&push), groups);
                if let Some(t) = &gpu.timer {
                    t.record_end(cmd, s as u32);
                }
                if let Some(down) = &slot.hits_down {
                    compute_barrier(self.ctx, cmd);
                    let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: (count * size_of::<GpuHit>()) as u64 }];
                    dev.cmd_copy_buffer(cmd, slot.hits.buffer, down.buffer, &region);
                }
            }
        })
    }
}

/// Reads slot `slot`'s hits of submission `ticket` into their rays' places.
fn collect(slot: &Slot, ticket: Ticket, placement: &Placement, hits: &mut [GpuHit]) -> Result<()> {
    slot.hits_out().read_after(ticket, placement.count(), |src: &[GpuHit]| match placement {
        Placement::Given { start, count } => hits[*start..start + count].copy_from_slice(src),
        Placement::Sorted { base, part } => {
            for (h, &i) in src.iter().zip(*part) {
                hits[base + i as usize] = *h;
            }
        }
    })
}

/// Traces `rays` through `bvh`; one hit per ray, in order.
pub fn trace_rays(ctx: &Context, bvh: &GpuBvh, rays: &[GpuRay], any_hit: bool) -> Result<Vec<GpuHit>> {
    RayQuery::new(ctx, bvh)?.trace(rays, any_hit)
}
