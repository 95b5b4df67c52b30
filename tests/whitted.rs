//! The Whitted integrator against values worked out by hand: hard shadows from a point light,
//! mirror reflection weighted by Ks, Fresnel-weighted refraction through a glass slab, and
//! the depth limit. Each scene is built in code so the expected value follows from its numbers.

mod common;

use common::procedural::quad;
use glam::Vec3;
use vkrt::bvh::BuilderKind;
use vkrt::integrator::{whitted, RenderSettings};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::scene::{Camera, Light, Material, Scene, Triangle};

/// Renders a 3x3 image with one sample at each pixel centre and returns the centre pixel,
/// whose ray runs exactly along the camera's forward axis.
fn centre_pixel(scene: &Scene, max_depth: u32) -> [f32; 3] {
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(scene, &PrepareOptions { builder: BuilderKind::Sah, ..Default::default() }).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let settings = RenderSettings { width: 3, height: 3, spp: 1, max_depth, ..RenderSettings::default() };
    let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(&ctx);
    image.get(1, 1)
}

fn assert_close(what: &str, got: [f32; 3], want: [f32; 3], tol: f32) {
    for k in 0..3 {
        assert!((got[k] - want[k]).abs() <= tol, "{what}: got {got:?}, want {want:?} (tolerance {tol})");
    }
}

fn emitter(radiance: Vec3) -> Material {
    Material { name: "emitter".into(), diffuse: Vec3::ZERO, emission: radiance, ..Material::default() }
}

/// The 12 triangles of the box [lo, hi], faces counter-clockwise seen from outside.
fn boxed(lo: Vec3, hi: Vec3, material: u32) -> Vec<Triangle> {
    let e = hi - lo;
    let (x, y, z) = (Vec3::X * e.x, Vec3::Y * e.y, Vec3::Z * e.z);
    [
        quad(lo, y, x, material),     // -z face
        quad(lo + z, x, y, material), // +z face
        quad(lo, z, y, material),     // -x face
        quad(lo + x, y, z, material), // +x face
        quad(lo, x, z, material),     // -y face
        quad(lo + y, z, x, material), // +y face
    ]
    .into_iter()
    .flatten()
    .collect()
}

fn scene(triangles: Vec<Triangle>, materials: Vec<Material>, camera: Camera, lights: Vec<Light>) -> Scene {
    Scene { triangles, materials, lights, camera, ambient: Vec3::ZERO, ..Scene::default() }
}

