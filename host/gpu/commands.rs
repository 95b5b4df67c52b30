//! Command submission with up to [`IN_FLIGHT`] submissions queued at once, so the device never
//! waits for the host to record the next tile or batch (on a discrete GPU a submit-then-wait per
//! tile leaves it idle for the host's turn each time; lavapipe runs a queue thread and hides it).
//!
//! Every command buffer starts with [`compute_barrier`]: its first scope is all work submitted
//! before it on the queue, so each submission sees the writes of every earlier one (tiles of the
//! next batch add to the sums the last batch wrote). The host touches a buffer only after the
//! submissions that use it are done: [`Submissions::wait`] for one ticket, [`Context::drain`]
//! for all (the buffer read and write calls drain first unless told a ticket). Each command
//! buffer also ends with a barrier to the host, so its writes are visible to reads after the
//! fence wait; host writes before a submission are visible to it by vkQueueSubmit's rule.

use super::Context;
use anyhow::{anyhow, Context as _, Result};
use ash::vk;

/// Submissions queued at once: two let the host record one while the device runs the other.
pub const IN_FLIGHT: usize = 2;

/// A submission's number, counted from 1 on each context; waiting for it waits for every
/// earlier one too.
pub type Ticket = u64;

struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    /// The submission using this slot, 0 if none is pending.
    pending: Ticket,
}

/// The ring of command buffers and fences behind [`Context::submit`].
pub struct Submissions {
    slots: Vec<Slot>,
    next: usize,
    submitted: Ticket,
}

impl Submissions {
    /// `IN_FLIGHT` command buffers from `pool` and their fences.
    pub(super) fn new(device: &ash::Device, pool: vk::CommandPool) -> Result<Self> {
        let alloc = vk::CommandBufferAllocateInfo::default().command_pool(pool).level(vk::CommandBufferLevel::PRIMARY).command_buffer_count(IN_FLIGHT as u32);
        let mut ring = Self { slots: Vec::new(), next: 0, submitted: 0 };
        // SAFETY: valid device and pool; on failure the fences made so far are destroyed here
        // (the command buffers go with the pool, which the caller destroys).
        unsafe {
            let cmds = device.allocate_command_buffers(&alloc).context("vkAllocateCommandBuffers")?;
            for cmd in cmds {
                match device.create_fence(&vk::FenceCreateInfo::default(), None) {
                    Ok(fence) => ring.slots.push(Slot { cmd, fence, pending: 0 }),
                    Err(e) => {
                        ring.destroy(device);
                        return Err(anyhow!("vkCreateFence: {e}"));
                    }
                }
            }
        }
        Ok(ring)
    }

    /// Waits for the slot's submission if it has one pending.
    fn wait_slot(device: &ash::Device, slot: &mut Slot) -> Result<()> {
        if slot.pending == 0 {
            return Ok(());
        }
        // SAFETY: the fence belongs to the device and was submitted with the slot's work.
        unsafe {
            device.wait_for_fences(&[slot.fence], true, u64::MAX).context("vkWaitForFences")?;
            device.reset_fences(&[slot.fence]).context("vkResetFences")?;
        }
        slot.pending = 0;
        Ok(())
    }

    /// Waits for submission `ticket` and every one before it.
    pub fn wait(&mut self, device: &ash::Device, ticket: Ticket) -> Result<()> {
        for slot in self.slots.iter_mut().filter(|s| s.pending != 0 && s.pending <= ticket) {
            Self::wait_slot(device, slot)?;
        }
        Ok(())
    }

    /// The last submission made (0 before the first).
    pub fn last(&self) -> Ticket {
        self.submitted
    }

