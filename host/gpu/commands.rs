//! One-shot command submission: record, submit, wait. Every submission vkrt makes is short
//! (a tile or a batch of samples), so waiting right away costs little and keeps lifetimes simple.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;

/// Records commands with `record`, submits them to the compute queue and waits for them.
/// `what` names the work in errors.
pub fn submit_and_wait(ctx: &Context, what: &str, record: impl FnOnce(vk::CommandBuffer)) -> Result<()> {
    let dev = &ctx.device;
    let alloc = vk::CommandBufferAllocateInfo::default()
        .command_pool(ctx.command_pool)
        .level(vk::CommandBufferLevel::PRIMARY)
        .command_buffer_count(1);
    // SAFETY: the pool belongs to this device; the command buffer and fence are freed below on
    // every path, after the fence wait (or after a failed submit, when nothing is pending).
    unsafe {
        let cmd = dev.allocate_command_buffers(&alloc).with_context(|| format!("vkAllocateCommandBuffers for {what}"))?[0];
        let fence = match dev.create_fence(&vk::FenceCreateInfo::default(), None) {
            Ok(f) => f,
            Err(e) => {
                dev.free_command_buffers(ctx.command_pool, &[cmd]);
                return Err(anyhow::anyhow!("vkCreateFence for {what}: {e}"));
            }
        };
        let result = (|| -> Result<()> {
            dev.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT))
                .with_context(|| format!("vkBeginCommandBuffer for {what}"))?;
            record(cmd);
            dev.end_command_buffer(cmd).with_context(|| format!("vkEndCommandBuffer for {what}"))?;
            let cmds = [cmd];
            let submit = [vk::SubmitInfo::default().command_buffers(&cmds)];
            dev.queue_submit(ctx.queue, &submit, fence).with_context(|| format!("vkQueueSubmit for {what}"))?;
            dev.wait_for_fences(&[fence], true, u64::MAX).with_context(|| format!("vkWaitForFences for {what}"))?;
            Ok(())
        })();
        dev.destroy_fence(fence, None);
        dev.free_command_buffers(ctx.command_pool, &[cmd]);
        result
    }
}

/// A barrier that makes compute (and transfer) writes visible to later compute and transfer work.
pub fn compute_barrier(ctx: &Context, cmd: vk::CommandBuffer) {
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_READ)];
    // SAFETY: `cmd` is in the recording state (called from inside a `submit_and_wait` closure).
    unsafe {
        ctx.device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::TRANSFER,
            vk::DependencyFlags::empty(),
            &barrier,
            &[],
            &[],
        );
    }
}
