//! The thin-lens camera (`--aperture`, `--focus-distance`; scene::camera::Lens): with no
//! aperture it is the pinhole, bit for bit; with one, the plane in focus stays sharp and an
//! edge off it blurs by the circle of confusion the lens equation predicts.

mod common;

use common::procedural::quad;
use glam::{Vec2, Vec3};
use vkrt::bvh::BuilderKind;
use vkrt::integrator::{whitted, Image, RenderSettings};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::scene::camera::{concentric_disk, Lens};
use vkrt::scene::{Camera, Material, Scene};

const SIZE: u32 = 128;
const FOV_DEG: f32 = 40.0;
const NEAR: f32 = 2.0;
const FAR: f32 = 8.0;
const APERTURE: f32 = 0.12;

/// Two emitters facing the camera (at the origin, looking down -z) on a black background: a
/// near one at depth NEAR over the top half of the image and a far one at depth FAR over the
/// bottom half, each filling the left half, so each has a vertical edge down the middle column.
fn two_edges(lens: Lens) -> Scene {
    let light = Material { name: "light".into(), diffuse: Vec3::ZERO, emission: Vec3::ONE, ..Material::default() };
    let mut triangles = Vec::new();
    triangles.extend(quad(Vec3::new(-10.0, 0.0, -NEAR), Vec3::X * 10.0, Vec3::Y * 10.0, 0));
    triangles.extend(quad(Vec3::new(-40.0, -40.0, -FAR), Vec3::X * 40.0, Vec3::Y * 40.0, 0));
    let camera = Camera { eye: Vec3::ZERO, target: -Vec3::Z, up: Vec3::Y, fov_y_deg: FOV_DEG, lens };
    Scene { triangles, materials: vec![light], camera, ..Scene::default() }
}

/// The image's radius of the circle of confusion, in pixels, of a point at `depth` seen
/// through the lens focused at `focus`: a lens point at lateral offset a reaches it through
/// the pinhole direction (x - a (1 - depth / focus)) / depth, so the directions span
/// 2 R |1 / depth - 1 / focus| in tangent units.
fn coc_radius_px(depth: f32, focus: f32) -> f32 {
    let px_per_tan = SIZE as f32 / (2.0 * (FOV_DEG.to_radians() / 2.0).tan());
    APERTURE * (1.0 / depth - 1.0 / focus).abs() * px_per_tan
}

/// How far the edge spreads, in pixels: sum over a row of |value - ideal step| averaged over
/// `rows`, the step at the middle column (value 1 left of it, 0 right). For a disc of radius
/// r it is E|X| = 4 r / (3 pi) (the mean |x| of a uniform disc's marginal), plus the pixel
/// box's 1/4 when r is small.
fn edge_spread(image: &Image, rows: std::ops::Range<u32>) -> f32 {
    let n = rows.len() as f32;
    let mut total = 0.0;
    for y in rows {
        for x in 0..image.width {
            let ideal = if x < image.width / 2 { 1.0 } else { 0.0 };
            total += (image.get(x, y)[1] - ideal).abs();
        }
    }
    total / n
}

fn render_path(scene: &Scene, spp: u64) -> Image {
    let mut settings = common::path_settings(SIZE, SIZE, spp);
    settings.max_depth = Some(1);
    common::render_path(scene, &settings).image()
}

fn render_whitted(scene: &Scene, spp: u32) -> Image {
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(scene, &PrepareOptions { builder: BuilderKind::Sah, ..Default::default() }).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let settings = RenderSettings { width: SIZE, height: SIZE, spp, max_depth: 1, ..RenderSettings::default() };
    let (image, _) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    common::assert_no_validation_messages(&ctx);
    image
}

