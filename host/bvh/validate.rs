//! BVH invariants (placeholder).
