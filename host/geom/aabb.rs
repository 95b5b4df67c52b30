//! Axis-aligned bounding boxes: the box type of scenes, BVH nodes and reports.

use glam::Vec3;

/// An axis-aligned box. The empty box has min = +inf, max = -inf so that `union` needs no branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3::splat(f32::INFINITY), max: Vec3::splat(f32::NEG_INFINITY) };

    pub fn from_points(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.grow(p))
    }
    pub fn grow(&self, p: Vec3) -> Self {
        Self { min: self.min.min(p), max: self.max.max(p) }
    }
    pub fn union(&self, o: &Aabb) -> Self {
        Self { min: self.min.min(o.min), max: self.max.max(o.max) }
    }
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }
    pub fn extent(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
    /// Surface area; 0 for an empty box.
    pub fn area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
    /// The axis (0, 1, 2) along which the box is widest.
    pub fn widest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }
    /// True if `o` lies inside this box (boundaries included).
    pub fn contains(&self, o: &Aabb) -> bool {
        o.is_empty() || (self.min.cmple(o.min).all() && self.max.cmpge(o.max).all())
    }
}
