//! GPU-visible structs (placeholder).
pub mod constants;
