//! The triangle list's walls: listed triangles whose plane has the whole scene on one side.
//!
//! Why: a shadow ray of the integrators runs between two points of the scene (a surface point
//! and a point on an emitter, a light vertex, a mirror point, or a point light's position),
//! each moved off its surface toward the side it is seen from. Both ends lie in the closed
//! half-space behind such a wall, and a segment between two points of a half-space can meet its
//! boundary plane only at an end, which the shadow ray's interval leaves out: a wall never
//! occludes one, and its test is wasted. In a Cornell box the ten wall triangles are the whole
//! list, so every shadow ray tested ten triangles for nothing (docs/experiments/
//! bounding-walls.md: cornell-measured 0.865x the render time, the same image bytes). Rays that
//! leave the scene (directional lights, the environment map) and batch queries of arbitrary
//! rays still test every wall.

use crate::geom::Aabb;
use crate::gpu_abi::GpuTriangle;
use glam::{BVec3, DVec3, Vec3};

/// How far (times the scene's scale, its largest |coordinate|) a point may lie beyond a wall's
/// plane and still count as behind it: the rounding of coplanar vertices (a quad's second
/// triangle, a box standing on the floor). Far below the shadow rays' end offsets (256 ulps,
/// or 1/65536 of the scale near the origin: shaders/include/offset.glsl), so a point that
/// close beyond a wall is where those offsets decide anyway.
pub const WALL_TOLERANCE: f64 = 1e-6;

/// Bit i set where `list[i]` is a wall: every vertex of `triangles` (the whole scene, the list
/// included) and every point of `points` (point lights' positions) lies on one closed side of
/// its plane, within [`WALL_TOLERANCE`] times `scale`. `bounds` holds all of `triangles`: where
/// its eight corners are on one side, so is every vertex, and the scan is skipped. A degenerate
/// triangle has no plane and is no wall.
pub fn walls(list: &[GpuTriangle], triangles: &[GpuTriangle], points: &[Vec3], bounds: &Aabb, scale: f32) -> u32 {
    let tolerance = WALL_TOLERANCE * f64::from(scale);
    let mut mask = 0u32;
    for (i, tri) in list.iter().enumerate().take(32) {
        let a = DVec3::from(Vec3::from(tri.v0));
        let n = (DVec3::from(Vec3::from(tri.v1)) - a).cross(DVec3::from(Vec3::from(tri.v2)) - a);
        if !(n.length() > 0.0) {
            continue;
        }
        let n = n.normalize();
        let on_one_side = |ps: &mut dyn Iterator<Item = Vec3>| {
            let mut sides = Sides::default();
            for p in ps {
                sides.see(n.dot(DVec3::from(p) - a), tolerance);
                if !sides.one_side() {
                    return false;
                }
            }
            true
        };
        let corners = (0..8).map(|c| Vec3::select(BVec3::new(c & 1 != 0, c & 2 != 0, c & 4 != 0), bounds.max, bounds.min));
        let vertices = triangles.iter().flat_map(|t| [t.v0, t.v1, t.v2]).map(Vec3::from);
        // The box first; where it straddles the plane, the vertices decide.
        if on_one_side(&mut points.iter().copied().chain(corners)) || on_one_side(&mut points.iter().copied().chain(vertices)) {
            mask |= 1 << i;
        }
    }
    mask
}

#[derive(Default)]
struct Sides {
    front: bool,
    back: bool,
}

impl Sides {
    fn see(&mut self, distance: f64, tolerance: f64) {
        // NaN coordinates count as both sides: no wall.
        self.front |= !(distance <= tolerance);
        self.back |= !(distance >= -tolerance);
    }
    fn one_side(&self) -> bool {
        !(self.front && self.back)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(v0: [f32; 3], v1: [f32; 3], v2: [f32; 3]) -> GpuTriangle {
        GpuTriangle { v0, prim: 0, v1, shading: 0, v2, _pad1: 0 }
    }

    fn bounds_of(tris: &[GpuTriangle]) -> Aabb {
        tris.iter().flat_map(|t| [t.v0, t.v1, t.v2]).fold(Aabb::EMPTY, |b, v| b.union(&Aabb { min: Vec3::from(v), max: Vec3::from(v) }))
    }

    /// A unit room's floor and a tilted ceiling, with a small block on the floor.
    fn room() -> Vec<GpuTriangle> {
        vec![
            tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            tri([0.0, 1.0, 0.0], [1.0, 1.2, 0.0], [0.0, 1.0, 1.0]),
            tri([0.4, 0.0, 0.4], [0.6, 0.0, 0.4], [0.5, 0.3, 0.5]),
        ]
    }

    #[test]
    fn a_room_s_floor_and_tilted_ceiling_are_walls_and_a_block_in_it_is_not() {
        let tris = room();
        assert_eq!(walls(&tris, &tris, &[], &bounds_of(&tris), 1.2), 0b011);
    }

    #[test]
    fn a_point_light_beyond_a_wall_or_geometry_behind_it_makes_it_no_wall() {
        let tris = room();
        let below = [Vec3::new(0.5, -0.5, 0.5)];
        assert_eq!(walls(&tris, &tris, &below, &bounds_of(&tris), 1.2), 0b010);
        let mut with_cellar = tris.clone();
        with_cellar.push(tri([0.2, -0.3, 0.2], [0.3, -0.3, 0.2], [0.2, -0.3, 0.3]));
        assert_eq!(walls(&tris, &with_cellar, &[], &bounds_of(&with_cellar), 1.2), 0b010);
    }

    #[test]
    fn rounding_within_the_tolerance_keeps_a_wall_and_more_does_not() {
        let mut tris = room();
        let scale = 1.2f32;
        let near = (WALL_TOLERANCE * f64::from(scale) * 0.5) as f32;
        let far = (WALL_TOLERANCE * f64::from(scale) * 4.0) as f32;
        tris[2].v0[1] = -near;
        assert_eq!(walls(&tris[..1], &tris, &[], &bounds_of(&tris), scale), 1);
        tris[2].v0[1] = -far;
        assert_eq!(walls(&tris[..1], &tris, &[], &bounds_of(&tris), scale), 0);
    }

    #[test]
    fn degenerate_and_nan_triangles_are_no_walls() {
        let flat = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        let nan = tri([f32::NAN, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
        let tris = room();
        assert_eq!(walls(&[flat, nan], &tris, &[], &bounds_of(&tris), 1.2), 0);
    }
}
