//! Device memory: how the host reaches it ([`HostAccess`]), and buffers sub-allocated from
//! large blocks by the `gpu-allocator` crate (one `vkAllocateMemory` per buffer would meet
//! drivers' allocation-count limits, 4096 on some, and cost a kernel call each).

use anyhow::{anyhow, Context as _, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings, MemoryLocation as AllocatorLocation};

/// Sub-allocation block size. 64 MiB (the crate's default for host-visible memory, where all
/// of lavapipe's memory is) keeps small scenes small; larger buffers get a block of their own.
const BLOCK_BYTES: u64 = 64 << 20;

/// Every buffer starts at a multiple of this in its memory, so a mapping can be read as any
/// GPU struct (the largest alignment is 16) whatever alignment the driver asks for.
pub const MAP_ALIGNMENT: u64 = 64;

/// How the host reaches device-local memory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HostAccess {
    /// Device-local memory is host-visible and cached on the whole heap (lavapipe, integrated
    /// GPUs): buffers are mapped, written and read in place.
    Mapped,
    /// It is host-visible on the whole heap but not cached (a discrete GPU with resizable BAR):
    /// the host writes in place (write-combined stores over PCIe are fast) but reads through a
    /// copy into cached staging memory. Reading such a mapping in place is uncached: on an
    /// H200 it held `vkrt trace` to 0.4-0.9 M rays/s against 100-700 M rays/s of traversal.
    MappedWrites,
    /// It is not host-visible (a discrete GPU without resizable BAR, or asked for): device
    /// buffers are written and read through a staging buffer and a copy.
    Staged,
}

impl HostAccess {
    /// Mapped if a host-visible, coherent, device-local memory type sits on the largest
    /// device-local heap (a 256 MiB BAR window beside 80 GiB of VRAM does not count): reads in
    /// place too if that type is also cached.
    pub fn detect(memory: &vk::PhysicalDeviceMemoryProperties) -> Self {
        let heaps = &memory.memory_heaps[..memory.memory_heap_count as usize];
        let types = &memory.memory_types[..memory.memory_type_count as usize];
        let device_local = |h: &vk::MemoryHeap| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL);
        let largest = heaps.iter().filter(|h| device_local(h)).map(|h| h.size).max().unwrap_or(0);
        let want = vk::MemoryPropertyFlags::DEVICE_LOCAL | vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let mappable = |t: &&vk::MemoryType| t.property_flags.contains(want) && heaps[t.heap_index as usize].size >= largest;
        let cached = |t: &vk::MemoryType| t.property_flags.contains(vk::MemoryPropertyFlags::HOST_CACHED);
        match types.iter().filter(mappable).map(cached).max() {
            Some(true) => HostAccess::Mapped,
            Some(false) => HostAccess::MappedWrites,
            None => HostAccess::Staged,
        }
    }

    /// The access `VKRT_MEMORY` names (`mapped-writes`, `staged`), to run a device the way
    /// another kind of device works.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "mapped-writes" => Some(HostAccess::MappedWrites),
            "staged" => Some(HostAccess::Staged),
            _ => None,
        }
    }

    /// Whether the host reads device buffers in place.
    pub fn reads_in_place(self) -> bool {
        self == HostAccess::Mapped
    }

    pub fn name(self) -> &'static str {
        match self {
            HostAccess::Mapped => "mapped (device memory is host-visible and cached)",
            HostAccess::MappedWrites => "mapped writes, staged reads (device memory is host-visible, uncached)",
            HostAccess::Staged => "staged (device memory through staging copies)",
        }
    }
}

/// Where a buffer should live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemoryLocation {
    /// Fast for the GPU; mapped unless [`HostAccess::Staged`].
    Device,
    /// Host-visible and coherent, written by the host (staging for uploads).
    Upload,
    /// Host-visible, cached where offered, read by the host (staging for read-backs).
    Readback,
}

