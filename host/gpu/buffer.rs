//! Storage and uniform buffers, with upload and read-back that work on every memory model:
//! mapped directly where device memory is host-visible (lavapipe, integrated GPUs, ReBAR),
//! through a staging buffer and a copy elsewhere.

use super::commands::submit_and_wait;
use super::Context;
use anyhow::{anyhow, Context as _, Result};
use ash::vk;

/// Where a buffer should live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemoryLocation {
    /// Fast for the GPU; mapped only if the device offers host-visible device-local memory.
    Device,
    /// Host-visible and coherent (staging, read-back).
    Host,
}

/// A buffer and its memory, freed on drop.
pub struct Buffer<'a> {
    ctx: &'a Context,
    pub buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    pub size: u64,
    mapped: Option<*mut u8>,
    name: String,
}

fn find_memory_type(ctx: &Context, bits: u32, want: vk::MemoryPropertyFlags) -> Option<u32> {
    let m = &ctx.memory;
    (0..m.memory_type_count).find(|&i| bits & (1 << i) != 0 && m.memory_types[i as usize].property_flags.contains(want))
}

impl<'a> Buffer<'a> {
    /// A buffer of `size` bytes (at least 16: Vulkan forbids empty buffers, and an empty array
    /// still needs something bound).
    pub fn new(ctx: &'a Context, name: &str, size: u64, usage: vk::BufferUsageFlags, location: MemoryLocation) -> Result<Self> {
        let size = size.max(16);
        let usage = usage | vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let info = vk::BufferCreateInfo::default().size(size).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        let dev = &ctx.device;
        // SAFETY: valid device and create info; every object is destroyed on the error paths below or in Drop.
        unsafe {
            let buffer = dev.create_buffer(&info, None).with_context(|| format!("vkCreateBuffer '{name}' ({size} bytes)"))?;
            let req = dev.get_buffer_memory_requirements(buffer);
            let hv = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            let dl = vk::MemoryPropertyFlags::DEVICE_LOCAL;
            let choice = match location {
                MemoryLocation::Device => find_memory_type(ctx, req.memory_type_bits, dl | hv)
                    .map(|t| (t, true))
                    .or_else(|| find_memory_type(ctx, req.memory_type_bits, dl).map(|t| (t, false))),
                MemoryLocation::Host => find_memory_type(ctx, req.memory_type_bits, hv | vk::MemoryPropertyFlags::HOST_CACHED)
                    .or_else(|| find_memory_type(ctx, req.memory_type_bits, hv))
                    .map(|t| (t, true)),
            };
            let Some((type_index, mappable)) = choice else {
                dev.destroy_buffer(buffer, None);
                return Err(anyhow!("no suitable memory type for buffer '{name}'"));
            };
            let alloc = vk::MemoryAllocateInfo::default().allocation_size(req.size).memory_type_index(type_index);
            let memory = match dev.allocate_memory(&alloc, None) {
                Ok(m) => m,
                Err(e) => {
                    dev.destroy_buffer(buffer, None);
                    return Err(anyhow!("vkAllocateMemory for buffer '{name}' ({} bytes): {e}", req.size));
                }
            };
            let mut made = Self { ctx, buffer, memory, size, mapped: None, name: name.to_string() };
            dev.bind_buffer_memory(buffer, memory, 0).with_context(|| format!("vkBindBufferMemory '{name}'"))?;
            if mappable {
                let ptr = dev
                    .map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty())
                    .with_context(|| format!("vkMapMemory '{name}'"))?;
                made.mapped = Some(ptr as *mut u8);
            }
            Ok(made)
        }
    }

    /// A view of the whole buffer as texels of `format`, for a `utextureBuffer`; the buffer
    /// needs UNIFORM_TEXEL_BUFFER usage.
    pub fn texel_view(&self, format: TexelFormat) -> Result<TexelView<'a>> {
        let info = vk::BufferViewCreateInfo::default()
            .buffer(self.buffer)
            .format(format.vk())
            .offset(0)
            .range(self.size / format.bytes() * format.bytes());
        // SAFETY: valid buffer made with texel usage (checked by the validation layers in tests).
        let view = unsafe { self.ctx.device.create_buffer_view(&info, None) }
            .with_context(|| format!("vkCreateBufferView '{}' ({format:?})", self.name))?;
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
    /// when the buffer is host-visible, else into a mapped staging buffer copied over after.
    pub fn write_with<T: bytemuck::Pod>(&self, count: usize, fill: impl FnOnce(&mut [T])) -> Result<()> {
        let len = self.checked_len::<T>(count, "writing")?;
        if count == 0 {
            return Ok(());
        }
        let Some(ptr) = self.mapped_as::<T>() else {
            let staging = Buffer::new(self.ctx, "staging upload", len, vk::BufferUsageFlags::empty(), MemoryLocation::Host)?;
            staging.write_with(count, fill)?;
            return copy(self.ctx, &staging, self, len);
        };
        // SAFETY: the mapping covers `size` >= `len` bytes and is aligned for T (`mapped_as`),
        // T is plain data, and nothing on the GPU uses the buffer now (every submission is
        // waited for).
        fill(unsafe { std::slice::from_raw_parts_mut(ptr, count) });
        Ok(())
    }

    /// Fills the buffer with zeros.
    pub fn clear(&self) -> Result<()> {
        let buffer = self.buffer;
        let size = self.size;
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
    /// [`Self::write_with`]).
    pub fn read_with<T: bytemuck::Pod>(&self, count: usize, take: impl FnOnce(&[T])) -> Result<()> {
        let len = self.checked_len::<T>(count, "reading")?;
        if count == 0 {
            return Ok(());
        }
        let Some(ptr) = self.mapped_as::<T>() else {
            let staging = Buffer::new(self.ctx, "staging read-back", len, vk::BufferUsageFlags::empty(), MemoryLocation::Host)?;
            copy(self.ctx, self, &staging, len)?;
            return staging.read_with(count, take);
        };
        // SAFETY: as in `write_with`; coherent memory, the GPU is idle.
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

    /// The mapping as a pointer to T, if the buffer is mapped. Vulkan maps at
    /// minMemoryMapAlignment (at least 64 bytes), enough for any T vkrt reads or writes.
    fn mapped_as<T>(&self) -> Option<*mut T> {
        let ptr = self.mapped?;
        debug_assert_eq!(ptr as usize % std::mem::align_of::<T>(), 0, "mapping of '{}' misaligned", self.name);
        Some(ptr as *mut T)
    }
}

fn copy(ctx: &Context, src: &Buffer, dst: &Buffer, len: u64) -> Result<()> {
    let region = [vk::BufferCopy { src_offset: 0, dst_offset: 0, size: len }];
    submit_and_wait(ctx, &format!("copy '{}' to '{}'", src.name, dst.name), |cmd| unsafe {
        ctx.device.cmd_copy_buffer(cmd, src.buffer, dst.buffer, &region);
    })
}

/// The texel formats vkrt's `utextureBuffer`s read (both must support uniform texel buffers on
/// every Vulkan device: spec table "Mandatory format support: 32-bit components").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexelFormat {
    /// RGBA32UI, 16 bytes: a quarter of a GPU struct (GpuNode is 2 texels, GpuMaterial 4).
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
        // SAFETY: no pending submission uses the view (vkrt waits for each).
        unsafe { self.ctx.device.destroy_buffer_view(self.view, None) };
    }
}

impl Drop for Buffer<'_> {
    fn drop(&mut self) {
        // SAFETY: every submission that used this buffer has been waited for.
        unsafe {
            if self.mapped.is_some() {
                self.ctx.device.unmap_memory(self.memory);
            }
            self.ctx.device.destroy_buffer(self.buffer, None);
            self.ctx.device.free_memory(self.memory, None);
        }
    }
}
