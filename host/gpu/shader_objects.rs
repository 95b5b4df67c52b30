//! Compute shaders as shader objects (`VK_EXT_shader_object`, a multi-vendor extension) where a
//! device has them: unlike a pipeline, a shader object hands out its compiled form
//! (`vkGetShaderBinaryDataEXT`), which a later run can create it from. On lavapipe that skips
//! SPIR-V to NIR and NIR's passes, which its own disk cache does not: 0.13 of a cornell-measured
//! render's 0.14 s of pipeline creation (docs/experiments/shader-binaries.md). Optional, and by
//! default on lavapipe only (`ContextOptions::shader_objects`): GPUs, devices without the
//! extension, and runs with the validation layers (Debian 12's 1.3.239 layers predate the
//! extension and would report the device's creation and every dispatch) use pipelines.

use ash::vk;

/// The extension's functions on one device, and what a binary made there is valid for.
pub struct ShaderObjects {
    pub fns: ash::ext::shader_object::Device,
    /// `shaderBinaryUUID` and `shaderBinaryVersion`: a binary from another device, driver or
    /// driver version is refused, so they belong in the key a binary is kept under.
    pub binary_uuid: [u8; vk::UUID_SIZE],
    pub binary_version: u32,
}

/// The extensions a device must list for compute shader objects: the extension itself and the
/// one it depends on besides Vulkan 1.2 (dynamic rendering, core only from 1.3, which vkrt's
/// instance does not ask for).
pub const EXTENSIONS: [&std::ffi::CStr; 2] = [ash::ext::shader_object::NAME, ash::khr::dynamic_rendering::NAME];

/// `shaderBinaryUUID` and `shaderBinaryVersion` of `pd` if it lists [`EXTENSIONS`] and has the
/// `shaderObject` feature; None otherwise.
///
/// # Safety
/// `pd` must come from `instance`, created for Vulkan 1.2 or later.
pub unsafe fn supported(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<([u8; vk::UUID_SIZE], u32)> {
    let listed = instance.enumerate_device_extension_properties(pd).ok()?;
    let has = |name: &std::ffi::CStr| listed.iter().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name));
    if !EXTENSIONS.iter().all(|&n| has(n)) {
        return None;
    }
    let mut feature = vk::PhysicalDeviceShaderObjectFeaturesEXT::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut feature);
    instance.get_physical_device_features2(pd, &mut features);
    if feature.shader_object == vk::FALSE {
        return None;
    }
    let mut props = vk::PhysicalDeviceShaderObjectPropertiesEXT::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut props);
    instance.get_physical_device_properties2(pd, &mut props2);
    Some((props.shader_binary_uuid, props.shader_binary_version))
}
