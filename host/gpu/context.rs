//! The Vulkan instance, the chosen physical device, its logical device and compute queue.

use super::commands::Submissions;
use super::device_info::DeviceInfo;
use super::memory::{new_allocator, HostAccess};
use super::staging::Staging;
use anyhow::{anyhow, bail, Context as _, Result};
use ash::vk;
use gpu_allocator::vulkan::Allocator;
use std::ffi::{c_void, CStr};
use std::sync::Mutex;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Whether to turn on the Khronos validation layers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Validation {
    Off,
    /// On if the layer is installed (the tests use this: a message then fails the test).
    IfAvailable,
    /// On, or an error if the layer is missing.
    Required,
}

/// Where compute shaders are made as shader objects instead of pipelines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShaderObjectUse {
    /// Pipelines everywhere.
    Never,
    /// Shader objects where they are measured to pay: lavapipe, whose pipelines redo SPIR-V to
    /// NIR every run (docs/experiments/shader-binaries.md). A GPU driver keeps its own cache of
    /// compiled pipelines, and vkrt's shader-object path has not run on one yet.
    Auto,
    /// Shader objects wherever the device has them.
    Always,
}

/// How to create a [`Context`].
#[derive(Debug, Clone)]
pub struct ContextOptions {
    /// Device index or a case-insensitive part of its name; `None` picks the default
    /// (a discrete GPU if present, else the best other device, lavapipe on a GPU-less machine).
    pub device: Option<String>,
    pub validation: Option<Validation>,
    /// Reach device memory as another kind of device does, on any device (`VKRT_MEMORY`):
    /// `staged` (a discrete GPU without resizable BAR: every write and read through staging
    /// copies) or `mapped-writes` (one with it: writes in place, reads through staging).
    pub memory: Option<String>,
    /// Where to use compute shader objects (super::shader_objects) when the validation layers
    /// are off (`VKRT_SHADER_OBJECTS`: 0 never, 1 wherever the device has them; unset: auto).
    pub shader_objects: ShaderObjectUse,
    /// Where compiled shaders are kept between runs (with shader objects only); None: nowhere.
    pub shader_cache: Option<std::path::PathBuf>,
}

impl Default for ContextOptions {
    fn default() -> Self {
        Self { device: None, validation: None, memory: None, shader_objects: ShaderObjectUse::Auto, shader_cache: None }
    }
}

impl ContextOptions {
    /// Options from the environment: `VKRT_DEVICE`, `VKRT_VALIDATION` (0/1), `VKRT_MEMORY` and
    /// `VKRT_SHADER_OBJECTS` (0: pipelines only). No shader cache.
    pub fn from_env() -> Self {
        let device = std::env::var("VKRT_DEVICE").ok().filter(|s| !s.is_empty());
        let validation = match std::env::var("VKRT_VALIDATION").as_deref() {
            Ok("1") | Ok("on") | Ok("true") => Some(Validation::Required),
            Ok("0") | Ok("off") | Ok("false") => Some(Validation::Off),
            _ => None,
        };
        let memory = std::env::var("VKRT_MEMORY").ok().filter(|s| !s.is_empty());
        let shader_objects = match std::env::var("VKRT_SHADER_OBJECTS").as_deref() {
            Ok("0") | Ok("off") | Ok("false") => ShaderObjectUse::Never,
            Ok("1") | Ok("on") | Ok("true") => ShaderObjectUse::Always,
            _ => ShaderObjectUse::Auto,
        };
        Self { device, validation, memory, shader_objects, shader_cache: None }
    }
}

