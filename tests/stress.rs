//! Numerical robustness, small sizes (the full sweep is an opt-in tool).
//!
//! Leaks: closed meshes with shared vertices (icosphere, subdivided cube, torus) scaled from
//! 1e-4 to 1e6 and moved up to 1e5 from the origin; rays from inside in random directions and
//! aimed exactly at every vertex and edge midpoint. Every ray must hit, leaving through the
//! inside of the mesh (first hit on a back face, or exactly on a shared vertex or edge), on the
//! GPU and on its CPU twin.

mod common;

use common::Pcg;
use glam::Vec3;
use vkrt::bvh::{BuildConfig, BuilderKind};
use vkrt::integrator::gpu_scene::{GpuScene, PreparedScene};
use vkrt::integrator::ray_query::trace_rays;
use vkrt::layout::constants::PRIM_NONE;
use vkrt::layout::cpu_trace;
use vkrt::layout::GpuRay;
use vkrt::scene::closed_meshes::{icosphere, subdivided_cube, torus, IndexedMesh};
use vkrt::scene::procedural::scene_of;

#[test]
fn closed_meshes_are_closed_and_wound_outward() {
    for (name, mesh) in [("icosphere", icosphere(2)), ("cube", subdivided_cube(4)), ("torus", torus(1.0, 0.4, 16, 8))] {
        // Every directed edge appears once and its reverse once: closed and consistently wound.
        let mut directed = std::collections::HashMap::new();
        for t in &mesh.triangles {
            for k in 0..3 {
                *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &directed {
            assert_eq!(n, 1, "{name}: edge {a}->{b} used {n} times");
            assert_eq!(directed.get(&(b, a)), Some(&1), "{name}: edge {a}->{b} has no twin");
        }
        // Positive signed volume: normals point outward.
        let volume: f32 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!(volume > 0.0, "{name}: signed volume {volume}");
    }
}

/// Points inside the mesh (before scale and offset) to shoot from.
fn inside_points(name: &str) -> Vec<Vec3> {
    match name {
        // On the tube's centre circle, at a few angles.
        "torus" => (0..4).map(|k| {
            let a = k as f32 * 1.3;
            Vec3::new(a.cos(), 0.0, a.sin())
        }).collect(),
        _ => vec![Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1)],
    }
}

/// Counts the rays that leak (miss, or first hit not leaving through the inside).
fn leaks(mesh: &IndexedMesh, name: &str, scale: f32, offset: Vec3, ctx: &vkrt::gpu::Context) -> (usize, usize) {
    let scene = scene_of(mesh.to_triangles(scale, offset, 0));
    let world: Vec<Vec3> = mesh.positions.iter().map(|&p| p * scale + offset).collect();
    let mut rng = Pcg::new(17);
    let mut rays = Vec::new();
    for o in inside_points(name) {
        let origin = o * scale + offset;
        let mut push = |d: Vec3| {
            if d != Vec3::ZERO && d.is_finite() {
                rays.push(GpuRay { origin: origin.to_array(), tmin: 0.0, direction: d.to_array(), tmax: f32::INFINITY });
            }
        };
        for &v in &world {
            push(v - origin);
        }
        for (a, b) in mesh.edges() {
            push((world[a as usize] + world[b as usize]) * 0.5 - origin);
        }
        for _ in 0..500 {
            push(rng.unit_vector());
        }
    }
    let prepared = PreparedScene::new(&scene, BuilderKind::Sah, &BuildConfig::default()).unwrap();
    let gpu = GpuScene::upload(ctx, &prepared).unwrap();
    let gpu_hits = trace_rays(ctx, &gpu, &rays, false).unwrap();
    let mut leaked = 0;
    for (ray, g) in rays.iter().zip(&gpu_hits) {
        let c = cpu_trace::trace(&prepared.flat.nodes, &prepared.flat.triangles, ray, false);
        for h in [c, *g] {
            let dir = Vec3::from(ray.direction);
            let ok = h.prim != PRIM_NONE && {
                // From inside, the first surface is seen from its back. A ray through (or within
                // float noise of) a shared vertex or edge hits every triangle around it at the
                // same t, and on saddle-shaped parts (the torus's inner ring) one of those may
                // face the ray: then a back-facing triangle must be hit at that same t.
                scene.triangles[h.prim as usize].cross().dot(dir) > 0.0 || {
                    let r = cpu_trace::RayPre::new(ray);
                    let exit = scene
                        .triangles
                        .iter()
                        .filter(|t| t.cross().dot(dir) > 0.0)
                        .filter_map(|t| cpu_trace::intersect_triangle(&r, t.p[0], t.p[1], t.p[2], f32::INFINITY))
                        .map(|x| x.t)
                        .fold(f32::INFINITY, f32::min);
                    (exit - h.t).abs() <= 1e-5 * h.t
                }
            };
            leaked += (!ok) as usize;
        }
    }
    (leaked, rays.len() * 2)
}

#[test]
fn no_ray_leaks_out_of_closed_meshes_at_any_scale() {
    let ctx = common::gpu_context();
    let meshes = [("icosphere", icosphere(3)), ("cube", subdivided_cube(8)), ("torus", torus(1.0, 0.4, 48, 24))];
    let scales = [1e-4f32, 1e-2, 1.0, 1e2, 1e4, 1e6];
    let offsets = [Vec3::ZERO, Vec3::new(1e3, -2e2, 5e2), Vec3::new(1e5, -3e4, 7e4)];
    let mut total = 0;
    for (name, mesh) in &meshes {
        for &scale in &scales {
            for &offset in &offsets {
                // A mesh far smaller than the float spacing at its position cannot be
                // represented at all; keep cases whose size is at least 1e-3 of the offset.
                if scale < offset.abs().max_element() * 1e-3 {
                    continue;
                }
                let (leaked, rays) = leaks(mesh, name, scale, offset, &ctx);
                println!("{name:9} scale {scale:8.0e} offset {:>22}: {rays} rays (GPU + CPU), {leaked} leaks", format!("{offset}"));
                assert_eq!(leaked, 0, "{name} at scale {scale:e}, offset {offset}: {leaked} of {rays} rays leaked");
                total += rays;
            }
        }
    }
    assert!(total > 100_000, "only {total} rays tried");
    common::assert_no_validation_messages(&ctx);
}
