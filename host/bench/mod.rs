//! Instruments for comparing BVH builders and layouts: ray sets, the `vkrt trace` batch query
//! command, the `vkrt bvh` builder x layout table, and traversal heat maps.

pub mod bvh_table;
pub mod heatmap;
pub mod rays;
pub mod trace_cmd;
