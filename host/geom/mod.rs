//! Geometry values everything else is built on: axis-aligned boxes, 2D Morton codes. No
//! scene, BVH or GPU format knowledge lives here, so every other module may use it.

pub mod aabb;
pub mod morton;
pub mod simd_aabb;

pub use aabb::Aabb;
pub use simd_aabb::SimdAabb;
