//! The triangle list: the scene's few largest triangles, kept out of the BVH and tested by every
//! ray before its walk (CPU twin of `trace_list` in shaders/include/triangle_list.glsl).
//!
//! Why: a triangle whose box spans much of the scene (a room's wall, floor or ceiling) makes
//! every ancestor's box span the scene too, so a ray that starts inside the room enters most of
//! the tree: in the Cornell boxes a ray visited 18-24 of 35 nodes (docs/experiments/
//! triangle-list.md). Taking the walls out leaves a tree that rays mostly miss or leave early,
//! and the walls themselves cost one triangle test each. On lavapipe the list's triangles come
//! from a uniform block at constant offsets in an unrolled loop (one scalar load and a
//! broadcast each, against a texel-fetch call per node and triangle in the walk), and on GPUs
//! from the constant cache. The choice sees only boxes, as a builder does.

use super::intersect::{intersect_triangle, RayPre};
use super::leaf::miss;
use crate::geom::Aabb;
use crate::gpu_abi::constants::MAX_LIST_TRIANGLES;
use crate::gpu_abi::{GpuHit, GpuRay, GpuTriangle};

/// A triangle joins the list when its box's surface area is at least this fraction of the
/// scene box's. A cube room's wall is ~1/3; 0.15 lists the Cornell boxes' ten wall triangles,
/// and lists 4 of Conference's triangles and 8 of Sponza's, whose path-tracing times did not
/// move; 0.05 listed 44 of Sponza's and cost 13 % (docs/experiments/triangle-list.md).
pub const LIST_AREA_FRACTION: f32 = 0.15;

/// Which triangles (by index into `boxes`) go to the list: those whose box's area is at least
/// [`LIST_AREA_FRACTION`] of the scene box's, the largest first, at most
/// [`MAX_LIST_TRIANGLES`]; returned in index order. Empty for an empty or flat-boxed scene.
pub fn choose(boxes: &[Aabb]) -> Vec<u32> {
    let scene_area = boxes.iter().fold(Aabb::EMPTY, |a, b| a.union(b)).area();
    if !(scene_area > 0.0) {
        return Vec::new();
    }
    let mut large: Vec<(f32, u32)> =
        boxes.iter().enumerate().filter(|(_, b)| b.area() >= LIST_AREA_FRACTION * scene_area).map(|(i, b)| (b.area(), i as u32)).collect();
    // Largest first, ties by index, so the choice does not depend on the sort's stability.
    large.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    large.truncate(MAX_LIST_TRIANGLES as usize);
    let mut chosen: Vec<u32> = large.into_iter().map(|(_, i)| i).collect();
    chosen.sort_unstable();
    chosen
}

/// `trace_list` in triangle_list.glsl: tests `list` (the triangles from index `first` of the
/// leaf-order array) in order, keeping the closest hit below `ray.tmax`; the hit's `prim` is
/// the triangle's, and `tris_tested` counts every test. A ray with an empty interval or a NaN
/// anywhere tests nothing. Unlike a leaf, an any-hit query tests them all: the shader's
/// unrolled loop has no early exit. Triangles whose bit is set in `skip` are left out (the
/// walls, for a ray between two points of the scene: `super::walls`).
pub fn trace(list: &[GpuTriangle], ray: &GpuRay, skip: u32) -> GpuHit {
    let r = RayPre::new(ray);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    if !(r.tmin < tmax) {
        return hit;
    }
    for (i, tri) in list.iter().enumerate() {
        if skip >> i & 1 != 0 {
            continue;
        }
        hit.tris_tested += 1;
        if let Some(h) = intersect_triangle(&r, tri.v0.into(), tri.v1.into(), tri.v2.into(), tmax) {
            tmax = h.t;
            hit = GpuHit { t: h.t, prim: tri.prim, u: h.u, v: h.v, ..hit };
        }
    }
    hit
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn boxed(min: [f32; 3], max: [f32; 3]) -> Aabb {
        Aabb { min: Vec3::from(min), max: Vec3::from(max) }
    }

    #[test]
    fn lists_the_walls_of_a_room_and_not_what_stands_in_it() {
        // Two wall-sized flat boxes (area 2 each against the unit room's 6) and a small block.
        let boxes = [boxed([0.0, 0.0, 0.0], [1.0, 1.0, 0.0]), boxed([0.4, 0.0, 0.4], [0.6, 0.2, 0.6]), boxed([0.0, 0.0, 0.0], [0.0, 1.0, 1.0])];
        assert_eq!(choose(&boxes), vec![0, 2]);
    }

    #[test]
    fn keeps_at_most_the_largest_allowed() {
        let n = MAX_LIST_TRIANGLES as usize + 5;
        // All flat boxes spanning the unit square in x and y, at growing z: all large, equal.
        let mut boxes: Vec<Aabb> = (0..n).map(|i| boxed([0.0, 0.0, i as f32 * 0.01], [1.0, 1.0, i as f32 * 0.01])).collect();
        // One larger than the rest must be among those kept.
        boxes[n - 1] = boxed([0.0, 0.0, 0.0], [1.0, 1.0, 0.05]);
        let chosen = choose(&boxes);
        assert_eq!(chosen.len(), MAX_LIST_TRIANGLES as usize);
        assert!(chosen.contains(&(n as u32 - 1)));
        assert!(chosen.windows(2).all(|w| w[0] < w[1]), "index order");
    }

    #[test]
    fn an_empty_or_degenerate_scene_lists_nothing() {
        assert!(choose(&[]).is_empty());
        assert!(choose(&[boxed([1.0, 1.0, 1.0], [1.0, 1.0, 1.0])]).is_empty());
    }

    #[test]
    fn the_list_keeps_the_closest_hit() {
        let tri = |z: f32, prim: u32| GpuTriangle { v0: [-1.0, -1.0, z], prim, v1: [1.0, -1.0, z], shading: 0, v2: [0.0, 1.0, z], _pad1: 0 };
        let list = [tri(3.0, 7), tri(2.0, 8), tri(4.0, 9)];
        let ray = GpuRay { origin: [0.0, 0.0, 0.0], tmin: 0.0, direction: [0.0, 0.0, 1.0], tmax: f32::INFINITY };
        let hit = trace(&list, &ray, 0);
        assert_eq!((hit.prim, hit.t, hit.tris_tested), (8, 2.0, 3));
        let short = GpuRay { tmax: 1.5, ..ray };
        assert_eq!(trace(&list, &short, 0).prim, crate::gpu_abi::constants::PRIM_NONE);
        // Skipping the closest leaves the next: the skip mask is by list position.
        assert_eq!(trace(&list, &ray, 0b010).prim, 7);
    }
}
