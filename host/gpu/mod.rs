//! Vulkan through ash: instance and device choice ([`context`]), buffers ([`buffer`]), arrays
//! the shaders read as texels ([`texel_array`]), one-shot command submission ([`commands`]).
//! Headless, compute only, core Vulkan 1.2.

pub mod buffer;
pub mod commands;
pub mod context;
pub mod device_info;
pub mod texel_array;

pub use buffer::{Buffer, MemoryLocation, TexelFormat, TexelView};
pub use texel_array::TexelArray;
pub use context::{Context, ContextOptions, Validation};
pub use device_info::DeviceInfo;
