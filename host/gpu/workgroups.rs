//! The compute workgroup shape vkrt uses on a device, chosen from what the device reports
//! rather than assumed: GPUs run subgroups of 8 to 128 lanes (lavapipe 8, or 16 with
//! LP_NATIVE_VECTOR_WIDTH=512; NVIDIA 32; AMD 32 or 64; some 128), and a workgroup smaller
//! than a subgroup leaves lanes idle. The shape only decides how pixels and rays are grouped
//! for execution: which samples a pixel takes never depends on it, so images are the same on
//! every device (tests/subgroups.rs checks it across lavapipe's two widths). The tile size of
//! image submissions is chosen here too, by device type; images do not depend on it either.
//!
//! The shaders declare only the spec-constant ids (`local_size_x_id = SPEC_WORKGROUP_X`), no
//! literal defaults: with both, glslang + `spirv-opt -Os` output made Mesa 25 lavapipe hang
//! forever on feature-specialised pipelines (a two-triangle floor lit by a point light, Whitted
//! and path; found and isolated in docs/experiments/workgroup-spec-hang.md).

use super::DeviceInfo;

/// Workgroup sizes: image kernels run `x` by `y` invocations, 1D kernels `d1`; image
/// submissions cover `tile` x `tile` pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Workgroups {
    pub x: u32,
    pub y: u32,
    pub d1: u32,
    pub tile: u32,
}

/// Tile side on a CPU device (lavapipe): tiles of 64, 128 and 512 ran within noise of each
/// other (docs/experiments/tried-and-not-kept.md), and small ones keep a submission short, so
/// an interrupt or a time limit is met within one.
const CPU_TILE: u32 = 128;
/// Tile side on a GPU: 512² = 262k invocations per submission. A 128² tile is 16k, an eighth
/// of what an H100 keeps resident (132 SMs x 2048 threads), and each submission starts with a
/// barrier on the last. Bounded for watchdogs (about 2 s on desktop drivers): a path-traced
/// submission of 4 spp and at most ~16 rays per sample is 17M rays, under 0.2 s at the
/// 100M rays/s even a small GPU traces on 10M triangles.
const GPU_TILE: u32 = 512;

/// The fewest invocations per workgroup: 64, a multiple of every subgroup size up to 64.
const MIN_INVOCATIONS: u32 = 64;
/// Image workgroups are this wide: one coherence/adaptive block of 8 pixels per row.
const IMAGE_WIDTH: u32 = 8;

impl Workgroups {
    /// 8 wide and at least 64 invocations, and at least one whole subgroup, within the
    /// device's limits.
    pub fn for_device(info: &DeviceInfo) -> Self {
        let max = info.max_workgroup_invocations.max(1);
        let invocations = MIN_INVOCATIONS.max(info.subgroup_size.next_power_of_two()).min(max);
        let x = IMAGE_WIDTH.min(invocations).min(info.max_workgroup_size[0].max(1));
        let y = (invocations / x).clamp(1, info.max_workgroup_size[1].max(1));
        let d1 = invocations.min(info.max_workgroup_size[0].max(1));
        let tile = if info.device_type == ash::vk::PhysicalDeviceType::CPU { CPU_TILE } else { GPU_TILE };
        Self { x, y, d1, tile }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(subgroup_size: u32) -> DeviceInfo {
        DeviceInfo {
            index: 0,
            name: "test".into(),
            device_type: ash::vk::PhysicalDeviceType::OTHER,
            api_version: 0,
            driver_name: String::new(),
            driver_info: String::new(),
            driver_version: 0,
            driver_id: ash::vk::DriverId::default(),
            max_storage_buffer_range: 1 << 27,
            max_texel_buffer_elements: 1 << 27,
            max_workgroup_size: [1024, 1024, 64],
            max_workgroup_invocations: 1024,
            subgroup_size,
            max_push_constants_size: 128,
            device_local_bytes: 0,
            host_access: crate::gpu::HostAccess::Mapped,
            divides_exactly: true,
            usable: true,
        }
    }

    #[test]
    fn a_workgroup_holds_whole_subgroups() {
        for (sub, want) in [(8, (8, 8, 64)), (16, (8, 8, 64)), (32, (8, 8, 64)), (64, (8, 8, 64)), (128, (8, 16, 128))] {
            let w = Workgroups::for_device(&device(sub));
            assert_eq!((w.x, w.y, w.d1), want, "subgroup size {sub}");
            assert_eq!(w.x * w.y % sub, 0, "subgroup size {sub}: {w:?}");
            assert_eq!(w.tile, GPU_TILE);
        }
        let cpu = DeviceInfo { device_type: ash::vk::PhysicalDeviceType::CPU, ..device(8) };
        assert_eq!(Workgroups::for_device(&cpu).tile, CPU_TILE);
    }
}
