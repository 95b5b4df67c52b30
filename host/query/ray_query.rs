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
use std::cell::RefCell;
use std::mem::size_of;

/// Rays of a query's first submission: bounded so no dispatch runs long (on lavapipe, 64k
/// incoherent rays through a 300k-triangle scene take well under a second). Later submissions
/// take as many rays as [`next_batch`] makes of the last one's device time.
pub const RAYS_PER_BATCH: usize = 1 << 16;

/// Device seconds a submission aims at. A GPU traces 64k rays in tens of microseconds, less
/// than a submission's round trip and the copies around it (the first GPU check, on an H200,
/// saw `vkrt trace` end to end 30-40x below its traversal alone with 64k-ray submissions:
/// docs/experiments/first-gpu-check.md), so batches grow there until each takes about this
/// long; on lavapipe a 64k batch of a realistic scene takes longer already, and stays put.
/// Short enough for a device without a watchdog.
pub const BATCH_SECONDS: f64 = 0.016;

/// Rays sorted together when a batch is reordered ([`ray_order`]): on Conference's incoherent
/// rays, sorting within 64k-ray windows kept little of the gain, 256k most of it
/// (docs/experiments/ray-reordering.md). `vkrt trace` hands over 1M rays at a time.
pub const ORDER_WINDOW: usize = 1 << 20;

/// The rays of the submission after one of `rays` rays (the current size) that took `seconds`
/// on the device: twice as many while it took under half of [`BATCH_SECONDS`], half as many
/// (not below [`RAYS_PER_BATCH`]) when it took over twice that, at most `max`. Started at
/// [`RAYS_PER_BATCH`], as every query's batches are, sizes stay that times a power of two.
pub fn next_batch(rays: usize, seconds: f64, max: usize) -> usize {
    let max = max.max(RAYS_PER_BATCH);
    if seconds < 0.5 * BATCH_SECONDS && 2 * rays <= max {
        2 * rays
    } else if seconds > 2.0 * BATCH_SECONDS && rays / 2 >= RAYS_PER_BATCH {
        rays / 2
    } else {
        rays.min(max)
    }
}

/// One submission's buffers, bound to a descriptor set of their own so the next batch can be
/// written while this one runs. On a [`HostAccess::Staged`](crate::gpu::HostAccess) device the
/// host fills `rays_up` and reads `hits_down`, copied in the same command buffer as the
/// dispatch, and under `MappedWrites` (uncached, over a BAR) it reads `hits_down`; elsewhere it
/// uses `rays` and `hits` in place.
struct Slot<'a> {
    /// Rays the buffers hold.
    capacity: usize,
    rays: Buffer<'a>,
    hits: Buffer<'a>,
    rays_up: Option<Buffer<'a>>,
    hits_down: Option<Buffer<'a>>,
}

