//! Storage and uniform buffers, with upload and read-back that work on every memory model
//! ([`HostAccess`](super::HostAccess)): mapped and written in place where device memory is
//! host-visible (lavapipe, integrated GPUs, resizable BAR), read in place only where it is also
//! cached (not over a BAR), through the context's reused staging buffers and a copy elsewhere.
//! Host access waits for the submissions in flight first ([`Context::drain`]), or for one given
//! ticket (`*_after`, for double-buffered work).

use super::commands::{submit_and_wait, Ticket};
use super::memory::{MemoryLocation, RawBuffer};
use super::Context;
use anyhow::{anyhow, Context as _, Result};
use ash::vk;

/// A buffer and its memory, freed on drop (after the submissions in flight, which may use it).
pub struct Buffer<'a> {
    ctx: &'a Context,
    raw: RawBuffer,
    pub buffer: vk::Buffer,
    pub size: u64,
    name: String,
}

impl Context {
    /// A buffer from the context's allocator (see [`RawBuffer::new`]).
    pub(super) fn raw_buffer(&self, name: &str, size: u64, usage: vk::BufferUsageFlags, location: MemoryLocation) -> Result<RawBuffer> {
        let mut allocator = self.allocator.lock().map_err(|_| anyhow!("the memory allocator is poisoned"))?;
        let allocator = allocator.as_mut().ok_or_else(|| anyhow!("the context is shutting down"))?;
        RawBuffer::new(&self.device, allocator, self.host_access, name, size, usage, location)
    }

    /// Returns a buffer made by [`Self::raw_buffer`].
    pub(super) fn free_raw(&self, raw: &mut RawBuffer) {
        if let Ok(mut allocator) = self.allocator.lock() {
            if let Some(a) = allocator.as_mut() {
                raw.destroy(&self.device, a);
            }
        }
    }
}

impl<'a> Buffer<'a> {
    /// A buffer of `size` bytes (at least 16: Vulkan forbids empty buffers, and an empty array
    /// still needs something bound).
    pub fn new(ctx: &'a Context, name: &str, size: u64, usage: vk::BufferUsageFlags, location: MemoryLocation) -> Result<Self> {
        let size = size.max(16);
        let usage = usage | vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let raw = ctx.raw_buffer(name, size, usage, location)?;
        Ok(Self { ctx, buffer: raw.buffer, size, raw, name: name.to_string() })
    }

    /// True if the host writes the buffer in place (no staging copy).
    pub fn is_mapped(&self) -> bool {
        self.raw.mapped.is_some()
    }

    /// True if the host also reads the buffer in place (mapped and cached).
    pub fn reads_in_place(&self) -> bool {
        self.raw.reads_in_place
    }

