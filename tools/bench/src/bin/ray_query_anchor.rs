//! The driver's own ray tracing as an anchor for vkrt's traversal (issue 46, item 2): the same
//! rays as `vkrt trace`, through `VK_KHR_ray_query` in a compute shader, over a BVH that the
//! Vulkan driver builds and walks itself (on lavapipe: Mesa's common BVH builder and its NIR
//! traversal). A benchmark, not part of the renderer: vkrt keeps its own CPU-built BVH and
//! stackless walk, as its design requires. `tools/embree_compare.py --ray-query` runs it beside
//! `vkrt trace` and Embree on the same `.npy` rays.
//!
//! Usage: vkrt-ray-query SCENE RAYS.npy [--out HITS.npy] [--rounds R]
//! Prints the build time and size of the driver's acceleration structures, and rays/s (best of
//! R rounds) over the dispatch alone and over upload, dispatch and read-back (what `vkrt trace`
//! prints). `--out` writes the hits in `vkrt trace`'s format (t, prim, u, v; misses t = +inf,
//! prim = 0xFFFFFFFF), so that the tools can compare hit triangles. Triangle ids are vkrt's
//! (its loaders' order). `VKRT_DEVICE` picks the device by a part of its name.

use anyhow::{anyhow, bail, Context as _, Result};
use ash::vk;
use std::ffi::{c_char, CStr};
use std::path::{Path, PathBuf};
use std::time::Instant;
use vkrt::gpu_abi::{GpuHit, GpuRay};
use vkrt::output::npy::{HitWriter, RayReader};

/// Invocations per workgroup: vkrt's own for ray batches on lavapipe (`vkrt info`).
const WORKGROUP: u32 = 64;
/// Workgroups per dispatch at most (the least `maxComputeWorkGroupCount[0]` Vulkan allows).
const MAX_GROUPS: u32 = 65_535;
/// Rays of the untimed first dispatch (pipeline and first-run costs stay out of the timing, as
/// `vkrt trace`'s warm-up keeps them out of its rays/s).
const WARM_UP_RAYS: usize = 1024;

const SHADER: &str = r#"#version 460
#extension GL_EXT_ray_query : require
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
struct Ray { vec4 origin_tmin; vec4 direction_tmax; };
struct Hit { float t; uint prim; float u; float v; };
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Hits { Hit hits[]; };
layout(push_constant) uniform Push { uint base; uint count; } push;
void main() {
    uint i = push.base + gl_GlobalInvocationID.x;
    if (i >= push.count) return;
    Ray r = rays[i];
    // vkrt's files say +inf for an unbounded ray; the largest float is the same ray here.
    float tmax = min(r.direction_tmax.w, 3.4028235e38);
    rayQueryEXT q;
    rayQueryInitializeEXT(q, scene, gl_RayFlagsOpaqueEXT, 0xFF, r.origin_tmin.xyz, r.origin_tmin.w,
                          r.direction_tmax.xyz, tmax);
    while (rayQueryProceedEXT(q)) {}
    Hit h = Hit(1.0 / 0.0, 0xFFFFFFFFu, 0.0, 0.0);
    if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
        vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, true);
        h = Hit(rayQueryGetIntersectionTEXT(q, true), uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true)), b.x, b.y);
    }
    hits[i] = h;
}
"#;

struct Args {
    scene: PathBuf,
    rays: PathBuf,
    out: Option<PathBuf>,
    rounds: usize,
}

fn parse_args() -> Result<Option<Args>> {
    let usage = "usage: vkrt-ray-query SCENE RAYS.npy [--out HITS.npy] [--rounds R]";
    let mut positional = Vec::new();
    let (mut out, mut rounds) = (None, 3usize);
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "-h" | "--help" => {
                println!("{usage}");
                return Ok(None);
            }
            "--out" => out = Some(PathBuf::from(it.next().ok_or_else(|| anyhow!("--out needs a path\n{usage}"))?)),
            "--rounds" => {
                let v = it.next().ok_or_else(|| anyhow!("--rounds needs a count\n{usage}"))?;
                rounds = v.parse::<usize>().with_context(|| format!("--rounds {v}: not a count"))?.max(1);
            }
            _ if a.starts_with("--") => bail!("unknown option {a}\n{usage}"),
            _ => positional.push(PathBuf::from(a)),
        }
    }
    match <[PathBuf; 2]>::try_from(positional) {
        Ok([scene, rays]) => Ok(Some(Args { scene, rays, out, rounds })),
        Err(_) => bail!("{usage}"),
    }
}

