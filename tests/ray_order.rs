//! Ray reordering on the device: sorting a batch changes nothing but speed. Every hit, counters
//! included, is the same bit for bit whether the rays go in the given order, sorted, or as
//! `auto` picks; `auto` sorts incoherent batches and leaves camera rays alone.

mod common;

use common::{gpu_context, Pcg};
use glam::Vec3;
use vkrt::accel::LayoutKind;
use vkrt::bvh::BuilderKind;
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::GpuRay;
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::query::ray_order::RayOrder;
use vkrt::query::ray_query::{RayQuery, ORDER_WINDOW, RAYS_PER_BATCH};

/// Rays with origins uniform in the box's bounds and directions uniform on the sphere.
fn incoherent_rays(n: usize, lo: Vec3, hi: Vec3, seed: u64) -> Vec<GpuRay> {
    let mut rng = Pcg::new(seed);
    (0..n)
        .map(|_| {
            let o = lo + (hi - lo) * Vec3::new(rng.f32(), rng.f32(), rng.f32());
            let z = rng.range(-1.0, 1.0);
            let phi = rng.range(0.0, std::f32::consts::TAU);
            let r = (1.0 - z * z).max(0.0).sqrt();
            GpuRay { origin: o.to_array(), tmin: 0.0, direction: [r * phi.cos(), r * phi.sin(), z], tmax: f32::INFINITY }
        })
        .collect()
}

#[test]
fn every_order_gives_the_same_hits() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    let (lo, hi) = scene.triangles.iter().flat_map(|t| t.p).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), p| (l.min(p), h.max(p)));
    // More than one window and a ragged last submission, so the sorted path's scatter across
    // submissions and windows is exercised.
    let rays = incoherent_rays(ORDER_WINDOW + 3 * RAYS_PER_BATCH + 123, lo, hi, 11);
    let frame = scene.camera.frame().unwrap();
    let (w, h) = (256u32, 256u32);
    let camera: Vec<GpuRay> = (0..w * h)
        .map(|k| {
            let d = frame.ray_direction((k % w) as f32 + 0.5, (k / w) as f32 + 0.5, w, h);
            GpuRay { origin: frame.origin.to_array(), tmin: 0.0, direction: d.to_array(), tmax: f32::INFINITY }
        })
        .collect();
    let ctx = gpu_context();
    for layout in [LayoutKind::Threaded, LayoutKind::ParentLink] {
        let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: BuilderKind::Sah, layout, ..Default::default() }).unwrap();
        let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
        let mut query = RayQuery::new(&ctx, &gpu.bvh).unwrap();
        query.order = RayOrder::Given;
        let given = query.trace(&rays, false).unwrap();
        assert_eq!(query.rays_reordered(), 0);
        let hit = given.iter().filter(|h| h.prim != PRIM_NONE).count();
        assert!(hit > rays.len() / 2, "{layout:?}: only {hit} of {} rays hit the box", rays.len());
        for order in [RayOrder::Sorted, RayOrder::Auto] {
            let mut query = RayQuery::new(&ctx, &gpu.bvh).unwrap();
            query.order = order;
            let got = query.trace(&rays, false).unwrap();
            assert_eq!(query.rays_reordered(), rays.len() as u64, "{layout:?} {order:?}: incoherent rays are sorted");
            let differ = given.iter().zip(&got).position(|(a, b)| a != b);
            assert!(differ.is_none(), "{layout:?} {order:?}: ray {differ:?} got another hit");
            let any = query.trace(&rays[..200_000], true).unwrap();
            let any_given = {
                let mut q = RayQuery::new(&ctx, &gpu.bvh).unwrap();
                q.order = RayOrder::Given;
                q.trace(&rays[..200_000], true).unwrap()
            };
            assert!(any == any_given, "{layout:?} {order:?}: any-hit queries differ");
        }
        // Camera rays in scanline order are coherent: auto traces them as given.
        let mut query = RayQuery::new(&ctx, &gpu.bvh).unwrap();
        let auto = query.trace(&camera, false).unwrap();
        assert_eq!(query.rays_reordered(), 0, "{layout:?}: camera rays were sorted");
        query.order = RayOrder::Sorted;
        assert!(query.trace(&camera, false).unwrap() == auto, "{layout:?}: sorted camera rays differ");
    }
    common::assert_no_validation_messages(&ctx);
}

/// Submissions grow while the device is fast (`query::ray_query::next_batch`), and a slot whose
/// batches outgrew it is replaced by a larger one: whatever the submissions' sizes, the hits are
/// the same, in the caller's order, sorted or not.
#[test]
fn the_submissions_size_changes_no_hit() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    let (lo, hi) = scene.triangles.iter().flat_map(|t| t.p).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), p| (l.min(p), h.max(p)));
    // More than a window, so the sizes carry across windows.
    let rays = incoherent_rays(ORDER_WINDOW + 70_001, lo, hi, 23);
    let ctx = gpu_context();
    let prepared = PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let plain = RayQuery::new(&ctx, &gpu.bvh).unwrap();
    plain.set_batch_rays(RAYS_PER_BATCH);
    let expected = plain.trace(&rays, false).unwrap();
    for order in [RayOrder::Given, RayOrder::Sorted] {
        // A ragged size, larger than the slots the query starts with, then a small one.
        for size in [3 * RAYS_PER_BATCH + 17, 1000] {
            let mut query = RayQuery::new(&ctx, &gpu.bvh).unwrap();
            query.order = order;
            query.set_batch_rays(size);
            let got = query.trace(&rays, false).unwrap();
            let differ = expected.iter().zip(&got).position(|(a, b)| a != b);
            assert!(got.len() == rays.len() && differ.is_none(), "{order:?}, {size} rays per submission: ray {differ:?} got another hit");
            // The query goes on from where its batches got to, its slots already grown.
            assert!(query.trace(&rays[..300_000], false).unwrap() == expected[..300_000], "{order:?}, {size}: a second trace differs");
        }
    }
    common::assert_no_validation_messages(&ctx);
}

/// The warm-up dispatch (`RayQuery::warm_up`, which `vkrt trace` and `vkrt bvh` run first so
/// that lavapipe's shader compile is not timed) is neither timed nor counted, and leaves the
/// query tracing the same hits as a query without it.
#[test]
fn the_warm_up_is_neither_timed_nor_counted() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    let (lo, hi) = scene.triangles.iter().flat_map(|t| t.p).fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), p| (l.min(p), h.max(p)));
    let rays = incoherent_rays(20_000, lo, hi, 5);
    let ctx = gpu_context();
    let prepared = PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let cold = RayQuery::new(&ctx, &gpu.bvh).unwrap();
    let cold_hits = cold.trace(&rays, false).unwrap();
    let mut warm = RayQuery::new(&ctx, &gpu.bvh).unwrap();
    warm.order = RayOrder::Sorted;
    warm.warm_up().unwrap();
    assert_eq!(warm.rays_reordered(), 0, "the warm-up's rays were counted");
    if let Some(s) = warm.device_seconds() {
        assert_eq!(s, 0.0, "the warm-up's dispatch was timed");
    }
    assert!(warm.trace(&rays, false).unwrap() == cold_hits, "a query traces other hits after its warm-up");
    assert_eq!(warm.rays_reordered(), rays.len() as u64);
    if let Some(s) = warm.device_seconds() {
        assert!(s > 0.0, "the traced batch was not timed");
    }
    common::assert_no_validation_messages(&ctx);
}