#[test]
fn cpu_twin_rays_of_one_pixel_meet_on_the_plane_of_focus() {
    let camera = Camera { eye: Vec3::new(1.0, 2.0, 3.0), target: Vec3::new(0.0, 1.0, -4.0), up: Vec3::Y, fov_y_deg: 50.0, lens: Lens::PINHOLE };
    let pinhole = camera.frame().unwrap();
    let lens = Camera { lens: Lens { aperture_radius: 0.3, focus_distance: 0.0 }, ..camera }.frame().unwrap();
    // Focus distance 0 means the target's distance.
    assert!((lens.focus_distance - (camera.target - camera.eye).length()).abs() < 1e-5);
    let (x, y) = (37.3, 11.8);
    let d = pinhole.ray_direction(x, y, 64, 48);
    let focus_point = pinhole.origin + d * (lens.focus_distance / d.dot(pinhole.forward));
    let mut spread = 0.0f32;
    for i in 0..16 {
        let u = Vec2::new((i % 4) as f32 / 4.0 + 0.1, (i / 4) as f32 / 4.0 + 0.2);
        // No aperture: the pinhole ray whatever the lens sample.
        assert_eq!(pinhole.ray(x, y, 64, 48, u), (pinhole.origin, d));
        let (o, dir) = lens.ray(x, y, 64, 48, u);
        assert!((dir.length() - 1.0).abs() < 1e-5);
        // The origin lies on the aperture disc, in the lens plane.
        let offset = o - lens.origin;
        assert!(offset.dot(lens.forward).abs() < 1e-5 && offset.length() <= 0.3 + 1e-5, "origin {o}");
        spread = spread.max(offset.length());
        // And the ray passes through the pinhole ray's point on the plane of focus.
        let t = (focus_point - o).dot(dir);
        assert!((o + t * dir - focus_point).length() < 1e-4, "misses the focus point by {}", (o + t * dir - focus_point).length());
    }
    assert!(spread > 0.15, "lens samples stay near the centre ({spread})");
    // The disc map keeps the square's centre and corners' radii.
    assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
    assert!((concentric_disk(Vec2::new(1.0, 0.5)).length() - 1.0).abs() < 1e-6);
}

#[test]
fn no_aperture_renders_the_pinhole_image_bit_for_bit() {
    let pinhole = two_edges(Lens::PINHOLE);
    let zero = two_edges(Lens { aperture_radius: 0.0, focus_distance: 3.0 });
    assert_eq!(render_path(&pinhole, 8).pixels, render_path(&zero, 8).pixels, "path tracer");
    assert_eq!(render_whitted(&pinhole, 4).pixels, render_whitted(&zero, 4).pixels, "Whitted");
}

#[test]
fn the_plane_in_focus_stays_sharp_and_the_other_blurs_by_its_circle_of_confusion() {
    let pinhole = render_path(&two_edges(Lens::PINHOLE), 64);
    let lens = render_path(&two_edges(Lens { aperture_radius: APERTURE, focus_distance: NEAR }), 256);
    // Rows well inside each half: the near emitter's top rows, the far one's bottom rows.
    let (near_rows, far_rows) = (4..40, SIZE - 40..SIZE - 4);
    let r = coc_radius_px(FAR, NEAR);
    let expected = 4.0 * r / (3.0 * std::f32::consts::PI);
    let (pin_near, pin_far) = (edge_spread(&pinhole, near_rows.clone()), edge_spread(&pinhole, far_rows.clone()));
    let (near, far) = (edge_spread(&lens, near_rows), edge_spread(&lens, far_rows));
    eprintln!("edge spread (px): pinhole near {pin_near:.3} far {pin_far:.3}; lens near {near:.3} far {far:.3} (expected {expected:.3}, r = {r:.2} px)");
    // The pinhole's edges are one pixel's box filter wide (1/4 px of spread).
    assert!(pin_near < 0.4 && pin_far < 0.4, "pinhole edges spread {pin_near}, {pin_far}");
    // In focus: as sharp as the pinhole's.
    assert!(near < pin_near + 0.15, "the in-focus edge spreads {near} px (pinhole {pin_near})");
    // Out of focus: the disc's spread, within the Monte Carlo noise and the pixel box.
    assert!((far - expected).abs() < 0.12 * expected + 0.3, "the out-of-focus edge spreads {far} px, expected {expected}");
}

#[test]
fn whitted_blurs_with_samples_and_is_a_pinhole_at_one() {
    let scene = two_edges(Lens { aperture_radius: APERTURE, focus_distance: NEAR });
    let one = render_whitted(&scene, 1);
    assert_eq!(one.pixels, render_whitted(&two_edges(Lens::PINHOLE), 1).pixels, "one sample looks through the lens centre");
    let many = render_whitted(&scene, 64);
    let far_rows = SIZE - 40..SIZE - 4;
    let expected = 4.0 * coc_radius_px(FAR, NEAR) / (3.0 * std::f32::consts::PI);
    let (near, far) = (edge_spread(&many, 4..40), edge_spread(&many, far_rows));
    eprintln!("Whitted edge spread (px): near {near:.3}, far {far:.3} (expected {expected:.3})");
    assert!(near < 0.5, "the in-focus edge spreads {near} px");
    assert!((far - expected).abs() < 0.2 * expected + 0.3, "the out-of-focus edge spreads {far} px, expected {expected}");
}