/// Owns the instance, device and queue; everything else borrows it.
pub struct Context {
    _entry: ash::Entry,
    pub instance: ash::Instance,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Validation messages collected by the debug callback (kept boxed: the callback holds a
    /// pointer to it).
    messages: Box<Mutex<Vec<String>>>,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub command_pool: vk::CommandPool,
    pub memory: vk::PhysicalDeviceMemoryProperties,
    pub info: DeviceInfo,
    /// The workgroup shape pipelines are specialised to on this device.
    pub workgroups: super::Workgroups,
    /// How the host reaches device buffers.
    pub host_access: HostAccess,
    /// Buffer memory; `None` only while the context is dropped.
    pub(super) allocator: Mutex<Option<Allocator>>,
    pub(super) staging: Mutex<Staging>,
    pub(super) submissions: Mutex<Submissions>,
    /// Bytes copied through staging so far ([`Context::staged_bytes`]).
    pub(super) staged_bytes: std::sync::atomic::AtomicU64,
    pub validation_enabled: bool,
    /// Compute shader objects, when the device has them and the options allow
    /// (`ContextOptions::shader_objects`, validation off); None: pipelines.
    pub shader_objects: Option<super::shader_objects::ShaderObjects>,
    /// `ContextOptions::shader_cache`.
    pub shader_cache: Option<std::path::PathBuf>,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if severity.intersects(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        let text = if data.is_null() || (*data).p_message.is_null() {
            String::from("(no message)")
        } else {
            CStr::from_ptr((*data).p_message).to_string_lossy().into_owned()
        };
        eprintln!("vulkan validation: {text}");
        if let Some(store) = (user as *const Mutex<Vec<String>>).as_ref() {
            if let Ok(mut v) = store.lock() {
                v.push(text);
            }
        }
    }
    vk::FALSE
}

/// The Vulkan loader, loaded once per process and never unloaded, with one instance that is
/// never destroyed (see [`load_entry`]).
static ENTRY: std::sync::OnceLock<ash::Entry> = std::sync::OnceLock::new();

/// Held while an instance or device is created or destroyed. NVIDIA's Linux driver is reported
/// to race in concurrent vkCreateInstance / vkCreateDevice (SIGSEGV in parallel tests:
/// gfx-rs/wgpu#5930, kvark/blade#336). The crash seen here on an H200 was another one (the
/// driver unloaded under a live thread, see [`load_entry`]), but the calls are rare and short,
/// so they take turns.
static LIFECYCLE: Mutex<()> = Mutex::new(());

/// Takes the [`LIFECYCLE`] turn (a panic elsewhere while holding it leaves nothing half-made
/// that matters here, so a poisoned lock is taken as is).
fn lifecycle_turn() -> std::sync::MutexGuard<'static, ()> {
    LIFECYCLE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Loads the Vulkan loader (once; callers hold the [`LIFECYCLE`] turn), or explains how to
/// install it. The first load also creates an instance that is never destroyed, so that the
/// loader keeps the drivers loaded for the life of the process: NVIDIA's leaves a destructor
/// in each thread that called it, which runs when the thread exits, and once the last context
/// was dropped the loader had unloaded the driver under it. On an H200 every run of
/// `tests/progressive.rs` with two test threads (a thread per test, exiting after its context)
/// then died of SIGSEGV in a thread-exit destructor at an address of no loaded library; with
/// one thread (tests on the main thread, which exits with the process) none did.
fn load_entry() -> Result<ash::Entry> {
    if let Some(entry) = ENTRY.get() {
        return Ok(entry.clone());
    }
    // SAFETY: loading the system's Vulkan loader library; no other code runs during it.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| {
        anyhow!("could not load the Vulkan loader (libvulkan.so.1): {e}. Install it and a driver: run `tools/ensure-deps.sh` as root (Debian: libvulkan1, mesa-vulkan-drivers)")
    })?;
    // Kept, not destroyed (ash::Instance has no Drop). Without a driver this fails, and the
    // caller's own vkCreateInstance then reports why.
    let _keeper = create_instance(&entry, false);
    Ok(ENTRY.get_or_init(|| entry).clone())
}

fn create_instance(entry: &ash::Entry, validation: bool) -> Result<ash::Instance> {
    let app = vk::ApplicationInfo::default().application_name(c"vkrt").engine_name(c"vkrt").api_version(vk::API_VERSION_1_2);
    let layers = [VALIDATION_LAYER.as_ptr()];
    let extensions = [ash::ext::debug_utils::NAME.as_ptr(), ash::ext::validation_features::NAME.as_ptr()];
    // Synchronization validation too: it reports missing barriers between submissions and
    // between the host and the device, the hazards a discrete GPU would turn into wrong pixels.
    let enabled = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled);
    let mut info = vk::InstanceCreateInfo::default().application_info(&app);
    if validation {
        info = info.enabled_layer_names(&layers).enabled_extension_names(&extensions).push_next(&mut features);
    }
    // SAFETY: the create info and everything it points to live until the call returns.
    unsafe { entry.create_instance(&info, None) }.context("vkCreateInstance")
}

