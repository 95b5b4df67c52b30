//! The staging buffers a context reuses for [`HostAccess::Staged`](super::HostAccess) writes and
//! reads: one for uploads, one for read-backs, grown to the largest transfer up to
//! [`KEEP_BYTES`]; a bigger transfer gets a buffer of its own, freed after. Before, every write
//! and read made (and freed) a staging buffer, which on a discrete GPU is an allocation per
//! 64k-ray chunk of `vkrt trace`.

use super::memory::{MemoryLocation, RawBuffer};
use super::Context;
use anyhow::{anyhow, Result};
use ash::vk;
use gpu_allocator::vulkan::Allocator;
use std::sync::atomic::Ordering;

/// The largest staging buffer kept between transfers: a 2048² accumulation read (64 MiB).
const KEEP_BYTES: u64 = 64 << 20;

/// The kept staging buffers.
#[derive(Default)]
pub struct Staging {
    up: Option<RawBuffer>,
    down: Option<RawBuffer>,
}

impl Staging {
    pub(super) fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        for b in [self.up.take(), self.down.take()].into_iter().flatten() {
            let mut b = b;
            b.destroy(device, allocator);
        }
    }
}

impl Context {
    /// Runs `transfer` with a mapped staging buffer of at least `len` bytes for `direction`
    /// (`Upload` or `Readback`). Callers drain first: the buffer is free once the lock is held.
    pub(super) fn with_staging<R>(&self, direction: MemoryLocation, len: u64, transfer: impl FnOnce(&RawBuffer) -> Result<R>) -> Result<R> {
        self.note_staged(len);
        let mut staging = self.staging.lock().map_err(|_| anyhow!("the staging buffers are poisoned"))?;
        let kept = match direction {
            MemoryLocation::Upload => &mut staging.up,
            MemoryLocation::Readback => &mut staging.down,
            MemoryLocation::Device => return Err(anyhow!("staging is host memory: Upload or Readback")),
        };
        let name = if direction == MemoryLocation::Upload { "staging upload" } else { "staging read-back" };
        let usage = vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        if len > KEEP_BYTES {
            let mut once = self.raw_buffer(name, len, usage, direction)?;
            let result = transfer(&once);
            self.free_raw(&mut once);
            return result;
        }
        if kept.as_ref().map_or(true, |b| b.size < len) {
            if let Some(mut old) = kept.take() {
                self.free_raw(&mut old);
            }
            // Grown in powers of two so a run of growing transfers reallocates a few times only.
            *kept = Some(self.raw_buffer(name, len.next_power_of_two().min(KEEP_BYTES), usage, direction)?);
        }
        match kept.as_ref() {
            Some(b) => transfer(b),
            None => Err(anyhow!("no staging buffer")),
        }
    }

    /// Counts `bytes` copied through a staging buffer of the caller's own.
    pub fn note_staged(&self, bytes: u64) {
        self.staged_bytes.fetch_add(bytes, Ordering::Relaxed);
    }

    /// Bytes copied through staging buffers so far (what [`HostAccess::Staged`] costs; tests
    /// check that the staged path really ran).
    pub fn staged_bytes(&self) -> u64 {
        self.staged_bytes.load(Ordering::Relaxed)
    }
}
