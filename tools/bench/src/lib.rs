//! What vkrt's benchmark tools share: argument helpers, and the generated test scenes of the
//! test suite (`tests/common`), included by path so that they stay out of the renderer.

pub mod args;

#[path = "../../../tests/common/closed_meshes.rs"]
pub mod closed_meshes;

#[path = "../../../tests/common/procedural.rs"]
pub mod procedural;
