//! The packet walk (`trace_packet`, shaders/include/traverse_packet.glsl) must return exactly the
//! hits of the per-ray threaded walk (`trace`): same primitive and bit-identical t for closest
//! hits, hit iff hit for any-hit queries. Rays of mixed directions share subgroups on purpose,
//! so lanes of one packet disagree about which nodes they need.

mod common;

use common::gpu_context;
use glam::Vec3;
use vkrt::bvh::{BuildConfig, BuilderKind};
use vkrt::integrator::gpu_scene::{GpuScene, PreparedScene};
use vkrt::integrator::ray_query::RayQuery;
use vkrt::layout::constants::PRIM_NONE;
use vkrt::layout::GpuRay;
use vkrt::pipeline::shaders;
use vkrt::rng::Pcg32;
use vkrt::scene::Scene;

/// Rays cycling through four kinds, so every subgroup mixes them: aimed at a point on a random
/// triangle, random direction, axis-parallel (zero direction components), and aimed at a
/// triangle with a tmax that stops short of it half the time.
fn mixed_rays(scene: &Scene, n: usize, seed: u64) -> Vec<GpuRay> {
    let mut rng = Pcg32::new(seed);
    let b = scene.bounds();
    let (lo, hi) = (b.min - 0.1 * b.extent(), b.max + 0.1 * b.extent());
    let mut rays = Vec::with_capacity(n);
    while rays.len() < n {
        let origin = Vec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        let t = &scene.triangles[rng.below(scene.triangles.len())];
        let (mut u, mut v) = (rng.f32(), rng.f32());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        let target = t.p[0] + u * (t.p[1] - t.p[0]) + v * (t.p[2] - t.p[0]);
        let (direction, tmax) = match rays.len() % 4 {
            0 => (target - origin, f32::INFINITY),
            1 => (rng.unit_vector(), f32::INFINITY),
            2 => {
                let mut d = Vec3::ZERO;
                d[rng.below(3)] = if rng.f32() < 0.5 { 1.0 } else { -1.0 };
                (d, f32::INFINITY)
            }
            _ => (target - origin, rng.range(0.5, 1.5)),
        };
        if direction != Vec3::ZERO {
            rays.push(GpuRay { origin: origin.to_array(), tmin: 0.0, direction: direction.to_array(), tmax });
        }
    }
    rays
}

/// Traces `rays` with both variants, closest and any hit, and compares; returns the hit count.
fn check(name: &str, scene: &Scene, rays: &[GpuRay]) -> usize {
    let ctx = gpu_context();
    let prepared = PreparedScene::new(scene, BuilderKind::Sah, &BuildConfig::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let threaded = RayQuery::with_shader(&ctx, &gpu, shaders::TRACE).unwrap();
    let packet = RayQuery::with_shader(&ctx, &gpu, shaders::TRACE_PACKET).unwrap();
    let (tc, pc) = (threaded.trace(rays, false).unwrap(), packet.trace(rays, false).unwrap());
    let (ta, pa) = (threaded.trace(rays, true).unwrap(), packet.trace(rays, true).unwrap());
    for (i, r) in rays.iter().enumerate() {
        assert_eq!(tc[i].prim, pc[i].prim, "{name} ray {i} {r:?}: closest prim: threaded {:?}, packet {:?}", tc[i], pc[i]);
        assert_eq!(tc[i].t.to_bits(), pc[i].t.to_bits(), "{name} ray {i} {r:?}: closest t: threaded {:?}, packet {:?}", tc[i], pc[i]);
        // The packet visits every node the ray's own walk visits, and maybe more.
        assert!(pc[i].nodes_visited >= tc[i].nodes_visited, "{name} ray {i}: packet visited fewer nodes");
        assert_eq!(ta[i].prim == PRIM_NONE, pa[i].prim == PRIM_NONE, "{name} ray {i} {r:?}: any hit: threaded {:?}, packet {:?}", ta[i], pa[i]);
        assert_eq!(tc[i].prim == PRIM_NONE, ta[i].prim == PRIM_NONE, "{name} ray {i}: closest and any hit disagree");
    }
    common::assert_no_validation_messages(&ctx);
    tc.iter().filter(|h| h.prim != PRIM_NONE).count()
}

#[test]
fn packet_matches_threaded_on_random_soups() {
    for (n, seed) in [(1usize, 3u64), (100, 5), (3000, 9)] {
        let scene = vkrt::scene::procedural::random_soup(n, seed);
        let rays = mixed_rays(&scene, 4000, seed + 1);
        let hits = check(&format!("soup {n}"), &scene, &rays);
        assert!(hits >= rays.len() / 8, "soup {n}: only {hits} of {} rays hit", rays.len());
    }
}

#[test]
fn packet_matches_threaded_in_the_cornell_box() {
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    // Coherent camera rays, then the same image with a mixed ray every third slot.
    let primary = vkrt::bench::rays::primary(&scene, 64, 48).unwrap();
    let mixed = mixed_rays(&scene, primary.len(), 11);
    let interleaved: Vec<GpuRay> = primary.iter().zip(&mixed).enumerate().map(|(i, (p, m))| if i % 3 == 2 { *m } else { *p }).collect();
    for (name, rays) in [("cornell primary", &primary), ("cornell mixed", &mixed), ("cornell interleaved", &interleaved)] {
        let hits = check(name, &scene, rays);
        assert!(hits >= rays.len() / 4, "{name}: only {hits} of {} rays hit", rays.len());
    }
}
