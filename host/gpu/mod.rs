//! Vulkan through ash: instance and device choice ([`context`]), memory and how the host
//! reaches it ([`memory`], [`staging`]), buffers ([`buffer`]), arrays the shaders read as
//! texels ([`texel_array`]), submissions kept in flight ([`commands`]), device-side timing
//! ([`timer`]), the workgroup shape ([`workgroups`]), compute shader objects where a device has
//! them ([`shader_objects`]). Headless, compute only, core Vulkan 1.2.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod device_info;
pub mod memory;
pub mod shader_objects;
pub mod staging;
pub mod texel_array;
pub mod timer;
pub mod workgroups;

pub use buffer::{Buffer, TexelFormat, TexelView};
pub use commands::{Ticket, IN_FLIGHT};
pub use context::{Context, ContextOptions, ShaderObjectUse, Validation};
pub use device_info::DeviceInfo;
pub use memory::{HostAccess, MemoryLocation};
pub use texel_array::TexelArray;
pub use timer::GpuTimer;
pub use workgroups::Workgroups;
