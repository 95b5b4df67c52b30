//! The agreement chain: brute force == BVH tree walk == flat CPU twin == GPU traversal, for
//! every builder x layout, on random triangle soups, the Cornell box and axis-parallel rays.
//! Same primitive id; the same t, bit for bit on the CPU and on every device
//! (`GPU_T_TOLERANCE_ULPS`); the GPU's traversal counters equal its twin's.

mod common;

use common::{gpu_context, Pcg};
use glam::Vec3;
use vkrt::accel::intersect::{self, RayPre};
use vkrt::accel::leaf;
use vkrt::accel::LayoutKind;
use vkrt::bvh::{self, BuildConfig, BuilderKind, Bvh, NodeKind};
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::{GpuHit, GpuRay};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::query::ray_query::trace_rays;
use vkrt::scene::{Scene, Triangle};

const BUILDERS: &[BuilderKind] = &BuilderKind::ALL;

/// ULPs the GPU's t may differ from the CPU twin's: none, on every device. The twin does the
/// shader's arithmetic in the same order, `precise` forbids fusing, products and sums are
/// correctly rounded on every Vulkan device, and the divisions (ray setup, 1 / det) are the
/// rounded quotients: lavapipe's division is IEEE, and elsewhere, where the spec lets OpFDiv be
/// 2.5 ULP off, `div_rn` corrects it (SPEC_CORRECT_DIVISION; before it, an H200 gave t 6 ULP
/// off and a ray that visited 9 nodes where the twin visited 15).
const GPU_T_TOLERANCE_ULPS: u32 = 0;

/// ULPs between two finite floats of the same sign (u32::MAX if the signs differ).
fn ulps(a: f32, b: f32) -> u32 {
    if a.is_sign_negative() != b.is_sign_negative() {
        return if a == b { 0 } else { u32::MAX };
    }
    a.to_bits().abs_diff(b.to_bits())
}

/// Closest hit by walking the `Bvh` node tree (before flattening), nearest child first.
fn tree_walk(bvh: &Bvh, tris: &[Triangle], ray: &GpuRay) -> GpuHit {
    let r = RayPre::new(ray);
    let mut best = leaf::miss();
    let mut tmax = ray.tmax;
    if bvh.nodes.is_empty() {
        return best;
    }
    let mut stack = vec![0u32];
    while let Some(i) = stack.pop() {
        let node = &bvh.nodes[i as usize];
        if intersect::intersect_box(&r, node.bounds.min, node.bounds.max, tmax).is_none() {
            continue;
        }
        match node.kind {
            NodeKind::Interior { left, right } => {
                stack.push(right);
                stack.push(left);
            }
            NodeKind::Leaf { first, count } => {
                for &prim in &bvh.prim_indices[first as usize..(first + count) as usize] {
                    let t = &tris[prim as usize];
                    if let Some(h) = intersect::intersect_triangle(&r, t.p[0], t.p[1], t.p[2], tmax) {
                        tmax = h.t;
                        best = GpuHit { t: h.t, prim, u: h.u, v: h.v, ..best };
                    }
                }
            }
        }
    }
    best
}

/// Same primitive, and t within `max_ulps` (0 between CPU walks: the same arithmetic).
fn assert_same_hit(what: &str, ray: &GpuRay, expected: &GpuHit, got: &GpuHit, max_ulps: u32) {
    assert_eq!(expected.prim, got.prim, "{what}: primitive differs for ray {ray:?}: expected {expected:?}, got {got:?}");
    if expected.prim != PRIM_NONE {
        let d = ulps(expected.t, got.t);
        assert!(d <= max_ulps, "{what}: t differs by {d} ulps (at most {max_ulps}) for ray {ray:?}: {expected:?} vs {got:?}");
    }
}

fn ray(origin: Vec3, dir: Vec3) -> GpuRay {
    GpuRay { origin: origin.to_array(), tmin: 0.0, direction: dir.to_array(), tmax: f32::INFINITY }
}

