//! Vulkan through ash: instance and device choice ([`context`]), buffers ([`buffer`]), one-shot
//! command submission ([`commands`]). Headless, compute only, core Vulkan 1.2.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod device_info;

pub use buffer::{Buffer, MemoryLocation, TexelView};
pub use context::{Context, ContextOptions, Validation};
pub use device_info::DeviceInfo;
