//! Compute pipelines built from the SPIR-V that host/build.rs compiled: the shader table
//! ([`variants`]), the embedded SPIR-V ([`shaders`]) and the pipeline object ([`compute`]).

pub mod compute;
pub mod shaders;
pub mod variants;

pub use compute::{BindingKind, ComputePipeline};