/// Rays of three kinds: aimed at random points on random triangles (they mostly hit), random
/// origins and directions in the bounds, and axis-parallel rays (zero direction components).
fn test_rays(scene: &Scene, n: usize, seed: u64) -> Vec<GpuRay> {
    let mut rng = Pcg::new(seed);
    let b = scene.bounds();
    let (lo, hi) = (b.min - 0.1 * b.extent(), b.max + 0.1 * b.extent());
    let mut rays = Vec::with_capacity(n);
    let point = |rng: &mut Pcg| Vec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
    while rays.len() < n {
        let origin = point(&mut rng);
        match rays.len() % 3 {
            0 => {
                let t = &scene.triangles[(rng.next_u32() as usize) % scene.triangles.len()];
                let (mut u, mut v) = (rng.f32(), rng.f32());
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                let target = t.p[0] + u * (t.p[1] - t.p[0]) + v * (t.p[2] - t.p[0]);
                let d = (target - origin).normalize_or_zero();
                if d != Vec3::ZERO {
                    rays.push(ray(origin, d));
                }
            }
            1 => rays.push(ray(origin, rng.unit_vector())),
            _ => {
                let axis = (rng.next_u32() % 3) as usize;
                let mut d = Vec3::ZERO;
                d[axis] = if rng.next_u32() % 2 == 0 { 1.0 } else { -1.0 };
                rays.push(ray(origin, d));
            }
        }
    }
    rays
}

/// Runs the whole chain for `scene` with `rays` for every builder x layout; returns how many
/// rays hit.
fn check_chain(name: &str, scene: &Scene, rays: &[GpuRay]) -> usize {
    let ctx = gpu_context();
    let brute: Vec<GpuHit> = rays.iter().map(|r| leaf::brute_force(&scene.triangles, r)).collect();
    for &builder in BUILDERS {
        let (boxes, centroids) = vkrt::scene::triangle_boxes(&scene.triangles);
        let tree = bvh::build(builder, &boxes, &centroids, &BuildConfig::default());
        for (i, r) in rays.iter().enumerate() {
            let walked = tree_walk(&tree, &scene.triangles, r);
            assert_same_hit(&format!("{name} {builder:?} ray {i}: tree walk vs brute force"), r, &brute[i], &walked, 0);
        }
        // With the triangle list (the default) and with every triangle in the tree.
        for (layout, triangle_list) in LayoutKind::ALL.into_iter().flat_map(|l| [(l, true), (l, false)]) {
            let prepared = PreparedScene::new(scene, &PrepareOptions { builder, layout, triangle_list, ..Default::default() }).unwrap();
            assert_eq!(prepared.flat.layout(), layout);
            if !triangle_list {
                assert!(prepared.flat.list().is_empty());
            }
            let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
            let gpu_hits = trace_rays(&ctx, &gpu.bvh, rays, false).unwrap();
            let gpu_any = trace_rays(&ctx, &gpu.bvh, rays, true).unwrap();
            for (i, r) in rays.iter().enumerate() {
                let what = format!("{name} {builder:?} {} (triangle list {triangle_list}) ray {i}", layout.name());
                let twin = prepared.flat.trace(r, false);
                assert_same_hit(&format!("{what}: flat twin vs brute force"), r, &brute[i], &twin, 0);
                assert_same_hit(&format!("{what}: GPU vs flat twin"), r, &twin, &gpu_hits[i], GPU_T_TOLERANCE_ULPS);
                // The GPU counters are the twin's: same nodes, same order.
                assert_eq!(twin.nodes_visited, gpu_hits[i].nodes_visited, "{what}: nodes visited");
                assert_eq!(twin.tris_tested, gpu_hits[i].tris_tested, "{what}: triangles tested");
                // Any-hit finds a hit exactly when there is one, and it is a real one.
                let twin_any = prepared.flat.trace(r, true);
                assert_eq!(twin_any.prim == PRIM_NONE, brute[i].prim == PRIM_NONE, "{what}: any-hit on CPU");
                assert_eq!(twin_any.prim, gpu_any[i].prim, "{what}: any-hit GPU vs CPU");
                assert_eq!(twin_any.nodes_visited, gpu_any[i].nodes_visited, "{what}: any-hit nodes visited");
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
    brute.iter().filter(|h| h.prim != PRIM_NONE).count()
}

#[test]
fn random_soups_agree_along_the_chain() {
    for (n, seed) in [(1usize, 1u64), (7, 2), (500, 3), (5000, 4)] {
        let scene = common::procedural::random_soup(n, seed);
        if n == 1 {
            // One triangle spans the scene: it is the list, and the tree is empty.
            let prepared = PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
            assert_eq!(prepared.flat.list().len(), 1);
        }
        let rays = test_rays(&scene, 3000, seed + 100);
        let hits = check_chain(&format!("soup {n}"), &scene, &rays);
        // The aimed third of the rays nearly always hit: the test is not vacuous.
        assert!(hits >= rays.len() / 4, "soup {n}: only {hits} of {} rays hit", rays.len());
    }
}

#[test]
fn cornell_box_agrees_along_the_chain() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.obj")).unwrap();
    // The chain covers the list and the tree together: the box's ten wall, floor and ceiling
    // triangles are listed, the blocks and the light are in the tree.
    let prepared = PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
    assert_eq!(prepared.flat.list().len(), 10);
    let rays = test_rays(&scene, 6000, 7);
    let hits = check_chain("cornell", &scene, &rays);
    assert!(hits >= rays.len() / 2, "cornell: only {hits} of {} rays hit", rays.len());
}

#[test]
fn primary_rays_through_the_cornell_box_agree() {
    // Camera rays through pixel centres, with exactly axis-parallel rays among them (the
    // central column and row have zero components). The .yaml has the standard camera.
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    let frame = scene.camera.frame().unwrap();
    let (w, h) = (33u32, 33u32);
    let rays: Vec<GpuRay> =
        (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).map(|(i, j)| ray(frame.origin, frame.ray_direction(i as f32 + 0.5, j as f32 + 0.5, w, h))).collect();
    let hits = check_chain("cornell primary", &scene, &rays);
    // The box fills the standard camera's view but for a thin border (open front, black rim).
    assert!(hits * 10 >= rays.len() * 9, "only {hits} of {} camera rays hit the box", rays.len());
}

#[test]
fn empty_scene_misses_everything() {
    let scene = Scene::default();
    let ctx = gpu_context();
    let rays = vec![ray(Vec3::ZERO, Vec3::X), ray(Vec3::ONE, -Vec3::Y)];
    for layout in LayoutKind::ALL {
        let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: BuilderKind::Sah, layout, ..Default::default() }).unwrap();
        let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
        let hits = trace_rays(&ctx, &gpu.bvh, &rays, false).unwrap();
        assert!(hits.iter().all(|h| h.prim == PRIM_NONE && h.t == f32::INFINITY));
        assert!(rays.iter().all(|r| prepared.flat.trace(r, false).prim == PRIM_NONE));
    }
    common::assert_no_validation_messages(&ctx);
}

