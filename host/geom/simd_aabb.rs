//! The box the BVH builders' hot loops use: [`super::Aabb`] in 16-byte SIMD lanes.
//!
//! `Vec3A` is SSE/NEON-backed, so a union is two SIMD min/max operations. The binned SAH
//! builder's binning loop, the hottest loop of a build, does three unions per primitive per
//! level, and the sweep builder's prefix sweeps are unions and areas only. Everything else
//! uses [`super::Aabb`] (plain `Vec3` corners, 24 bytes, what the rest of the code reads);
//! converting is free in both directions and loses nothing.

use super::Aabb;
use glam::Vec3A;

/// An axis-aligned box with SIMD-lane corners. Empty: min = +inf, max = -inf, so a union
/// needs no branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimdAabb {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl SimdAabb {
    pub const EMPTY: SimdAabb = SimdAabb { min: Vec3A::INFINITY, max: Vec3A::NEG_INFINITY };

    pub fn union(self, o: SimdAabb) -> SimdAabb {
        SimdAabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }
    pub fn grow(self, p: Vec3A) -> SimdAabb {
        SimdAabb { min: self.min.min(p), max: self.max.max(p) }
    }
    /// Surface area; 0 for the empty box (its negative extent is clamped away).
    pub fn area(self) -> f32 {
        let e = (self.max - self.min).max(Vec3A::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

impl From<Aabb> for SimdAabb {
    fn from(b: Aabb) -> Self {
        SimdAabb { min: b.min.into(), max: b.max.into() }
    }
}

impl From<SimdAabb> for Aabb {
    fn from(b: SimdAabb) -> Self {
        Aabb { min: b.min.into(), max: b.max.into() }
    }
}