    /// A view of the whole buffer as texels of `format`, for a `utextureBuffer`; the buffer
    /// needs UNIFORM_TEXEL_BUFFER usage.
    pub fn texel_view(&self, format: TexelFormat) -> Result<TexelView<'a>> {
        let info = vk::BufferViewCreateInfo::default().buffer(self.buffer).format(format.vk()).offset(0).range(self.size / format.bytes() * format.bytes());
        // SAFETY: valid buffer made with texel usage (checked by the validation layers in tests).
        let view = unsafe { self.ctx.device.create_buffer_view(&info, None) }.with_context(|| format!("vkCreateBufferView '{}' ({format:?})", self.name))?;
        Ok(TexelView { ctx: self.ctx, view })
    }

    /// A device buffer holding `data`.
    pub fn with_data<T: bytemuck::Pod>(ctx: &'a Context, name: &str, data: &[T], usage: vk::BufferUsageFlags) -> Result<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let b = Self::new(ctx, name, bytes.len() as u64, usage, MemoryLocation::Device)?;
        b.write(bytes)?;
        Ok(b)
    }

    /// Copies `bytes` to the start of the buffer.
    pub fn write(&self, bytes: &[u8]) -> Result<()> {
        self.write_with(bytes.len(), |dst: &mut [u8]| dst.copy_from_slice(bytes))
    }

    /// Lets `fill` write the first `count` values of type T in place: straight into the mapping
    /// when the buffer is mapped, else into a staging buffer copied over after. Waits for every
    /// submission in flight first.
    pub fn write_with<T: bytemuck::Pod>(&self, count: usize, fill: impl FnOnce(&mut [T])) -> Result<()> {
        self.ctx.drain()?;
        self.write_unsynchronized(count, fill)
    }

    /// As [`Self::write_with`], waiting only for submission `ticket`: the caller promises that
    /// no later submission in flight uses this buffer. An unmapped buffer waits for all.
    pub fn write_after<T: bytemuck::Pod>(&self, ticket: Ticket, count: usize, fill: impl FnOnce(&mut [T])) -> Result<()> {
        if self.is_mapped() {
            self.ctx.wait(ticket)?
        } else {
            self.ctx.drain()?
        }
        self.write_unsynchronized(count, fill)
    }

    fn write_unsynchronized<T: bytemuck::Pod>(&self, count: usize, fill: impl FnOnce(&mut [T])) -> Result<()> {
        let len = self.checked_len::<T>(count, "writing")?;
        if count == 0 {
            return Ok(());
        }
        let Some(ptr) = self.mapped_as::<T>() else {
            return self.ctx.with_staging(MemoryLocation::Upload, len, |staging| {
                // SAFETY: the staging mapping holds at least `len` bytes and is not in use (the
                // context's lock is held and every submission has been waited for).
                fill(unsafe { std::slice::from_raw_parts_mut(mapped_ptr::<T>(staging)?, count) });
                copy(self.ctx, staging.buffer, self.buffer, len, &self.name)
            });
        };
        // SAFETY: the mapping covers `size` >= `len` bytes and is aligned for T (`mapped_as`),
        // T is plain data, and no submission that uses the buffer is in flight (waited above).
        fill(unsafe { std::slice::from_raw_parts_mut(ptr, count) });
        Ok(())
    }

    /// Fills the buffer with zeros (after everything submitted before).
    pub fn clear(&self) -> Result<()> {
        let (buffer, size) = (self.buffer, self.size);
        submit_and_wait(self.ctx, "clear buffer", |cmd| unsafe {
            self.ctx.device.cmd_fill_buffer(cmd, buffer, 0, size, 0);
        })
    }

    /// Reads `len` bytes from the start of the buffer.
    pub fn read(&self, len: u64) -> Result<Vec<u8>> {
        self.read_as(len.min(self.size) as usize)
    }

    /// Reads `count` values of type T.
    pub fn read_as<T: bytemuck::Pod>(&self, count: usize) -> Result<Vec<T>> {
        let mut out = Vec::new();
        self.read_into(count, &mut out)?;
        Ok(out)
    }

    /// Appends the first `count` values of type T to `out`, copying once (a read of a million
    /// hits is 32 MiB: each extra copy into fresh memory cost tens of milliseconds in page
    /// faults on lavapipe).
    pub fn read_into<T: bytemuck::Pod>(&self, count: usize, out: &mut Vec<T>) -> Result<()> {
        self.read_with(count, |src: &[T]| out.extend_from_slice(src))
    }

    /// Lets `take` read the first `count` values of type T in place (the read-side twin of
    /// [`Self::write_with`]), after every submission in flight.
    pub fn read_with<T: bytemuck::Pod>(&self, count: usize, take: impl FnOnce(&[T])) -> Result<()> {
        self.ctx.drain()?;
        self.read_unsynchronized(count, take)
    }

    /// As [`Self::read_with`], waiting only for submission `ticket` (same promise as
    /// [`Self::write_after`]).
    pub fn read_after<T: bytemuck::Pod>(&self, ticket: Ticket, count: usize, take: impl FnOnce(&[T])) -> Result<()> {
        if self.reads_in_place() {
            self.ctx.wait(ticket)?
        } else {
            self.ctx.drain()?
        }
        self.read_unsynchronized(count, take)
    }

    fn read_unsynchronized<T: bytemuck::Pod>(&self, count: usize, take: impl FnOnce(&[T])) -> Result<()> {
        let len = self.checked_len::<T>(count, "reading")?;
        if count == 0 {
            return Ok(());
        }
        let Some(ptr) = self.mapped_as::<T>().filter(|_| self.reads_in_place()) else {
            return self.ctx.with_staging(MemoryLocation::Readback, len, |staging| {
                copy(self.ctx, self.buffer, staging.buffer, len, &self.name)?;
                // SAFETY: as in `write_unsynchronized`; the copy has completed.
                take(unsafe { std::slice::from_raw_parts(mapped_ptr::<T>(staging)?, count) });
                Ok(())
            });
        };
        // SAFETY: as in `write_unsynchronized`; coherent memory, the submissions are done.
        take(unsafe { std::slice::from_raw_parts(ptr, count) });
        Ok(())
    }

    /// The bytes `count` values of T take, or an error naming the buffer if they do not fit.
    fn checked_len<T>(&self, count: usize, doing: &str) -> Result<u64> {
        let len = (count * std::mem::size_of::<T>()) as u64;
        if len > self.size {
            return Err(anyhow!("{doing} {len} bytes in buffer '{}' of {} bytes", self.name, self.size));
        }
        Ok(len)
    }

    /// The mapping as a pointer to T, if the buffer is mapped.
    fn mapped_as<T>(&self) -> Option<*mut T> {
        mapped_ptr::<T>(&self.raw).ok()
    }
}