/// A ray with a NaN anywhere (origin, direction, tmin or tmax) misses at the root: at most the
/// root node is visited and no triangle is tested, in every layout, on the GPU and in the CPU
/// twin. (Before the fix, a direction like (NaN, 0, 0) with tmax = +inf entered every box whose
/// far slab overflowed to infinity and walked most of the tree.)
#[test]
fn nan_rays_miss_at_the_root() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.obj")).unwrap();
    let centre = scene.bounds().center();
    let mut rays = vec![ray(centre, Vec3::new(f32::NAN, 0.0, 0.0)), ray(centre, Vec3::new(0.0, f32::NAN, 0.0))];
    for (i, r) in test_rays(&scene, 40, 11).into_iter().enumerate() {
        for k in 0..8 {
            let mut q = r;
            match k {
                0..=2 => q.origin[k] = f32::NAN,
                3..=5 => q.direction[k - 3] = f32::NAN,
                6 => q.tmin = f32::NAN,
                _ => q.tmax = f32::NAN,
            }
            // Some with the other components zero, the case where slabs overflow.
            if i % 2 == 0 && (3..=5).contains(&k) {
                q.direction = [0.0; 3];
                q.direction[k - 3] = f32::NAN;
            }
            rays.push(q);
        }
    }
    let ctx = gpu_context();
    for layout in LayoutKind::ALL {
        let prepared = PreparedScene::new(&scene, &PrepareOptions { layout, ..Default::default() }).unwrap();
        let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
        for any_hit in [false, true] {
            let hits = trace_rays(&ctx, &gpu.bvh, &rays, any_hit).unwrap();
            for (i, (r, h)) in rays.iter().zip(&hits).enumerate() {
                let twin = prepared.flat.trace(r, any_hit);
                let what = format!("{} ray {i} {r:?} (any hit {any_hit})", layout.name());
                assert_eq!(h.prim, PRIM_NONE, "{what}: a NaN ray hit on the GPU");
                assert_eq!(twin.prim, PRIM_NONE, "{what}: a NaN ray hit in the twin");
                assert!(h.nodes_visited <= 1 && h.tris_tested == 0, "{what}: GPU visited {} nodes, tested {} triangles", h.nodes_visited, h.tris_tested);
                assert_eq!((twin.nodes_visited, twin.tris_tested), (h.nodes_visited, h.tris_tested), "{what}: twin vs GPU counters");
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
}
