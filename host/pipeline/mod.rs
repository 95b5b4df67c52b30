//! Compute pipelines built from the SPIR-V that host/build.rs compiled: the shader table
//! ([`variants`]), the embedded SPIR-V ([`shaders`]), the pipeline object ([`compute`]) and the
//! compiled shaders kept between runs ([`shader_cache`]).

pub mod compute;
pub mod shader_cache;
pub mod shaders;
pub mod variants;

pub use compute::{BindingKind, ComputePipeline, ShaderOrigin};