#[test]
fn point_light_lights_the_floor_and_an_occluder_casts_a_hard_shadow() {
    // Floor y = 0 (Kd 0.5), point light of intensity 1 one unit above the origin; the camera
    // looks at the origin from the side, so an occluder over the origin is out of its view.
    let floor = Material { name: "floor".into(), diffuse: Vec3::splat(0.5), ..Material::default() };
    let camera = Camera { eye: Vec3::new(0.0, 1.0, 2.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 30.0, ..Camera::default() };
    let light = Light::Point { position: Vec3::Y, intensity: Vec3::ONE };
    let mut tris: Vec<Triangle> = quad(Vec3::new(-2.0, 0.0, 2.0), Vec3::X * 4.0, Vec3::Z * -4.0, 0).to_vec();
    let lit = centre_pixel(&scene(tris.clone(), vec![floor.clone()], camera, vec![light]), 7);
    // Kd * cos * I / d^2 = 0.5 * 1 * 1 / 1 (no ambient, no specular).
    assert_close("lit floor", lit, [0.5; 3], 1e-4);
    tris.extend(quad(Vec3::new(-0.1, 0.5, 0.1), Vec3::X * 0.2, Vec3::Z * -0.2, 0));
    let shadowed = centre_pixel(&scene(tris, vec![floor], camera, vec![light]), 7);
    assert_close("shadowed floor", shadowed, [0.0; 3], 0.0);
}

#[test]
fn mirror_reflects_the_emitter_behind_the_camera_weighted_by_ks() {
    // Camera at the origin looking down -z at a mirror (Ks 0.8, illum 3) at z = -1; behind the
    // camera, at z = +1, an emitter facing the mirror. The centre ray reflects straight back.
    let ks = 0.8;
    let mirror = Material {
        name: "mirror".into(),
        diffuse: Vec3::ZERO,
        specular: Vec3::splat(ks),
        // A highlight this sharp is zero away from the exact mirror direction, so the centre
        // pixel is the reflection alone.
        shininess: 1e6,
        illum: 3,
        ..Material::default()
    };
    let le = Vec3::new(1.0, 0.5, 0.25);
    let camera = Camera { eye: Vec3::ZERO, target: -Vec3::Z, up: Vec3::Y, fov_y_deg: 20.0, ..Camera::default() };
    let mirror_quad = quad(Vec3::new(-1.0, -1.0, -1.0), Vec3::X * 2.0, Vec3::Y * 2.0, 0);
    // Facing -z (toward the mirror): u x v = Y x X = -Z.
    let facing = quad(Vec3::new(-1.0, -1.0, 1.0), Vec3::Y * 2.0, Vec3::X * 2.0, 1);
    let tris: Vec<Triangle> = mirror_quad.iter().chain(facing.iter()).copied().collect();
    let s = scene(tris, vec![mirror.clone(), emitter(le)], camera, vec![]);
    assert_close("mirror, depth 2", centre_pixel(&s, 2), (le * ks).to_array(), 1e-5);
    // One ray per path: the reflection is never traced.
    assert_close("mirror, depth 1", centre_pixel(&s, 1), [0.0; 3], 0.0);
    // Emitters emit from their front face only: turned away, the mirror shows nothing.
    let away = quad(Vec3::new(-1.0, -1.0, 1.0), Vec3::X * 2.0, Vec3::Y * 2.0, 1);
    let tris: Vec<Triangle> = mirror_quad.iter().chain(away.iter()).copied().collect();
    let s = scene(tris, vec![mirror, emitter(le)], camera, vec![]);
    assert_close("mirror, emitter facing away", centre_pixel(&s, 7), [0.0; 3], 0.0);
}

#[test]
fn glass_slab_transmits_by_fresnel_at_normal_incidence() {
    // Camera looking down -z through a glass slab (n = 1.5) at an emitter of radiance 1.
    // At normal incidence each interface reflects F = ((n-1)/(n+1))^2 = 0.04 and transmits 0.96.
    let glass = Material { name: "glass".into(), diffuse: Vec3::ZERO, ior: 1.5, illum: 7, ..Material::default() };
    let camera = Camera { eye: Vec3::new(0.0, 0.0, 1.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 10.0, ..Camera::default() };
    let mut tris = boxed(Vec3::new(-1.0, -1.0, -2.0), Vec3::new(1.0, 1.0, -1.0), 0);
    // Emitter at z = -3 facing +z (toward the camera).
    tris.extend(quad(Vec3::new(-4.0, -4.0, -3.0), Vec3::X * 8.0, Vec3::Y * 8.0, 1));
    let s = scene(tris, vec![glass, emitter(Vec3::ONE)], camera, vec![]);
    let (f, t) = (0.04f32, 0.96f32);
    // Depth 3: camera -> front face -> back face -> emitter: T^2.
    assert_close("glass, depth 3", centre_pixel(&s, 3), [t * t; 3], 2e-4);
    // Depth 7 adds the paths that bounce inside the slab twice and four times:
    // T^2 (1 + F^2 + F^4).
    let deep = t * t * (1.0 + f * f + f.powi(4));
    assert_close("glass, depth 7", centre_pixel(&s, 7), [deep; 3], 2e-4);
    // Depth 2 cannot reach the emitter through two interfaces.
    assert_close("glass, depth 2", centre_pixel(&s, 2), [0.0; 3], 0.0);
}

/// The ray tree lives on a fixed stack: depths 1 to whitted::MAX_DEPTH render, others are an
/// error that names the limit (it used to clamp them silently while reporting the depth asked for).
#[test]
fn depths_outside_the_stack_are_refused_by_name() {
    let scene = common::procedural::random_soup(20, 5);
    let ctx = common::gpu_context();
    let gpu = common::upload(&ctx, &scene);
    for (depth, ok) in [(0, false), (1, true), (whitted::MAX_DEPTH, true), (whitted::MAX_DEPTH + 1, false)] {
        let settings = RenderSettings { width: 4, height: 4, max_depth: depth, ..RenderSettings::default() };
        match whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}) {
            Ok(_) => assert!(ok, "depth {depth} rendered"),
            Err(e) => {
                assert!(!ok, "depth {depth} refused: {e:#}");
                assert!(format!("{e:#}").contains(&format!("1 to {}", whitted::MAX_DEPTH)), "{e:#}");
            }
        }
    }
}
