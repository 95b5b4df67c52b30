//! Degenerate input: scenes and rays that break naive code. No hang, no crash, defined results,
//! and the GPU agrees with its CPU twin and with brute force on every ray.

mod common;

use common::procedural::scene_of;
use common::Pcg;
use glam::Vec3;
use vkrt::accel::leaf;
use vkrt::accel::LayoutKind;
use vkrt::bvh::{self, BuildConfig, BuilderKind};
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::{GpuHit, GpuRay};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::query::ray_query::trace_rays;
use vkrt::scene::{Scene, Triangle};

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
    Triangle { p: [a.into(), b.into(), c.into()], n: None, uv: None, material: 0 }
}

fn ray(o: Vec3, d: Vec3) -> GpuRay {
    GpuRay { origin: o.to_array(), tmin: 0.0, direction: d.to_array(), tmax: f32::INFINITY }
}

/// Traces `rays` on the GPU with every builder and layout and checks every hit against the CPU twin and
/// brute force; returns the GPU hits of the last builder.
fn check(name: &str, scene: &Scene, rays: &[GpuRay]) -> Vec<GpuHit> {
    let ctx = common::gpu_context();
    let mut last = Vec::new();
    for (builder, layout) in BuilderKind::ALL.into_iter().flat_map(|b| LayoutKind::ALL.map(|l| (b, l))) {
        let (boxes, centroids) = vkrt::scene::triangle_boxes(&scene.triangles);
        let tree = bvh::build(builder, &boxes, &centroids, &BuildConfig::default());
        bvh::validate::validate(&tree, &boxes).unwrap_or_else(|e| panic!("{name} {builder:?}: {e}"));
        let prepared = PreparedScene::new(scene, &PrepareOptions { builder, layout, ..Default::default() }).unwrap();
        let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
        let hits = trace_rays(&ctx, &gpu.bvh, rays, false).unwrap();
        for (i, (r, g)) in rays.iter().zip(&hits).enumerate() {
            let twin = prepared.flat.trace(r, false);
            let brute = leaf::brute_force(&scene.triangles, r);
            assert_eq!(twin.prim, g.prim, "{name} {builder:?} {layout:?} ray {i} {r:?}: GPU vs CPU twin");
            assert_eq!(brute.t == f32::INFINITY, g.prim == PRIM_NONE, "{name} {builder:?} ray {i}: hit vs brute force");
            if brute.prim != PRIM_NONE {
                assert!((brute.t - g.t).abs() <= 1e-5 * brute.t, "{name} {builder:?} ray {i}: t {} vs {}", g.t, brute.t);
            }
        }
        last = hits;
    }
    common::assert_no_validation_messages(&ctx);
    last
}

#[test]
fn nan_inf_zero_and_denormal_rays_are_defined() {
    let scene = common::procedural::random_soup(300, 9);
    let nan = f32::NAN;
    let inf = f32::INFINITY;
    let tiny = f32::from_bits(1); // the smallest denormal
    let c = Vec3::splat(0.5);
    let rays = vec![
        ray(Vec3::new(nan, 0.5, 0.5), Vec3::X),
        ray(c, Vec3::new(nan, nan, nan)),
        ray(c, Vec3::new(inf, 0.0, 0.0)),
        ray(Vec3::splat(inf), -Vec3::X),
        ray(c, Vec3::ZERO),
        ray(Vec3::new(-1.0, 0.5, 0.5), Vec3::new(1.0, tiny, -tiny)),
        ray(Vec3::new(0.5, -1.0, 0.5), Vec3::new(tiny, 1.0, tiny)),
        ray(Vec3::new(0.5, 0.5, 2.0), Vec3::new(0.0, 0.0, -1.0)),
        ray(Vec3::new(0.5, 0.5, 2.0), Vec3::new(-0.0, -0.0, -1.0)),
        GpuRay { origin: c.to_array(), tmin: nan, direction: [1.0, 0.0, 0.0], tmax: inf },
        GpuRay { origin: c.to_array(), tmin: 0.0, direction: [1.0, 0.0, 0.0], tmax: nan },
        GpuRay { origin: c.to_array(), tmin: 1.0, direction: [1.0, 0.0, 0.0], tmax: 0.0 },
    ];
    let hits = check("degenerate rays", &scene, &rays);
    // NaN anywhere in a ray, an infinite or zero direction, or an empty [tmin, tmax]: a miss.
    for i in [0, 1, 2, 3, 4, 9, 10, 11] {
        assert_eq!(hits[i].prim, PRIM_NONE, "ray {i} {:?} should miss: {:?}", rays[i], hits[i]);
        assert_eq!(hits[i].t, f32::INFINITY);
    }
    // A NaN in the origin, direction or tmin fails the first box test: no walk of the tree.
    for i in [0, 1, 9] {
        assert_eq!(hits[i].nodes_visited, 1, "ray {i} {:?} walked the tree", rays[i]);
    }
    // Denormal and signed-zero components behave as the plain axis-parallel ray does.
    assert!(hits[5..9].iter().any(|h| h.prim != PRIM_NONE), "no axis-parallel ray hit the soup");
    assert_eq!(hits[7].prim, hits[8].prim, "-0 and +0 direction components differ");
}

