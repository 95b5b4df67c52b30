//! Compute pipelines built from the SPIR-V that `host/build.rs` compiled.

pub mod compute;
pub mod shaders;
pub mod variants;

pub use compute::{BindingKind, ComputePipeline};
