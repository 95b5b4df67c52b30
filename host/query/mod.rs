//! Batch ray queries without rendering: the GPU engine ([`ray_query`]) of `vkrt trace`, `vkrt
//! bvh` and the GPU end of the agreement tests, the order rays are traced in ([`ray_order`]),
//! and the ray sets the comparisons use ([`rays`]).

pub mod ray_order;
pub mod ray_query;
pub mod rays;

pub use ray_order::RayOrder;
pub use ray_query::{trace_rays, RayQuery};
