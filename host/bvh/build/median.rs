//! Median-split builder (placeholder until implemented).
use crate::bvh::{Aabb, BuildConfig, Bvh};
pub fn build(_boxes: &[Aabb], _centroids: &[glam::Vec3], _config: &BuildConfig) -> Bvh { todo!() }
