//! What the path tracer does for mirrors (`PathSettings::mirror_sampling`): the mirror probe
//! (shaders/include/mirror_probe.glsl: where a mirror over a Lambert lobe reflects the black
//! outside of an open scene, the camera ray's first hit takes the Lambert lobe for most
//! samples) and light sampled through planar mirrors (shaders/include/mirror_light.glsl). Both
//! are estimator changes, so: the same expectation with and without them, less noise where they
//! act, and runs that resume bit for bit (the probe is recomputed).
//! Measured on lavapipe (1024 spp, seeds 1 and 2): image means 0.17307 with and 0.17331
//! without (-0.14 %; 1 % allowed per channel), the image's noise 0.00236 against 0.00711
//! (0.33x: the mirror throws the lamp onto the floor, which light sampling now aims at); the
//! panel's centre 0.05601 against 0.05588 (+0.2 %; 3 % allowed, about four standard errors of
//! the mean without), its noise 0.00077 against 0.00441 (0.17x).

mod common;

use common::noise::{image_noise, luminance, noise_over};
use common::procedural::quad;
use glam::Vec3;
use vkrt::integrator::path::{self, Accumulation, PathSettings};
use vkrt::integrator::Image;
use vkrt::scene::{Camera, Light, Material, Scene};

const SIZE: u32 = 48;

/// An open box (no front wall, no sky) lit by a small ceiling quad, with a mirror panel on the
/// back wall facing the opening: Ks 0.8 over Kd 0.5, so the Lambert lobe (albedo 0.1) is
/// picked 1 time in 9 by albedo. Seen from the default camera in front of the opening, the
/// whole panel reflects the opening, i.e. black, and its light comes through the Lambert lobe;
/// the panel also throws the lamp's light onto the floor (light through a planar mirror).
fn open_box_with_a_dark_mirror(test: &str) -> vkrt::scene::Scene {
    // A directory per test: tests run in parallel.
    let mtl = "newmtl white\nKd 0.7 0.7 0.7\n\
               newmtl light\nKd 0 0 0\nKe 12 12 12\n\
               newmtl mirror\nKd 0.5 0.5 0.5\nKs 0.8 0.8 0.8\nillum 5\n";
    // Faces wind counter-clockwise seen from inside the box (the light faces down, the mirror +z).
    // The mirror face is given twice, as files do (CornellBox-Mirror.obj repeats its tall box's
    // front face): light through it must not be counted twice.
    let obj = "mtllib box.mtl\n\
        v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n\
        v -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\n\
        v -0.3 1.99 -0.3\nv 0.3 1.99 -0.3\nv 0.3 1.99 0.3\nv -0.3 1.99 0.3\n\
        v -0.7 0.3 -0.99\nv 0.7 0.3 -0.99\nv 0.7 1.7 -0.99\nv -0.7 1.7 -0.99\n\
        usemtl white\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 1 5 8 4\nf 2 3 7 6\n\
        usemtl light\nf 9 10 11 12\n\
        usemtl mirror\nf 13 14 15 16\nf 14 15 16 13\n";
    common::noise::load_obj_text(&format!("mirrors_{test}"), obj, mtl)
}

fn settings(spp: u64, seed: u32, mirror_sampling: bool) -> PathSettings {
    let mut s = common::path_settings(SIZE, SIZE, spp);
    s.image.seed = seed;
    s.mirror_sampling = mirror_sampling;
    s
}

/// The central 8 x 8 pixels: on the mirror panel, which fills the middle of the image.
fn centre() -> impl Iterator<Item = (u32, u32)> {
    let lo = SIZE / 2 - 4;
    (lo..lo + 8).flat_map(move |y| (lo..lo + 8).map(move |x| (x, y)))
}

/// The centre's mean luminance.
fn centre_mean(image: &Image) -> f64 {
    centre().map(|p| luminance(image, p)).sum::<f64>() / 64.0
}

/// The noise in the centre (common::noise::noise_over).
fn centre_noise(a: &Image, b: &Image) -> f64 {
    noise_over(a, b, centre())
}

#[test]
fn mirror_sampling_converges_to_the_same_light_with_less_noise() {
    let scene = open_box_with_a_dark_mirror("converges");
    let render = |seed: u32, probe: bool| common::render_path(&scene, &settings(1024, seed, probe)).image();
    let on = [render(1, true), render(2, true)];
    let off = [render(1, false), render(2, false)];
    for (a, b) in on.iter().zip(&off) {
        let (m_on, m_off) = (a.mean(), b.mean());
        for k in 0..3 {
            assert!((m_on[k] - m_off[k]).abs() <= 0.01 * m_off[k], "channel {k} means {} vs {}", m_on[k], m_off[k]);
        }
    }
    let mean_on = (centre_mean(&on[0]) + centre_mean(&on[1])) / 2.0;
    let mean_off = (centre_mean(&off[0]) + centre_mean(&off[1])) / 2.0;
    let (noise_on, noise_off) = (centre_noise(&on[0], &on[1]), centre_noise(&off[0], &off[1]));
    let (image_on, image_off) = (image_noise(&on[0], &on[1]), image_noise(&off[0], &off[1]));
    eprintln!("centre: mean {mean_on:.5} with mirror sampling, {mean_off:.5} without; noise {noise_on:.5} vs {noise_off:.5}; image noise {image_on:.5} vs {image_off:.5}");
    // Less noise over the image: the light the mirror throws onto the floor is aimed at.
    assert!(image_on < 0.6 * image_off, "image noise {image_on} with mirror sampling, {image_off} without");
    // The panel is lit (through its Lambert lobe), not black.
    assert!(mean_off > 1e-2, "the mirror panel's light is missing: {mean_off}");
    // The same expectation: both estimators are unbiased.
    assert!((mean_on - mean_off).abs() <= 0.03 * mean_off, "centre means differ: {mean_on} with the probe, {mean_off} without");
    // Less noise where the probe acts: most samples now take the lobe that carries the light.
    assert!(noise_on < 0.5 * noise_off, "centre noise {noise_on} with the probe, {noise_off} without");
}

