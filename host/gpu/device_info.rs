//! What `vkrt info` shows about a Vulkan device: the limits that matter to vkrt.

use ash::vk;
use std::fmt;

#[derive(Debug, Clone, PartialEq)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub device_type: vk::PhysicalDeviceType,
    pub api_version: u32,
    pub driver_name: String,
    pub driver_info: String,
    pub driver_version: u32,
    /// Which driver (`VkDriverId`): lavapipe is `MESA_LLVMPIPE`.
    pub driver_id: vk::DriverId,
    pub max_storage_buffer_range: u32,
    /// Most texels one texel-buffer view may hold (the scene's arrays are read as texels).
    pub max_texel_buffer_elements: u32,
    pub max_workgroup_size: [u32; 3],
    pub max_workgroup_invocations: u32,
    pub subgroup_size: u32,
    pub max_push_constants_size: u32,
    /// Size of the largest device-local heap, in bytes.
    pub device_local_bytes: u64,
    /// How the host reaches its device-local memory.
    pub host_access: super::HostAccess,
    /// Whether the device's shader division is IEEE (correctly rounded), as the CPU twin's is:
    /// lavapipe's (LLVM's fdiv; tests/traversal.rs holds it to 0 ulps). Elsewhere Vulkan allows
    /// 2.5 ulp, and the ray setup corrects its quotients (SPEC_CORRECT_DIVISION).
    pub divides_exactly: bool,
    /// True if it has a compute queue and Vulkan 1.2, so vkrt can use it.
    pub usable: bool,
}

fn cstr_field(raw: &[std::ffi::c_char]) -> String {
    let bytes: Vec<u8> = raw.iter().take_while(|&&c| c != 0).map(|&c| c as u8).collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

impl DeviceInfo {
    /// Reads the properties of `pd`.
    ///
    /// # Safety
    /// `pd` must come from `instance`, created for Vulkan 1.2 or later.
    pub unsafe fn query(instance: &ash::Instance, pd: vk::PhysicalDevice, index: usize) -> Self {
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver).push_next(&mut subgroup);
        instance.get_physical_device_properties2(pd, &mut props2);
        let p = props2.properties;
        let mem = instance.get_physical_device_memory_properties(pd);
        let device_local_bytes = mem.memory_heaps[..mem.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0);
        let has_compute = instance.get_physical_device_queue_family_properties(pd).iter().any(|q| q.queue_flags.contains(vk::QueueFlags::COMPUTE));
        let api_ok = vk::api_version_major(p.api_version) > 1 || vk::api_version_minor(p.api_version) >= 2;
        Self {
            index,
            name: cstr_field(&p.device_name),
            device_type: p.device_type,
            api_version: p.api_version,
            driver_name: cstr_field(&driver.driver_name),
            driver_info: cstr_field(&driver.driver_info),
            driver_version: p.driver_version,
            driver_id: driver.driver_id,
            max_storage_buffer_range: p.limits.max_storage_buffer_range,
            max_texel_buffer_elements: p.limits.max_texel_buffer_elements,
            max_workgroup_size: p.limits.max_compute_work_group_size,
            max_workgroup_invocations: p.limits.max_compute_work_group_invocations,
            subgroup_size: subgroup.subgroup_size,
            max_push_constants_size: p.limits.max_push_constants_size,
            device_local_bytes,
            host_access: super::HostAccess::detect(&mem),
            divides_exactly: driver.driver_id == vk::DriverId::MESA_LLVMPIPE,
            usable: has_compute && api_ok,
        }
    }

    pub fn type_name(&self) -> &'static str {
        match self.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other",
        }
    }

    /// Preference when no device is named: discrete, integrated, virtual, CPU (lavapipe), other.
    pub fn default_rank(&self) -> u32 {
        match self.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        }
    }
}

impl fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = self.api_version;
        writeln!(
            f,
            "[{}] {} ({}){}",
            self.index,
            self.name,
            self.type_name(),
            if self.usable { "" } else { " - not usable: needs Vulkan 1.2 and a compute queue" }
        )?;
        writeln!(
            f,
            "    Vulkan {}.{}.{}, driver {} {}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v),
            self.driver_name,
            self.driver_info
        )?;
        writeln!(f, "    max storage buffer range: {} MiB", self.max_storage_buffer_range / (1024 * 1024))?;
        writeln!(f, "    max texel buffer elements: {}", self.max_texel_buffer_elements)?;
        writeln!(f, "    max workgroup size: {:?}, max invocations: {}", self.max_workgroup_size, self.max_workgroup_invocations)?;
        writeln!(f, "    subgroup size: {}", self.subgroup_size)?;
        writeln!(f, "    max push constants: {} bytes", self.max_push_constants_size)?;
        writeln!(f, "    largest device-local heap: {} MiB", self.device_local_bytes / (1024 * 1024))?;
        writeln!(f, "    memory: {}", self.host_access.name())?;
        let wg = super::Workgroups::for_device(self);
        write!(f, "    vkrt workgroups: {}x{} (images, in tiles of {}²), {} (ray batches)", wg.x, wg.y, wg.tile, wg.d1)
    }
}
