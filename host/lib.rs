//! vkrt: a GPU-agnostic ray and path tracer written as Vulkan compute shaders.
//!
//! Data flow (see `DESIGN.md`): a scene file becomes a [`scene::Scene`]; a builder in [`bvh::build`]
//! turns its triangle boxes into a [`bvh::Bvh`]; [`layout`] flattens that into the arrays the shaders
//! walk (with a CPU twin that walks the same arrays); [`gpu`] and [`pipeline`] drive Vulkan; an
//! [`integrator`] renders in short batches; [`output`] writes images.

pub mod bench;
pub mod bvh;
pub mod cli;
pub mod cli_path;
pub mod error;
pub mod gpu;
pub mod integrator;
pub mod layout;
pub mod output;
pub mod pipeline;
pub mod rng;
pub mod scene;