/// A buffer in host-visible, coherent memory, mapped for its whole life (all of lavapipe's
/// memory is; on a GPU this is slower than device memory, which only matters to the end-to-end
/// rate).
struct Buffer {
    buffer: vk::Buffer,
    memory: vk::DeviceMemory,
    ptr: *mut u8,
    size: u64,
    address: vk::DeviceAddress,
}

struct Device {
    _entry: ash::Entry,
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    device: ash::Device,
    accel: ash::khr::acceleration_structure::Device,
    queue: vk::Queue,
    pool: vk::CommandPool,
    name: String,
}

impl Device {
    fn new() -> Result<Self> {
        let entry = unsafe { ash::Entry::load() }.context("loading the Vulkan loader")?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_2);
        let instance =
            unsafe { entry.create_instance(&vk::InstanceCreateInfo::default().application_info(&app), None) }.context("creating a Vulkan instance")?;
        let wanted = std::env::var("VKRT_DEVICE").ok().map(|s| s.to_ascii_lowercase());
        let needed = [ash::khr::acceleration_structure::NAME, ash::khr::ray_query::NAME, ash::khr::deferred_host_operations::NAME];
        let mut chosen = None;
        for pd in unsafe { instance.enumerate_physical_devices() }.context("listing Vulkan devices")? {
            let props = unsafe { instance.get_physical_device_properties(pd) };
            let name = props.device_name_as_c_str().unwrap_or(c"?").to_string_lossy().into_owned();
            if wanted.as_ref().is_some_and(|w| !name.to_ascii_lowercase().contains(w.as_str())) {
                continue;
            }
            let exts = unsafe { instance.enumerate_device_extension_properties(pd) }?;
            let has = |n: &CStr| exts.iter().any(|e| e.extension_name_as_c_str() == Ok(n));
            if needed.iter().all(|n| has(n)) {
                chosen = Some((pd, name));
                break;
            }
        }
        let (physical, name) = chosen.ok_or_else(|| anyhow!("no Vulkan device with VK_KHR_ray_query and VK_KHR_acceleration_structure"))?;
        let family = unsafe { instance.get_physical_device_queue_family_properties(physical) }
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .ok_or_else(|| anyhow!("{name} has no compute queue"))? as u32;
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&priorities)];
        let ext_ptrs: Vec<*const c_char> = needed.iter().map(|n| n.as_ptr()).collect();
        let mut v12 = vk::PhysicalDeviceVulkan12Features::default().buffer_device_address(true);
        let mut accel_features = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
        let mut query_features = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&ext_ptrs)
            .push_next(&mut v12)
            .push_next(&mut accel_features)
            .push_next(&mut query_features);
        let device = unsafe { instance.create_device(physical, &info, None) }.with_context(|| format!("creating a ray-query device on {name}"))?;
        let accel = ash::khr::acceleration_structure::Device::new(&instance, &device);
        let queue = unsafe { device.get_device_queue(family, 0) };
        let pool = unsafe { device.create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None) }?;
        Ok(Self { _entry: entry, instance, physical, device, accel, queue, pool, name })
    }

    fn buffer(&self, size: u64, usage: vk::BufferUsageFlags) -> Result<Buffer> {
        let size = size.max(16);
        let usage = usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let buffer = unsafe { self.device.create_buffer(&vk::BufferCreateInfo::default().size(size).usage(usage), None) }?;
        let req = unsafe { self.device.get_buffer_memory_requirements(buffer) };
        let mem_props = unsafe { self.instance.get_physical_device_memory_properties(self.physical) };
        let flags = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let type_index = (0..mem_props.memory_type_count)
            .find(|&i| req.memory_type_bits & (1 << i) != 0 && mem_props.memory_types[i as usize].property_flags.contains(flags))
            .ok_or_else(|| anyhow!("{}: no host-visible coherent memory for a {size}-byte buffer", self.name))?;
        let mut address_flags = vk::MemoryAllocateFlagsInfo::default().flags(vk::MemoryAllocateFlags::DEVICE_ADDRESS);
        let alloc = vk::MemoryAllocateInfo::default().allocation_size(req.size).memory_type_index(type_index).push_next(&mut address_flags);
        let memory = unsafe { self.device.allocate_memory(&alloc, None) }.with_context(|| format!("allocating {size} bytes"))?;
        unsafe { self.device.bind_buffer_memory(buffer, memory, 0) }?;
        let ptr = unsafe { self.device.map_memory(memory, 0, vk::WHOLE_SIZE, vk::MemoryMapFlags::empty()) }? as *mut u8;
        let address = unsafe { self.device.get_buffer_device_address(&vk::BufferDeviceAddressInfo::default().buffer(buffer)) };
        Ok(Buffer { buffer, memory, ptr, size, address })
    }

    fn write<T: plain::Plain>(&self, buf: &Buffer, offset: u64, data: &[T]) {
        let bytes = std::mem::size_of_val(data);
        assert!(offset + bytes as u64 <= buf.size);
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr() as *const u8, buf.ptr.add(offset as usize), bytes) };
    }

    /// Records commands with `record`, submits them and waits; the seconds from submission to
    /// the fence.
    fn run(&self, record: impl FnOnce(vk::CommandBuffer)) -> Result<f64> {
        let info = vk::CommandBufferAllocateInfo::default().command_pool(self.pool).command_buffer_count(1);
        let cmd = unsafe { self.device.allocate_command_buffers(&info) }?[0];
        unsafe { self.device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default()) }?;
        record(cmd);
        unsafe { self.device.end_command_buffer(cmd) }?;
        let fence = unsafe { self.device.create_fence(&vk::FenceCreateInfo::default(), None) }?;
        let cmds = [cmd];
        let start = Instant::now();
        unsafe {
            self.device.queue_submit(self.queue, &[vk::SubmitInfo::default().command_buffers(&cmds)], fence)?;
            self.device.wait_for_fences(&[fence], true, u64::MAX)?;
        }
        let seconds = start.elapsed().as_secs_f64();
        unsafe {
            self.device.destroy_fence(fence, None);
            self.device.free_command_buffers(self.pool, &cmds);
        }
        Ok(seconds)
    }

    /// Builds one acceleration structure of `kind` over `geometry` (`count` primitives); returns
    /// it, its storage and the build's seconds.
    fn build(
        &self,
        kind: vk::AccelerationStructureTypeKHR,
        geometry: vk::AccelerationStructureGeometryKHR,
        count: u32,
    ) -> Result<(vk::AccelerationStructureKHR, Buffer, f64)> {
        let geometries = [geometry];
        let mut info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(kind)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        unsafe { self.accel.get_acceleration_structure_build_sizes(vk::AccelerationStructureBuildTypeKHR::DEVICE, &info, &[count], &mut sizes) };
        let storage = self.buffer(sizes.acceleration_structure_size, vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR)?;
        let scratch = self.buffer(sizes.build_scratch_size + 256, vk::BufferUsageFlags::STORAGE_BUFFER)?;
        let create = vk::AccelerationStructureCreateInfoKHR::default().buffer(storage.buffer).size(sizes.acceleration_structure_size).ty(kind);
        let handle = unsafe { self.accel.create_acceleration_structure(&create, None) }?;
        // Scratch must be aligned to minAccelerationStructureScratchOffsetAlignment (at most 256).
        info = info.dst_acceleration_structure(handle).scratch_data(vk::DeviceOrHostAddressKHR { device_address: (scratch.address + 255) & !255 });
        let range = [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count)];
        let seconds = self.run(|cmd| unsafe { self.accel.cmd_build_acceleration_structures(cmd, &[info], &[&range]) })?;
        self.free(scratch);
        Ok((handle, storage, seconds))
    }

    fn free(&self, b: Buffer) {
        unsafe {
            self.device.destroy_buffer(b.buffer, None);
            self.device.free_memory(b.memory, None);
        }
    }
}