#[test]
fn degenerate_scenes_build_and_trace() {
    let mut rng = Pcg::new(5);
    let mut rays = Vec::new();
    for _ in 0..400 {
        let o = Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        rays.push(ray(o, (Vec3::splat(0.5) + 0.3 * rng.unit_vector() - o).normalize()));
    }
    // Rays down the z axis through the needles' sliver (y between 0 and 1e-7 * x).
    for x in [0.3f32, 0.6, 0.9] {
        rays.push(ray(Vec3::new(x, 0.4e-7 * x, 2.0), -Vec3::Z));
    }
    let needle = |k: f32| tri([0.0, 0.0, k], [1.0, 1e-7, k], [1.0, 0.0, k]);
    let cases: Vec<(&str, Vec<Triangle>)> = vec![
        ("one triangle", vec![tri([0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5])]),
        ("needles", (0..100).map(|k| needle(k as f32 * 0.01)).collect()),
        // Different triangles, one shared centroid: the builders must split by index.
        (
            "shared centroid",
            (0..500)
                .map(|k| {
                    let a = k as f32 * 0.1;
                    let (s, c) = (a.sin() * 0.4, a.cos() * 0.4);
                    tri([0.5 + s, 0.5 + c, 0.5], [0.5 - s, 0.5 - c, 0.5 + 0.2], [0.5, 0.5, 0.5 - 0.2])
                })
                .collect(),
        ),
        // Coplanar, overlapping sheets: the same quad ten times over, and shifted copies.
        (
            "coplanar sheets",
            (0..10)
                .flat_map(|k| {
                    let d = k as f32 * 0.05;
                    [tri([d, 0.0, 0.5], [1.0 + d, 0.0, 0.5], [d, 1.0, 0.5]), tri([0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5])]
                })
                .collect(),
        ),
    ];
    for (name, tris) in cases {
        let scene = scene_of(tris);
        let hits = check(name, &scene, &rays);
        assert!(hits.iter().any(|h| h.prim != PRIM_NONE), "{name}: no ray hit, the case tests nothing");
        println!("{name}: {} triangles, {} of {} rays hit", scene.triangles.len(), hits.iter().filter(|h| h.prim != PRIM_NONE).count(), rays.len());
    }
}

#[test]
fn empty_scene_renders_black_and_traces_misses() {
    let scene = Scene::default();
    let rays = vec![ray(Vec3::ZERO, Vec3::X)];
    let hits = check("empty", &scene, &rays);
    assert_eq!(hits[0].prim, PRIM_NONE);
}

#[test]
fn a_million_triangles_in_one_small_box() {
    // A million slivers crossing one 1e-3-wide box: the builders cannot separate them, leaves
    // stay within their size limit, and a ray through the box still finds the nearest one.
    let n = 1_000_000;
    let mut rng = Pcg::new(11);
    let tris: Vec<Triangle> = (0..n)
        .map(|_| {
            let z = rng.range(0.0, 1e-3);
            let a = rng.range(0.0, std::f32::consts::TAU);
            let (s, c) = (a.sin() * 5e-4, a.cos() * 5e-4);
            tri([s, c, z], [-s, -c, z], [c * 0.1, -s * 0.1, z + 1e-6])
        })
        .collect();
    let scene = scene_of(tris);
    let rays: Vec<GpuRay> = (0..16).map(|k| ray(Vec3::new(k as f32 * 1e-5, 0.0, 1.0), -Vec3::Z)).collect();
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: BuilderKind::Sah, ..Default::default() }).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let hits = trace_rays(&ctx, &gpu.bvh, &rays, false).unwrap();
    for (r, h) in rays.iter().zip(&hits) {
        let brute = leaf::brute_force(&scene.triangles, r);
        assert_eq!(brute.t, h.t, "million slivers: nearest hit differs");
        assert!(h.prim != PRIM_NONE);
    }
    common::assert_no_validation_messages(&ctx);
}