#[test]
fn a_resumed_run_probes_again_and_continues_bit_for_bit() {
    let scene = open_box_with_a_dark_mirror("resume");
    let ctx = common::gpu_context();
    let gpu = common::upload(&ctx, &scene);
    let run = |s: &PathSettings, resume: Option<Accumulation>| path::render(&ctx, &gpu, s, resume, &mut Default::default()).unwrap().0;
    let straight = run(&settings(8, 1, true), None);
    let mut first = settings(8, 1, true);
    first.stop.spp = Some(4);
    let half = run(&first, None);
    let resumed = run(&settings(8, 1, true), Some(half));
    assert!(
        resumed.even == straight.even && resumed.odd == straight.odd && resumed.counts == straight.counts,
        "4 + 4 resumed spp differ from 8 spp in one run"
    );
    // And the probe changed the image (else this test would not test it).
    let off = run(&settings(8, 1, false), None);
    assert!(off.even != straight.even, "the probe did not act on the dark mirror");
}

/// A Lambert floor (albedo 0.5, z = 0, facing +z) seen from straight above, lit by `light`,
/// and a flat mirror (Ks 0.8, no Lambert lobe) standing on the plane x = 1, facing the camera's
/// target (the origin).
fn floor_beside_a_mirror(light: Light) -> Scene {
    let floor = Material { name: "floor".into(), diffuse: Vec3::splat(0.5), ..Material::default() };
    let mirror = Material { name: "mirror".into(), illum: 3, specular: Vec3::splat(0.8), diffuse: Vec3::ZERO, ..Material::default() };
    let mut triangles = quad(Vec3::new(-50.0, -50.0, 0.0), Vec3::new(100.0, 0.0, 0.0), Vec3::new(0.0, 100.0, 0.0), 0).to_vec();
    // u x v = -x: the front faces the target.
    triangles.extend(quad(Vec3::new(1.0, -3.0, 0.0), Vec3::new(0.0, 0.0, 6.0), Vec3::new(0.0, 6.0, 0.0), 1));
    Scene {
        triangles,
        materials: vec![floor, mirror],
        lights: vec![light],
        camera: Camera { eye: Vec3::new(0.0, 0.0, 10.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 10.0, ..Camera::default() },
        ..Scene::default()
    }
}

#[test]
fn a_point_light_seen_in_a_flat_mirror_lights_the_floor_by_its_analytic_value() {
    // Lambert: L = rho / pi (E_direct + E_mirror). Direct: I cos / d^2 = 32 / 16. Through the
    // mirror the floor sees the light's image at (2, 0, 4): Ks I cos' / d'^2 with d'^2 = 20 and
    // cos' = 4 / sqrt(20) (the segment to the image crosses the mirror at (1, 0, 2), on it). At
    // most 3 segments, no path goes on past these (the floor -> mirror -> floor path ends at
    // its second floor hit), so the answer is exact up to the pixel's footprint (< 0.5 %).
    // Without aiming through the mirror BSDF sampling cannot find this light (a delta light by
    // way of a delta mirror): the floor would show direct light only.
    let (rho, i) = (0.5f32, 32.0f32);
    let scene = floor_beside_a_mirror(Light::Point { position: Vec3::new(0.0, 0.0, 4.0), intensity: Vec3::splat(i) });
    let direct = rho / std::f32::consts::PI * i / 16.0;
    let through = rho / std::f32::consts::PI * 0.8 * i * (4.0 / 20f32.sqrt()) / 20.0;
    assert_mirror_adds(&scene, direct, through);
}

#[test]
fn a_sun_seen_in_a_flat_mirror_lights_the_floor_by_its_analytic_value() {
    // A directional light of irradiance E from (-0.6, 0, 0.8): E cos = 0.8 E directly, and
    // reflected in the mirror (plane x = 1) it arrives from (0.6, 0, 0.8), through the mirror at
    // (1, 0, 4/3) seen from the origin: another 0.8 Ks E.
    let (rho, e) = (0.5f32, 2.0f32);
    let scene = floor_beside_a_mirror(Light::Directional { direction: Vec3::new(-0.6, 0.0, 0.8), intensity: Vec3::splat(e) });
    let direct = rho / std::f32::consts::PI * e * 0.8;
    assert_mirror_adds(&scene, direct, 0.8 * direct);
}

/// The floor's centre pixel is `direct + through` with light aimed through the mirror (at most
/// 3 segments per path, so nothing else reaches it), `direct` without, and `direct` at max
/// depth 2 (the mirror's path has three segments), each within 1 %.
fn assert_mirror_adds(scene: &Scene, direct: f32, through: f32) {
    let centre = |max_depth: u32, mirror_sampling: bool| {
        let mut s = common::path_settings(8, 8, 4);
        s.max_depth = Some(max_depth);
        s.mirror_sampling = mirror_sampling;
        common::render_path(scene, &s).image().get(4, 4)
    };
    for c in centre(3, true) {
        assert!((c / (direct + through) - 1.0).abs() < 0.01, "with the mirror: {c} vs {}", direct + through);
    }
    for c in centre(3, false) {
        assert!((c / direct - 1.0).abs() < 0.01, "without aiming through the mirror: {c} vs {direct}");
    }
    // Two segments per path: camera -> floor -> light only; the mirror's path has three.
    for c in centre(2, true) {
        assert!((c / direct - 1.0).abs() < 0.01, "max depth 2: {c} vs {direct}");
    }
}