/// Types that are plain bytes (no padding that matters, no pointers): what `Device::write` copies.
mod plain {
    pub trait Plain: Copy {}
    impl Plain for f32 {}
    impl Plain for vkrt::gpu_abi::GpuRay {}
    impl Plain for ash::vk::AccelerationStructureInstanceKHR {}
}

fn compile_shader() -> Result<Vec<u32>> {
    let dir = std::env::temp_dir().join(format!("vkrt-ray-query-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let src = dir.join("ray_query.comp");
    let spv = dir.join("ray_query.spv");
    std::fs::write(&src, SHADER).with_context(|| format!("writing {}", src.display()))?;
    let glslang = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    let out = std::process::Command::new(&glslang)
        .args(["-V", "--target-env", "vulkan1.2", "-o"])
        .arg(&spv)
        .arg(&src)
        .output()
        .with_context(|| format!("running {glslang} (Debian: glslang-tools)"))?;
    if !out.status.success() {
        bail!("{glslang} failed on the ray-query shader:\n{}", String::from_utf8_lossy(&out.stdout));
    }
    let bytes = std::fs::read(&spv).with_context(|| format!("reading {}", spv.display()))?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect())
}

fn read_rays(path: &Path) -> Result<Vec<GpuRay>> {
    let mut reader = RayReader::open(path)?;
    let n = usize::try_from(reader.count()).context("too many rays")?;
    reader.next_batch(n)
}

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

fn run() -> Result<()> {
    let Some(args) = parse_args()? else { return Ok(()) };
    let scene = vkrt::scene::load_scene(&args.scene)?;
    let rays = read_rays(&args.rays)?;
    let dev = Device::new()?;
    let d = &dev.device;

    // Unindexed triangles in vkrt's order: the primitive index the driver reports is vkrt's id.
    let positions: Vec<f32> = scene.triangles.iter().flat_map(|t| t.p.iter().flat_map(|p| p.to_array())).collect();
    let tri_count = u32::try_from(scene.triangles.len()).context("too many triangles")?;
    let vertices = dev.buffer(std::mem::size_of_val(positions.as_slice()) as u64, vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR)?;
    dev.write(&vertices, 0, &positions);
    let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
        .vertex_format(vk::Format::R32G32B32_SFLOAT)
        .vertex_data(vk::DeviceOrHostAddressConstKHR { device_address: vertices.address })
        .vertex_stride(12)
        .max_vertex(3 * tri_count.max(1) - 1)
        .index_type(vk::IndexType::NONE_KHR);
    let geometry = vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
        .flags(vk::GeometryFlagsKHR::OPAQUE);
    let (blas, blas_storage, blas_s) = dev.build(vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL, geometry, tri_count)?;
    let blas_address =
        unsafe { dev.accel.get_acceleration_structure_device_address(&vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(blas)) };
    let instance = vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR { matrix: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0] },
        instance_custom_index_and_mask: vk::Packed24_8::new(0, 0xFF),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
            0,
            vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE.as_raw() as u8,
        ),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR { device_handle: blas_address },
    };
    let instances =
        dev.buffer(std::mem::size_of::<vk::AccelerationStructureInstanceKHR>() as u64, vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR)?;
    dev.write(&instances, 0, &[instance]);
    let top =
        vk::AccelerationStructureGeometryKHR::default().geometry_type(vk::GeometryTypeKHR::INSTANCES).geometry(vk::AccelerationStructureGeometryDataKHR {
            instances: vk::AccelerationStructureGeometryInstancesDataKHR::default().data(vk::DeviceOrHostAddressConstKHR { device_address: instances.address }),
        });
    let (tlas, tlas_storage, tlas_s) = dev.build(vk::AccelerationStructureTypeKHR::TOP_LEVEL, top, 1)?;

    let n = rays.len();
    let ray_buf = dev.buffer((n.max(WARM_UP_RAYS) * 32) as u64, vk::BufferUsageFlags::STORAGE_BUFFER)?;
    let hit_buf = dev.buffer((n.max(WARM_UP_RAYS) * 16) as u64, vk::BufferUsageFlags::STORAGE_BUFFER)?;

    let bindings = [
        vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::COMPUTE),
        vk::DescriptorSetLayoutBinding::default()
            .binding(1)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::COMPUTE),
        vk::DescriptorSetLayoutBinding::default()
            .binding(2)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::COMPUTE),
    ];
    let set_layout = unsafe { d.create_descriptor_set_layout(&vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings), None) }?;
    let push_range = [vk::PushConstantRange::default().stage_flags(vk::ShaderStageFlags::COMPUTE).size(8)];
    let set_layouts = [set_layout];
    let layout =
        unsafe { d.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&push_range), None) }?;
    let code = compile_shader()?;
    let module = unsafe { d.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None) }?;
    let stage = vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::COMPUTE).module(module).name(c"main");
    let pipeline =
        unsafe { d.create_compute_pipelines(vk::PipelineCache::null(), &[vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout)], None) }
            .map_err(|(_, e)| anyhow!("creating the ray-query pipeline: {e}"))?[0];
    let sizes = [
        vk::DescriptorPoolSize::default().ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR).descriptor_count(1),
        vk::DescriptorPoolSize::default().ty(vk::DescriptorType::STORAGE_BUFFER).descriptor_count(2),
    ];
    let pool = unsafe { d.create_descriptor_pool(&vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes), None) }?;
    let set = unsafe { d.allocate_descriptor_sets(&vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&set_layouts)) }?[0];
    let tlases = [tlas];
    let mut as_write = vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(&tlases);
    let ray_info = [vk::DescriptorBufferInfo::default().buffer(ray_buf.buffer).range(vk::WHOLE_SIZE)];
    let hit_info = [vk::DescriptorBufferInfo::default().buffer(hit_buf.buffer).range(vk::WHOLE_SIZE)];
    let writes = [
        vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .descriptor_count(1)
            .push_next(&mut as_write),
        vk::WriteDescriptorSet::default().dst_set(set).dst_binding(1).descriptor_type(vk::DescriptorType::STORAGE_BUFFER).buffer_info(&ray_info),
        vk::WriteDescriptorSet::default().dst_set(set).dst_binding(2).descriptor_type(vk::DescriptorType::STORAGE_BUFFER).buffer_info(&hit_info),
    ];
    unsafe { d.update_descriptor_sets(&writes, &[]) };

    // Every dispatch of a trace in one submission, as `vkrt trace` submits a batch.
    let trace = |count: usize| -> Result<f64> {
        let count = u32::try_from(count).context("too many rays for one run")?;
        dev.run(|cmd| unsafe {
            d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
            d.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]);
            let per_dispatch = MAX_GROUPS * WORKGROUP;
            let mut base = 0u32;
            while base < count {
                let groups = (count - base).div_ceil(WORKGROUP).min(MAX_GROUPS);
                let push = [base, count];
                d.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::COMPUTE, 0, std::slice::from_raw_parts(push.as_ptr() as *const u8, 8));
                d.cmd_dispatch(cmd, groups, 1, 1);
                base = base.saturating_add(per_dispatch);
            }
        })
    };
    let warm: Vec<GpuRay> = (0..WARM_UP_RAYS).map(|_| GpuRay { origin: [0.0; 3], tmin: 0.0, direction: [0.0, 0.0, 1.0], tmax: 0.0 }).collect();
    dev.write(&ray_buf, 0, &warm);
    trace(WARM_UP_RAYS)?;

    let (mut best_dispatch, mut best_total) = (f64::INFINITY, f64::INFINITY);
    let miss = GpuHit { t: f32::INFINITY, prim: u32::MAX, u: 0.0, v: 0.0, nodes_visited: 0, tris_tested: 0, _pad0: 0, _pad1: 0 };
    let mut hits = vec![miss; n];
    for _ in 0..args.rounds {
        let start = Instant::now();
        dev.write(&ray_buf, 0, &rays);
        let dispatch = trace(n)?;
        for (i, h) in hits.iter_mut().enumerate() {
            let rec = unsafe { std::slice::from_raw_parts(hit_buf.ptr.add(16 * i) as *const u32, 4) };
            *h = GpuHit { t: f32::from_bits(rec[0]), prim: rec[1], u: f32::from_bits(rec[2]), v: f32::from_bits(rec[3]), ..miss };
        }
        best_total = best_total.min(start.elapsed().as_secs_f64());
        best_dispatch = best_dispatch.min(dispatch);
    }
    println!("device: {}", dev.name);
    println!(
        "acceleration structures: {} triangles, built in {:.3} s (bottom) + {:.3} s (top), {:.1} MiB",
        tri_count,
        blas_s,
        tlas_s,
        (blas_storage.size + tlas_storage.size) as f64 / (1 << 20) as f64
    );
    let misses = hits.iter().filter(|h| h.prim == u32::MAX).count();
    println!(
        "ray query: {} rays, {} missed: {:.4} M rays/s (traversal), {:.4} M rays/s (upload, traversal and read-back), best of {}",
        n,
        misses,
        n as f64 / best_dispatch / 1e6,
        n as f64 / best_total / 1e6,
        args.rounds
    );
    if let Some(out) = &args.out {
        let mut w = HitWriter::create(out, n as u64)?;
        w.write(&hits)?;
        w.finish()?;
    }
    unsafe {
        d.device_wait_idle()?;
        d.destroy_pipeline(pipeline, None);
        d.destroy_shader_module(module, None);
        d.destroy_pipeline_layout(layout, None);
        d.destroy_descriptor_pool(pool, None);
        d.destroy_descriptor_set_layout(set_layout, None);
        dev.accel.destroy_acceleration_structure(tlas, None);
        dev.accel.destroy_acceleration_structure(blas, None);
    }
    for b in [ray_buf, hit_buf, instances, vertices, blas_storage, tlas_storage] {
        dev.free(b);
    }
    unsafe {
        d.destroy_command_pool(dev.pool, None);
        d.destroy_device(None);
        dev.instance.destroy_instance(None);
    }
    Ok(())
}