    /// Records `record` after a [`compute_barrier`] into the next free command buffer (waiting
    /// for the oldest submission if all are in use) and submits it.
    fn submit(&mut self, device: &ash::Device, queue: vk::Queue, what: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<Ticket> {
        let slot = &mut self.slots[self.next];
        Self::wait_slot(device, slot).with_context(|| format!("waiting for an earlier submission before {what}"))?;
        // SAFETY: the slot's command buffer is not pending (waited above); its pool allows reset.
        unsafe {
            device.reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty()).with_context(|| format!("vkResetCommandBuffer for {what}"))?;
            let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device.begin_command_buffer(slot.cmd, &begin).with_context(|| format!("vkBeginCommandBuffer for {what}"))?;
            record_barrier(device, slot.cmd);
            record(slot.cmd);
            record_host_barrier(device, slot.cmd);
            device.end_command_buffer(slot.cmd).with_context(|| format!("vkEndCommandBuffer for {what}"))?;
            let cmds = [slot.cmd];
            let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
            device.queue_submit(queue, &submit, slot.fence).with_context(|| format!("vkQueueSubmit for {what}"))?;
        }
        self.submitted += 1;
        slot.pending = self.submitted;
        self.next = (self.next + 1) % self.slots.len();
        Ok(self.submitted)
    }

    /// Waits for everything pending, then destroys the fences (the command buffers go with
    /// their pool).
    pub(super) fn destroy(&mut self, device: &ash::Device) {
        let last = self.submitted;
        let _ = self.wait(device, last);
        for slot in self.slots.drain(..) {
            // SAFETY: the fence is no longer pending (waited above, or the device is lost).
            unsafe { device.destroy_fence(slot.fence, None) };
        }
    }
}

impl Context {
    /// Submits `record`'s commands, after a barrier on all earlier work; returns at once unless
    /// [`IN_FLIGHT`] submissions are pending, then after the oldest is done. `what` names the
    /// work in errors.
    pub fn submit(&self, what: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<Ticket> {
        let mut ring = self.submissions.lock().map_err(|_| anyhow!("the submission ring is poisoned"))?;
        ring.submit(&self.device, self.queue, what, record)
    }

    /// Waits for submission `ticket` and all before it.
    pub fn wait(&self, ticket: Ticket) -> Result<()> {
        let mut ring = self.submissions.lock().map_err(|_| anyhow!("the submission ring is poisoned"))?;
        ring.wait(&self.device, ticket)
    }

    /// Waits for every submission made so far: before the host reads or writes what they use.
    pub fn drain(&self) -> Result<()> {
        let mut ring = self.submissions.lock().map_err(|_| anyhow!("the submission ring is poisoned"))?;
        let last = ring.last();
        ring.wait(&self.device, last)
    }
}

/// Records commands with `record`, submits them and waits for them (and everything before).
pub fn submit_and_wait(ctx: &Context, what: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
    let ticket = ctx.submit(what, record)?;
    ctx.wait(ticket).with_context(|| format!("waiting for {what}"))
}

/// A barrier that makes compute (and transfer) writes visible to later compute and transfer
/// work, and orders later writes after earlier reads.
pub fn compute_barrier(ctx: &Context, cmd: vk::CommandBuffer) {
    record_barrier(&ctx.device, cmd);
}

fn record_barrier(device: &ash::Device, cmd: vk::CommandBuffer) {
    let stages = vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER;
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_READ | vk::AccessFlags::TRANSFER_WRITE)];
    // SAFETY: `cmd` is in the recording state (called while recording a submission).
    unsafe { device.cmd_pipeline_barrier(cmd, stages, stages, vk::DependencyFlags::empty(), &barrier, &[], &[]) };
}

/// Makes the commands' writes visible to the host once their fence has signalled.
fn record_host_barrier(device: &ash::Device, cmd: vk::CommandBuffer) {
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ)];
    let src = vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER;
    // SAFETY: as in `record_barrier`.
    unsafe { device.cmd_pipeline_barrier(cmd, src, vk::PipelineStageFlags::HOST, vk::DependencyFlags::empty(), &barrier, &[], &[]) };
}