fn layer_available(entry: &ash::Entry, name: &CStr) -> bool {
    // SAFETY: plain enumeration call.
    unsafe { entry.enumerate_instance_layer_properties() }
        .map(|layers| layers.iter().any(|l| l.layer_name_as_c_str().map(|n| n == name).unwrap_or(false)))
        .unwrap_or(false)
}

/// Every physical device the loader reports, with its properties.
pub fn list_devices() -> Result<Vec<DeviceInfo>> {
    let _turn = lifecycle_turn();
    let entry = load_entry()?;
    let instance = create_instance(&entry, false)?;
    // SAFETY: the instance is valid and destroyed right after use.
    let result = unsafe {
        instance
            .enumerate_physical_devices()
            .context("vkEnumeratePhysicalDevices")
            .map(|pds| pds.iter().enumerate().map(|(i, &pd)| DeviceInfo::query(&instance, pd, i)).collect())
    };
    unsafe { instance.destroy_instance(None) };
    result
}

/// The access a context uses: the device's own, or the forced one (`MappedWrites` or `Staged`,
/// [`HostAccess::from_name`]) where the device can do it: memory that is not host-visible
/// cannot be mapped, whatever is asked.
fn effective_access(own: HostAccess, forced: Option<HostAccess>) -> HostAccess {
    match forced {
        Some(f) if own != HostAccess::Staged => f,
        _ => own,
    }
}

/// Picks a device from `infos`: by index or name part if `wanted` is given, else the default:
/// the kind first ([`DeviceInfo::default_rank`]: a discrete GPU before an integrated one before
/// a CPU), then among devices of one kind the one that holds the largest scenes (the most
/// texel-buffer elements, where vkrt keeps its BVH and shading arrays), then the first listed. So
/// with both of Debian's CPU implementations installed the default is lavapipe (2^27 texels)
/// over SwiftShader (2^16: no scene of more than a few thousand triangles fits), which
/// `--device swiftshader` still picks by name.
pub fn choose_device(infos: &[DeviceInfo], wanted: Option<&str>) -> Result<usize> {
    let usable: Vec<&DeviceInfo> = infos.iter().filter(|d| d.usable).collect();
    if usable.is_empty() {
        bail!("no usable Vulkan device (found {}). On a machine without a GPU install Mesa's lavapipe: run `tools/ensure-deps.sh` as root", infos.len());
    }
    match wanted {
        Some(w) => {
            let found = if let Ok(i) = w.parse::<usize>() {
                infos.iter().find(|d| d.index == i)
            } else {
                let lw = w.to_lowercase();
                infos.iter().find(|d| d.name.to_lowercase().contains(&lw))
            };
            let names: Vec<String> = infos.iter().map(|d| format!("[{}] {}", d.index, d.name)).collect();
            match found {
                Some(d) if d.usable => Ok(d.index),
                Some(d) => bail!("device '{w}' ({}) is not usable: it needs Vulkan 1.2 and a compute queue", d.name),
                None => bail!("no Vulkan device matches '{w}'; devices: {}", names.join(", ")),
            }
        }
        None => Ok(usable.iter().min_by_key(|d| (d.default_rank(), std::cmp::Reverse(d.max_texel_buffer_elements), d.index)).map(|d| d.index).unwrap_or(0)),
    }
}

