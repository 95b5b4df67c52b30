//! Device-side timing with timestamp queries (core Vulkan): how long a dispatch ran on the
//! device, without the host's upload, sorting and read-back around it. `vkrt trace` reports
//! both rates, since on a discrete GPU moving rays over PCIe can cost more than tracing them.

use super::Context;
use anyhow::{Context as _, Result};
use ash::vk;

/// `pairs` (begin, end) timestamp pairs, one per double-buffered slot; destroyed on drop.
pub struct GpuTimer<'a> {
    ctx: &'a Context,
    pool: vk::QueryPool,
    /// Nanoseconds per timestamp tick.
    period_ns: f64,
}

impl<'a> GpuTimer<'a> {
    /// None if the compute queue has no timestamps (timestampValidBits = 0).
    pub fn new(ctx: &'a Context, pairs: u32) -> Result<Option<Self>> {
        // SAFETY: valid instance and physical device.
        let (families, props) =
            unsafe { (ctx.instance.get_physical_device_queue_family_properties(ctx.physical), ctx.instance.get_physical_device_properties(ctx.physical)) };
        let valid_bits = families.get(ctx.queue_family as usize).map_or(0, |f| f.timestamp_valid_bits);
        if valid_bits == 0 || props.limits.timestamp_period <= 0.0 {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(2 * pairs);
        // SAFETY: valid device and create info; destroyed in Drop.
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }.context("vkCreateQueryPool")?;
        Ok(Some(Self { ctx, pool, period_ns: f64::from(props.limits.timestamp_period) }))
    }

    /// Records the start of pair `i`: reset, then a timestamp once all earlier commands are
    /// done (so the interval is the work recorded after it).
    pub fn record_begin(&self, cmd: vk::CommandBuffer, i: u32) {
        // SAFETY: `cmd` is recording; the queries are in range (2 per pair).
        unsafe {
            self.ctx.device.cmd_reset_query_pool(cmd, self.pool, 2 * i, 2);
            self.ctx.device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, self.pool, 2 * i);
        }
    }

    /// Records the end of pair `i`: a timestamp once the work since `record_begin` is done.
    pub fn record_end(&self, cmd: vk::CommandBuffer, i: u32) {
        // SAFETY: as in `record_begin`.
        unsafe { self.ctx.device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, self.pool, 2 * i + 1) };
    }

    /// Seconds between pair `i`'s timestamps; waits for them (call after the submission is done).
    pub fn seconds(&self, i: u32) -> Result<f64> {
        let mut ticks = [0u64; 2];
        // SAFETY: both queries were written by a submission that has completed.
        unsafe {
            self.ctx
                .device
                .get_query_pool_results(self.pool, 2 * i, &mut ticks, vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT)
                .context("vkGetQueryPoolResults")?;
        }
        Ok(ticks[1].wrapping_sub(ticks[0]) as f64 * self.period_ns * 1e-9)
    }
}

impl Drop for GpuTimer<'_> {
    fn drop(&mut self) {
        let _ = self.ctx.drain();
        // SAFETY: no submission using the pool is pending after the drain.
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}