impl<'a> Slot<'a> {
    fn new(ctx: &'a Context, capacity: usize) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let (ray_bytes, hit_bytes) = ((capacity * size_of::<GpuRay>()) as u64, (capacity * size_of::<GpuHit>()) as u64);
        let rays = Buffer::new(ctx, "rays", ray_bytes, storage, MemoryLocation::Device)?;
        let hits = Buffer::new(ctx, "hits", hit_bytes, storage, MemoryLocation::Device)?;
        let rays_up =
            (!rays.is_mapped()).then(|| Buffer::new(ctx, "rays (upload)", ray_bytes, vk::BufferUsageFlags::empty(), MemoryLocation::Upload)).transpose()?;
        let hits_down = (!hits.reads_in_place())
            .then(|| Buffer::new(ctx, "hits (read-back)", hit_bytes, vk::BufferUsageFlags::empty(), MemoryLocation::Readback))
            .transpose()?;
        Ok(Self { capacity, rays, hits, rays_up, hits_down })
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
    /// One per descriptor set; a slot is replaced by a larger one when batches outgrow it.
    slots: RefCell<Vec<Slot<'a>>>,
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
    /// Rays of the next submission ([`next_batch`]; [`RAYS_PER_BATCH`] without timestamps).
    batch_rays: std::cell::Cell<usize>,
    /// The most rays a submission may take: [`ORDER_WINDOW`], or fewer where the device's
    /// storage buffers or dispatches are smaller.
    max_batch: usize,
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
            return Ok(Self {
                ctx,
                gpu: None,
                order: RayOrder::default(),
                reordered: 0.into(),
                device_seconds: None.into(),
                batch_rays: RAYS_PER_BATCH.into(),
                max_batch: RAYS_PER_BATCH,
            });
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
        let slots = (0..IN_FLIGHT).map(|_| Slot::new(ctx, RAYS_PER_BATCH)).collect::<Result<Vec<_>>>()?;
        for (set, slot) in slots.iter().enumerate() {
            pipeline.bind_in(set, BINDING_RAYS, &slot.rays)?;
            pipeline.bind_in(set, BINDING_HITS, &slot.hits)?;
        }
        let timer = GpuTimer::new(ctx, IN_FLIGHT as u32)?;
        let device_seconds = timer.as_ref().map(|_| 0.0).into();
        let gpu = QueryGpu { pipeline, slots: RefCell::new(slots), scene: bvh.push, timer };
        // Within the device's storage-buffer range, and within the 65,535 workgroups of one
        // dimension that every device can dispatch.
        let ray_bytes = size_of::<GpuRay>().max(size_of::<GpuHit>());
        let max_batch = ORDER_WINDOW.min(ctx.info.max_storage_buffer_range as usize / ray_bytes).min(65_535 * ctx.workgroups.d1 as usize).max(RAYS_PER_BATCH);
        Ok(Self { ctx, gpu: Some(gpu), order: RayOrder::default(), reordered: 0.into(), device_seconds, batch_rays: RAYS_PER_BATCH.into(), max_batch })
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

    /// Rays the next submission takes (for the benchmarks' reports and the tests).
    pub fn batch_rays(&self) -> usize {
        self.batch_rays.get()
    }

    /// Makes the next submission take `rays` rays (at least 1, at most what the device allows),
    /// as if the batches had grown to it: for the tests, which cannot make a device fast.
    pub fn set_batch_rays(&self, rays: usize) {
        self.batch_rays.set(rays.clamp(1, self.max_batch));
    }

    /// Traces `rays`, [`Self::batch_rays`] per submission, each window of [`ORDER_WINDOW`]
    /// rays in the order [`Self::order`] picks for it; one hit per ray, in the order of `rays`.
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
            // Per slot: the batch in flight in it, if any.
            let mut pending: Vec<Option<(Ticket, Placement)>> = (0..IN_FLIGHT).map(|_| None).collect();
            let mut next = 0usize;
            while next < window.len() {
                let s = batch % IN_FLIGHT;
                batch += 1;
                let after = match pending[s].take() {
                    Some((ticket, done)) => {
                        collect(&gpu.slots.borrow()[s], ticket, &done, &mut hits)?;
                        self.batch_done(gpu, s, done.count())?;
                        ticket
                    }
                    None => 0,
                };
                // After the collect: the batch size may have changed.
                let count = self.batch_rays.get().min(window.len() - next);
                let placement = match &order {
                    None => Placement::Given { start: base + next, count },
                    Some(order) => Placement::Sorted { base, part: &order[next..next + count] },
                };
                next += count;
                self.fit_slot(gpu, s, count)?;
                let slots = gpu.slots.borrow();
                slots[s].rays_in().write_after(after, count, |dst: &mut [GpuRay]| match &placement {
                    Placement::Given { start, count } => ray_order::parallel_zip(&rays[*start..start + count], dst, |src, dst| dst.copy_from_slice(src)),
                    Placement::Sorted { base, part } => ray_order::parallel_zip(part, dst, |part, dst| {
                        for (d, &i) in dst.iter_mut().zip(part) {
                            *d = rays[base + i as usize];
                        }
                    }),
                })?;
                let ticket = self.submit(gpu, &slots[s], s, count, any_hit)?;
                pending[s] = Some((ticket, placement));
            }
            // The window's order is dropped here: collect what still points into it.
            for (s, p) in pending.iter_mut().enumerate() {
                if let Some((ticket, done)) = p.take() {
                    collect(&gpu.slots.borrow()[s], ticket, &done, &mut hits)?;
                    self.batch_done(gpu, s, done.count())?;
                }
            }
        }
        Ok(hits)
    }

    /// After slot `s`'s batch of `count` rays is done: adds its dispatch time to
    /// `device_seconds` and sizes the next batch by it ([`next_batch`]; only a full-size batch
    /// says how long one takes).
    fn batch_done(&self, gpu: &QueryGpu, s: usize, count: usize) -> Result<()> {
        let (Some(timer), Some(total)) = (&gpu.timer, self.device_seconds.get()) else {
            return Ok(());
        };
        let seconds = timer.seconds(s as u32)?;
        self.device_seconds.set(Some(total + seconds));
        if count == self.batch_rays.get() {
            self.batch_rays.set(next_batch(count, seconds, self.max_batch));
        }
        Ok(())
    }

    /// Makes slot `s` hold `count` rays: a larger slot, bound to its descriptor set, when the
    /// batches have outgrown it. Its last batch has been collected, so nothing in flight uses
    /// its buffers or its set.
    fn fit_slot(&self, gpu: &QueryGpu<'a>, s: usize, count: usize) -> Result<()> {
        if count <= gpu.slots.borrow()[s].capacity {
            return Ok(());
        }
        let slot = Slot::new(self.ctx, count)?;
        gpu.pipeline.bind_in(s, BINDING_RAYS, &slot.rays)?;
        gpu.pipeline.bind_in(s, BINDING_HITS, &slot.hits)?;
        gpu.slots.borrow_mut()[s] = slot;
        Ok(())
    }

    /// Submits the trace of the `count` rays in slot `s`, with its staging copies if any.
    fn submit(&self, gpu: &QueryGpu, slot: &Slot, s: usize, count: usize, any_hit: bool) -> Result<Ticket> {
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
        Placement::Given { start, count } => ray_order::parallel_zip(src, &mut hits[*start..start + count], |src, dst| dst.copy_from_slice(src)),
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

#[cfg(test)]
mod tests {
    use super::*;

    const MAX: usize = ORDER_WINDOW;

    #[test]
    fn fast_batches_double_up_to_the_most_a_submission_may_take() {
        assert_eq!(next_batch(RAYS_PER_BATCH, 0.0001, MAX), 2 * RAYS_PER_BATCH);
        assert_eq!(next_batch(MAX / 2, 0.0001, MAX), MAX);
        assert_eq!(next_batch(MAX, 0.0001, MAX), MAX);
        // A device whose buffers hold fewer rays than a window.
        assert_eq!(next_batch(4 * RAYS_PER_BATCH, 0.0001, 5 * RAYS_PER_BATCH), 4 * RAYS_PER_BATCH);
    }

    #[test]
    fn batches_near_the_target_stay_and_slow_ones_halve_down_to_the_first_size() {
        assert_eq!(next_batch(4 * RAYS_PER_BATCH, BATCH_SECONDS, MAX), 4 * RAYS_PER_BATCH);
        assert_eq!(next_batch(4 * RAYS_PER_BATCH, 0.6 * BATCH_SECONDS, MAX), 4 * RAYS_PER_BATCH);
        assert_eq!(next_batch(4 * RAYS_PER_BATCH, 1.9 * BATCH_SECONDS, MAX), 4 * RAYS_PER_BATCH);
        assert_eq!(next_batch(4 * RAYS_PER_BATCH, 3.0 * BATCH_SECONDS, MAX), 2 * RAYS_PER_BATCH);
        // lavapipe on a realistic scene: 64k rays take tens of milliseconds, and stay 64k.
        assert_eq!(next_batch(RAYS_PER_BATCH, 0.5, MAX), RAYS_PER_BATCH);
    }
}