impl Context {
    pub fn new(options: &ContextOptions) -> Result<Self> {
        let forced = match options.memory.as_deref() {
            None => None,
            Some(name) => Some(
                HostAccess::from_name(name)
                    .ok_or_else(|| anyhow!("VKRT_MEMORY='{name}': expected 'mapped-writes' or 'staged' (or unset: the device's own way)"))?,
            ),
        };
        let _turn = lifecycle_turn();
        let entry = load_entry()?;
        let validation_mode = options.validation.unwrap_or(Validation::Off);
        let have_layer = layer_available(&entry, VALIDATION_LAYER);
        let validation = match validation_mode {
            Validation::Off => false,
            Validation::IfAvailable => have_layer,
            Validation::Required if !have_layer => {
                bail!("validation was asked for but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)")
            }
            Validation::Required => true,
        };
        let instance = create_instance(&entry, validation)?;
        let messages: Box<Mutex<Vec<String>>> = Box::new(Mutex::new(Vec::new()));
        let mut ctx_debug = None;
        if validation {
            let du = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(debug_callback))
                .user_data(&*messages as *const Mutex<Vec<String>> as *mut c_void);
            // SAFETY: `messages` is boxed and outlives the messenger (destroyed first in Drop).
            let messenger = unsafe { du.create_debug_utils_messenger(&info, None) }.context("vkCreateDebugUtilsMessengerEXT")?;
            ctx_debug = Some((du, messenger));
        }
        // From here on, failures must destroy what was created: build the rest in a closure.
        let made = unsafe { Self::create_device(&instance, options, if validation { ShaderObjectUse::Never } else { options.shader_objects }) };
        match made {
            Ok((physical, device, queue, queue_family, command_pool, memory, info, allocator, submissions, binary)) => Ok(Self {
                shader_objects: binary.map(|(binary_uuid, binary_version)| super::shader_objects::ShaderObjects {
                    fns: ash::ext::shader_object::Device::new(&instance, &device),
                    binary_uuid,
                    binary_version,
                }),
                shader_cache: options.shader_cache.clone(),
                _entry: entry,
                instance,
                debug: ctx_debug,
                messages,
                physical,
                device,
                queue,
                queue_family,
                command_pool,
                memory,
                workgroups: super::Workgroups::for_device(&info),
                host_access: effective_access(info.host_access, forced),
                allocator: Mutex::new(Some(allocator)),
                staging: Mutex::new(Staging::default()),
                submissions: Mutex::new(submissions),
                staged_bytes: 0.into(),
                info,
                validation_enabled: validation,
            }),
            Err(e) => {
                unsafe {
                    if let Some((du, m)) = ctx_debug {
                        du.destroy_debug_utils_messenger(m, None);
                    }
                    instance.destroy_instance(None);
                }
                Err(e)
            }
        }
    }

    #[allow(clippy::type_complexity)]
    unsafe fn create_device(
        instance: &ash::Instance,
        options: &ContextOptions,
        shader_objects: ShaderObjectUse,
    ) -> Result<(
        vk::PhysicalDevice,
        ash::Device,
        vk::Queue,
        u32,
        vk::CommandPool,
        vk::PhysicalDeviceMemoryProperties,
        DeviceInfo,
        Allocator,
        Submissions,
        Option<([u8; vk::UUID_SIZE], u32)>,
    )> {
        let pds = instance.enumerate_physical_devices().context("vkEnumeratePhysicalDevices")?;
        let infos: Vec<DeviceInfo> = pds.iter().enumerate().map(|(i, &pd)| DeviceInfo::query(instance, pd, i)).collect();
        let index = choose_device(&infos, options.device.as_deref())?;
        let physical = pds[index];
        let info = infos[index].clone();
        let families = instance.get_physical_device_queue_family_properties(physical);
        // Prefer a compute queue without graphics (an async compute queue) if there is one.
        let queue_family = families
            .iter()
            .enumerate()
            .filter(|(_, q)| q.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .min_by_key(|(_, q)| q.queue_flags.contains(vk::QueueFlags::GRAPHICS))
            .map(|(i, _)| i as u32)
            .ok_or_else(|| anyhow!("device {} has no compute queue", info.name))?;
        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let wanted = match shader_objects {
            ShaderObjectUse::Never => false,
            ShaderObjectUse::Auto => info.driver_id == vk::DriverId::MESA_LLVMPIPE,
            ShaderObjectUse::Always => true,
        };
        let binary = if wanted { super::shader_objects::supported(instance, physical) } else { None };
        let extensions = super::shader_objects::EXTENSIONS.map(|n| n.as_ptr());
        let mut feature = vk::PhysicalDeviceShaderObjectFeaturesEXT::default().shader_object(true);
        let mut device_info = vk::DeviceCreateInfo::default().queue_create_infos(&queue_info);
        if binary.is_some() {
            device_info = device_info.enabled_extension_names(&extensions).push_next(&mut feature);
        }
        let device = instance.create_device(physical, &device_info, None).with_context(|| format!("vkCreateDevice on {}", info.name))?;
        let queue = device.get_device_queue(queue_family, 0);
        let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(queue_family).flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let command_pool = match device.create_command_pool(&pool_info, None) {
            Ok(p) => p,
            Err(e) => {
                device.destroy_device(None);
                return Err(anyhow!("vkCreateCommandPool: {e}"));
            }
        };
        let memory = instance.get_physical_device_memory_properties(physical);
        let rest = new_allocator(instance, &device, physical).and_then(|a| Ok((a, Submissions::new(&device, command_pool)?)));
        match rest {
            Ok((allocator, submissions)) => Ok((physical, device, queue, queue_family, command_pool, memory, info, allocator, submissions, binary)),
            Err(e) => {
                // The pool's destruction frees its command buffers (Submissions::new destroys
                // its own fences when it fails).
                device.destroy_command_pool(command_pool, None);
                device.destroy_device(None);
                Err(e)
            }
        }
    }

    /// Validation messages (warnings and errors) seen so far.
    pub fn validation_messages(&self) -> Vec<String> {
        self.messages.lock().map(|v| v.clone()).unwrap_or_default()
    }

    /// Fails if the validation layers reported anything.
    pub fn check_validation(&self) -> Result<()> {
        let m = self.validation_messages();
        if m.is_empty() {
            Ok(())
        } else {
            bail!("{} Vulkan validation message(s); first: {}", m.len(), m[0])
        }
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        let _turn = lifecycle_turn();
        // SAFETY: every object made from the device is owned by something that borrows this
        // context, so it is gone by now; wait for the queue, then destroy in reverse order.
        unsafe {
            let _ = self.device.device_wait_idle();
            if let Ok(ring) = self.submissions.get_mut() {
                ring.destroy(&self.device);
            }
            if let (Ok(staging), Ok(allocator)) = (self.staging.get_mut(), self.allocator.get_mut()) {
                if let Some(a) = allocator.as_mut() {
                    staging.destroy(&self.device, a);
                }
            }
            // The allocator frees its memory blocks on drop, while the device still exists.
            if let Ok(allocator) = self.allocator.get_mut() {
                drop(allocator.take());
            }
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
            if let Some((du, m)) = self.debug.take() {
                du.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(index: usize, name: &str, device_type: vk::PhysicalDeviceType, texels: u32) -> DeviceInfo {
        DeviceInfo {
            index,
            name: name.into(),
            device_type,
            api_version: vk::API_VERSION_1_3,
            driver_name: String::new(),
            driver_info: String::new(),
            driver_version: 0,
            driver_id: vk::DriverId::default(),
            max_storage_buffer_range: 1 << 27,
            max_texel_buffer_elements: texels,
            max_workgroup_size: [256, 256, 64],
            max_workgroup_invocations: 256,
            subgroup_size: 4,
            max_push_constants_size: 128,
            device_local_bytes: 0,
            host_access: HostAccess::Mapped,
            divides_exactly: false,
            usable: true,
        }
    }

    /// SwiftShader listed first (as the loader lists it) does not win the default over lavapipe;
    /// a GPU wins over both; a name picks any of them.
    #[test]
    fn the_default_is_the_gpu_else_the_cpu_device_that_holds_the_largest_scenes() {
        let cpu = vk::PhysicalDeviceType::CPU;
        let both = [device(0, "SwiftShader Device (Subzero)", cpu, 1 << 16), device(1, "llvmpipe (LLVM 15.0.6, 256 bits)", cpu, 1 << 27)];
        assert_eq!(choose_device(&both, None).unwrap(), 1);
        assert_eq!(choose_device(&both, Some("swiftshader")).unwrap(), 0);
        let with_gpu = [both[0].clone(), both[1].clone(), device(2, "NVIDIA H100", vk::PhysicalDeviceType::DISCRETE_GPU, 1 << 27)];
        assert_eq!(choose_device(&with_gpu, None).unwrap(), 2);
        let same = [device(0, "a", cpu, 1 << 20), device(1, "b", cpu, 1 << 20)];
        assert_eq!(choose_device(&same, None).unwrap(), 0, "a tie goes to the first listed");
    }
}
