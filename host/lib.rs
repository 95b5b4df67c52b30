//! vkrt: a GPU-agnostic ray and path tracer written as Vulkan compute shaders.
//!
//! Data flows one way (docs/ARCHITECTURE.md has the picture and what each module may import):
//! a command ([`cli`]) loads a [`scene`]; [`prepare`] builds its BVH ([`bvh`], over [`geom`]
//! boxes), lays it out ([`accel`]) in the formats of [`gpu_abi`], fills the shading arrays and
//! uploads everything through [`gpu`]; an [`integrator`] (or a batch [`query`]) runs the
//! [`pipeline`]'s shaders in short batches; [`output`] writes the image.

pub mod accel;
pub mod bvh;
pub mod bytes;
pub mod cli;
pub mod error;
pub mod files;
pub mod geom;
pub mod gpu;
pub mod gpu_abi;
pub mod integrator;
pub mod output;
pub mod pipeline;
pub mod prepare;
pub mod query;
pub mod rng;
pub mod scene;
