//! SAH cost (placeholder).
