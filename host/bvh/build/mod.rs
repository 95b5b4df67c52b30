//! BVH builders, one per file. Each takes primitive boxes and centroids and a [`super::BuildConfig`].

pub mod binned_sah;
pub mod median;
pub mod reinsertion;
pub mod sweep_sah;