/// A buffer, its memory and, if the host may use it directly, its mapping. Freed by
/// [`RawBuffer::destroy`] (its owner's Drop), not on its own drop.
pub struct RawBuffer {
    pub buffer: vk::Buffer,
    allocation: Option<Allocation>,
    pub size: u64,
    /// The host's pointer to the buffer's first byte.
    pub mapped: Option<*mut u8>,
    /// Whether the host may read through `mapped` (false for device buffers under
    /// [`HostAccess::MappedWrites`]: uncached memory, read through staging instead).
    pub reads_in_place: bool,
}

// SAFETY: the mapping pointer is only dereferenced by the owner, under its own rules.
unsafe impl Send for RawBuffer {}

/// The allocator for a device: 64 MiB blocks ([`BLOCK_BYTES`]), no logging.
pub fn new_allocator(instance: &ash::Instance, device: &ash::Device, physical: vk::PhysicalDevice) -> Result<Allocator> {
    let mut debug_settings = AllocatorDebugSettings::default();
    debug_settings.log_leaks_on_shutdown = false;
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device: physical,
        debug_settings,
        buffer_device_address: false,
        allocation_sizes: AllocationSizes::new(BLOCK_BYTES, BLOCK_BYTES),
    })
    .map_err(|e| anyhow!("creating the memory allocator: {e}"))
}

impl RawBuffer {
    /// A buffer of `size` bytes in `location`; mapped if host-visible and `location` is not
    /// `Device` under [`HostAccess::Staged`], read in place only where that memory is cached.
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        access: HostAccess,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let info = vk::BufferCreateInfo::default().size(size).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info; the buffer is destroyed on the error paths.
        let buffer = unsafe { device.create_buffer(&info, None) }.with_context(|| format!("vkCreateBuffer '{name}' ({size} bytes)"))?;
        let mut requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        requirements.alignment = requirements.alignment.max(MAP_ALIGNMENT);
        let wanted = match (location, access) {
            // CpuToGpu prefers device-local host-visible memory: on a resizable-BAR GPU that is
            // the device-local type the host can map, where GpuOnly could pick the other one.
            (MemoryLocation::Device, HostAccess::Mapped | HostAccess::MappedWrites) => AllocatorLocation::CpuToGpu,
            (MemoryLocation::Device, HostAccess::Staged) => AllocatorLocation::GpuOnly,
            (MemoryLocation::Upload, _) => AllocatorLocation::CpuToGpu,
            (MemoryLocation::Readback, _) => AllocatorLocation::GpuToCpu,
        };
        let desc = AllocationCreateDesc { name, requirements, location: wanted, linear: true, allocation_scheme: AllocationScheme::GpuAllocatorManaged };
        let allocation = match allocator.allocate(&desc) {
            Ok(a) => a,
            Err(e) => {
                unsafe { device.destroy_buffer(buffer, None) };
                return Err(anyhow!("allocating {} bytes for buffer '{name}': {e}", requirements.size));
            }
        };
        // SAFETY: the allocation fits the requirements and outlives the buffer (both freed in `destroy`).
        if let Err(e) = unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) } {
            unsafe { device.destroy_buffer(buffer, None) };
            let _ = allocator.free(allocation);
            return Err(anyhow!("vkBindBufferMemory '{name}': {e}"));
        }
        let host_may_map = !(location == MemoryLocation::Device && access == HostAccess::Staged);
        let mapped = allocation.mapped_ptr().filter(|_| host_may_map).map(|p| p.as_ptr() as *mut u8);
        if location != MemoryLocation::Device && mapped.is_none() {
            unsafe { device.destroy_buffer(buffer, None) };
            let _ = allocator.free(allocation);
            return Err(anyhow!("buffer '{name}': the device offers no host-visible memory for staging"));
        }
        let reads_in_place = mapped.is_some() && (location != MemoryLocation::Device || access.reads_in_place());
        Ok(Self { buffer, allocation: Some(allocation), size, mapped, reads_in_place })
    }

    /// Destroys the buffer and returns its memory to the allocator.
    pub fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: no pending submission uses the buffer (owners drain before dropping it).
        unsafe { device.destroy_buffer(self.buffer, None) };
        if let Some(a) = self.allocation.take() {
            let _ = allocator.free(a);
        }
    }
}
