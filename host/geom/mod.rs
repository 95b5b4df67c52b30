//! Geometry values everything else is built on: axis-aligned boxes. No scene, BVH or GPU
//! format knowledge lives here, so every other module may use it.

pub mod aabb;
pub mod simd_aabb;

pub use aabb::Aabb;
pub use simd_aabb::SimdAabb;
