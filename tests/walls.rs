//! The triangle list's walls (host/accel/walls.rs): listed triangles with the whole scene on one
//! side of their plane, which shadow rays between two points of the scene skip. On the CPU twin:
//! no such segment in the measured Cornell box is decided by a wall. On lavapipe: a light beyond
//! a wall (a point light above the ceiling, the sun) is not let in, by either integrator.

mod common;

use common::Pcg;
use glam::Vec3;
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::GpuRay;
use vkrt::integrator::{whitted, RenderSettings};
use vkrt::prepare::{upload::list_walls, GpuScene, PrepareOptions, PreparedScene};
use vkrt::scene::{Light, Scene};

/// A point on triangle `t` away from its edges (moved a tenth of the way to the centroid).
fn point_on(t: &vkrt::scene::Triangle, rng: &mut Pcg) -> Vec3 {
    let (mut a, mut b) = (rng.f32(), rng.f32());
    if a + b > 1.0 {
        (a, b) = (1.0 - a, 1.0 - b);
    }
    let (a, b) = (0.9 * a + 0.1 / 3.0, 0.9 * b + 0.1 / 3.0);
    t.p[0] + a * (t.p[1] - t.p[0]) + b * (t.p[2] - t.p[0])
}

#[test]
fn no_shadow_ray_between_points_of_the_cornell_box_is_decided_by_a_wall() {
    let scene = common::cornell_measured();
    let prepared = PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
    let walls = list_walls(&prepared.arrays(), &prepared.info);
    assert_eq!((prepared.flat.list().len(), walls.count_ones()), (10, 10), "the ten wall triangles are listed, and all are walls");
    let eps = 1e-4 * prepared.info.scale;
    let centre = prepared.info.bounds.center();
    let mut rng = Pcg::new(17);
    let (mut occluded, mut open) = (0, 0);
    for i in 0..20_000 {
        let (s, t) = (&scene.triangles[rng.below(scene.triangles.len())], &scene.triangles[rng.below(scene.triangles.len())]);
        let (p, q) = (point_on(s, &mut rng), point_on(t, &mut rng));
        // Each end moved off its surface toward the room's inside (the shaders move an end
        // toward the side it is seen from, which for a wall is the inside).
        let inward = |tri: &vkrt::scene::Triangle, from: Vec3| {
            let n = tri.cross().normalize();
            from + eps * if n.dot(centre - from) >= 0.0 { n } else { -n }
        };
        let (a, b) = (inward(s, p), inward(t, q));
        let ray = GpuRay { origin: a.into(), tmin: 0.0, direction: (b - a).into(), tmax: 1.0 };
        let all = prepared.flat.trace(&ray, true).prim != PRIM_NONE;
        let skipping = prepared.flat.trace_skipping(&ray, true, walls).prim != PRIM_NONE;
        assert_eq!(all, skipping, "segment {i} from {a} to {b}");
        if all {
            occluded += 1;
        } else {
            open += 1;
        }
    }
    // Both answers occur often: the check is not vacuous.
    assert!(occluded > 2000 && open > 2000, "{occluded} occluded, {open} open");
    // A ray that leaves the room does meet one: why the shaders skip walls only between points.
    let up = GpuRay { origin: [100.0, 400.0, 450.0], tmin: 0.0, direction: [0.0, 1.0, 0.0], tmax: f32::INFINITY };
    assert_ne!(prepared.flat.trace(&up, true).prim, PRIM_NONE);
    assert_eq!(prepared.flat.trace_skipping(&up, true, walls).prim, PRIM_NONE);
}

/// The measured Cornell box with its lamp put out, lit by `light` alone.
fn dark_box_lit_by(light: Light) -> Scene {
    let mut scene = common::cornell_measured();
    for m in &mut scene.materials {
        m.emission = Vec3::ZERO;
    }
    scene.lights = vec![light];
    scene.ambient = Vec3::ZERO;
    scene
}

/// Mean radiance of the path tracer's and the Whitted integrator's images of `scene`, 32², and
/// how many of the list's triangles were walls.
fn renders(scene: &Scene) -> (f64, f64, u32) {
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(scene, &PrepareOptions::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let mean = |img: &vkrt::integrator::Image| img.pixels.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>() / img.pixels.len() as f64;
    let path = mean(&common::render_path_on(&ctx, &gpu, &common::path_settings(32, 32, 16)).image());
    let settings = RenderSettings { width: 32, height: 32, spp: 1, max_depth: 4, ..RenderSettings::default() };
    let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(&ctx);
    (path, mean(&image), gpu.list_walls.count_ones())
}

#[test]
fn a_light_beyond_a_wall_stays_out() {
    let intensity = Vec3::splat(2e5);
    // Inside, under the ceiling: every listed triangle is a wall, and the box is lit.
    let (path, whitted, walls) = renders(&dark_box_lit_by(Light::Point { position: Vec3::new(278.0, 500.0, 279.5), intensity }));
    assert_eq!(walls, 10);
    assert!(path > 0.01 && whitted > 0.01, "lit from inside: path {path}, Whitted {whitted}");
    // Above the ceiling: the ceiling is no wall, and its shadow keeps the box dark.
    let (path, whitted, walls) = renders(&dark_box_lit_by(Light::Point { position: Vec3::new(278.0, 600.0, 279.5), intensity }));
    assert_eq!(walls, 8, "the ceiling's two triangles are no walls with the light beyond them");
    assert_eq!((path, whitted), (0.0, 0.0), "a point light above the ceiling");
    // The sun overhead: its shadow rays leave the scene, so they test the walls and stay out.
    let (path, whitted, walls) = renders(&dark_box_lit_by(Light::Directional { direction: Vec3::Y, intensity: Vec3::splat(5.0) }));
    assert_eq!(walls, 10);
    assert_eq!((path, whitted), (0.0, 0.0), "the sun above the ceiling");
}