/// A raw buffer's mapping as a pointer to T (sub-allocations start 64-byte aligned,
/// `memory::MAP_ALIGNMENT`: enough for any T vkrt reads or writes).
fn mapped_ptr<T>(raw: &RawBuffer) -> Result<*mut T> {
    let ptr = raw.mapped.ok_or_else(|| anyhow!("buffer is not mapped"))?;
    if ptr as usize % std::mem::align_of::<T>() != 0 {
        return Err(anyhow!("buffer mapping misaligned for {}", std::any::type_name::<T>()));
    }
    Ok(ptr as *mut T)
}

/// Copies `len` bytes from `src` to `dst` and waits.
fn copy(ctx: &Context, src: vk::Buffer, dst: vk::Buffer, len: u64, name: &str) -> Result<()> {
    let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: len }];
    submit_and_wait(ctx, &format!("staging copy for '{name}'"), |cmd| unsafe {
        ctx.device.cmd_copy_buffer(cmd, src, dst, &region);
    })
}

/// The texel formats vkrt's `utextureBuffer`s read (both must support uniform texel buffers on
/// every Vulkan device: spec table "Mandatory format support: 32-bit components").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexelFormat {
    /// RGBA32UI, 16 bytes: a quarter of a GPU struct (GpuNode is 2 texels, GpuMaterial 6).
    Rgba32Uint,
    /// R32UI, 4 bytes: one packed RGBA8 texture texel.
    R32Uint,
}

impl TexelFormat {
    pub fn bytes(self) -> u64 {
        match self {
            TexelFormat::Rgba32Uint => 16,
            TexelFormat::R32Uint => 4,
        }
    }

    fn vk(self) -> vk::Format {
        match self {
            TexelFormat::Rgba32Uint => vk::Format::R32G32B32A32_UINT,
            TexelFormat::R32Uint => vk::Format::R32_UINT,
        }
    }
}

/// A texel view of a [`Buffer`], destroyed on drop (before the buffer).
pub struct TexelView<'a> {
    ctx: &'a Context,
    pub view: vk::BufferView,
}

impl Drop for TexelView<'_> {
    fn drop(&mut self) {
        // SAFETY: no submission using the view is pending after the drain.
        let _ = self.ctx.drain();
        unsafe { self.ctx.device.destroy_buffer_view(self.view, None) };
    }
}

impl Drop for Buffer<'_> {
    fn drop(&mut self) {
        // Submissions in flight may still use the buffer.
        let _ = self.ctx.drain();
        self.ctx.free_raw(&mut self.raw);
    }
}
