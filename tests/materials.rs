//! glTF 2.0 material features in both integrators, from scenes built here whose answers follow
//! from their numbers: normal maps (a constant tilted normal under a directional light shades
//! as a tilted Lambert surface), MikkTSpace tangents, per-material alpha cut-off and BLEND's
//! stochastic transparency, and the metallic-roughness mapping of Whitted.

mod common;

use glam::{Vec2, Vec3, Vec4};
use std::f32::consts::PI;
use vkrt::integrator::{whitted, RenderSettings};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::scene::{Camera, Light, Material, MetallicRoughness, Scene, Texture, Triangle};

/// A 100 x 100 quad at height z facing +z, with texture coordinates (0, 0) .. (1, 1) along +x, +y.
fn uv_quad(z: f32, material: u32) -> [Triangle; 2] {
    let [a, b, c, d] = [Vec3::new(-50.0, -50.0, z), Vec3::new(50.0, -50.0, z), Vec3::new(50.0, 50.0, z), Vec3::new(-50.0, 50.0, z)];
    let [ta, tb, tc, td] = [Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 1.0)];
    [Triangle { p: [a, b, c], n: None, uv: Some([ta, tb, tc]), material }, Triangle { p: [a, c, d], n: None, uv: Some([ta, tc, td]), material }]
}

/// A 2 x 2 texture of one RGBA texel.
fn flat_texture(name: &str, rgba: [u8; 4]) -> Texture {
    Texture::from_rgba(name, 2, 2, &[rgba; 4]).unwrap()
}

/// Looking straight down at the floor from z = 10 under a directional light.
fn top_view(triangles: Vec<Triangle>, materials: Vec<Material>, textures: Vec<Texture>, light: Light) -> Scene {
    Scene {
        triangles,
        materials,
        textures,
        lights: vec![light],
        camera: Camera { eye: Vec3::new(0.0, 0.0, 10.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 10.0, ..Camera::default() },
        ..Scene::default()
    }
}

fn whitted_image(scene: &Scene) -> vkrt::integrator::Image {
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(scene, &PrepareOptions::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let settings = RenderSettings { width: 8, height: 8, spp: 1, max_depth: 4, ..RenderSettings::default() };
    let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(&ctx);
    image
}

fn mean(image: &vkrt::integrator::Image) -> f32 {
    image.pixels.iter().flatten().sum::<f32>() / (image.pixels.len() * 3) as f32
}

#[test]
fn mikktspace_tangents_of_a_quad_run_along_u() {
    // The quad's u runs along +x and v along +y: the tangent is +x and the bitangent
    // w cross(n, t) = w (+y) must be +v, so w = +1. Mirrored texture coordinates flip w.
    for (flip, want_w) in [(false, 1.0), (true, -1.0)] {
        let mut triangles = uv_quad(0.0, 0).to_vec();
        if flip {
            for t in &mut triangles {
                for uv in t.uv.as_mut().unwrap() {
                    uv.y = 1.0 - uv.y;
                }
            }
        }
        let material = Material { normal_texture: Some(0), ..Material::default() };
        let mut scene = Scene { triangles, materials: vec![material], textures: vec![flat_texture("n", [128, 128, 255, 255])], ..Scene::default() };
        vkrt::scene::tangents::fill_missing_tangents(&mut scene);
        assert_eq!(scene.tangents.len(), 2);
        for t in scene.tangents.iter().flatten() {
            assert!((t.truncate() - Vec3::X).length() < 1e-4, "tangent {t} is not +x (flipped v: {flip})");
            assert_eq!(t.w, want_w, "bitangent sign (flipped v: {flip})");
        }
    }
    // Tangents the file gave are kept; a scene without normal maps gets none.
    let given = [Vec4::new(0.0, 1.0, 0.0, -1.0); 3];
    let material = Material { normal_texture: Some(0), ..Material::default() };
    let mut scene = Scene { triangles: uv_quad(0.0, 0).to_vec(), materials: vec![material], tangents: vec![given, [Vec4::ZERO; 3]], ..Scene::default() };
    scene.textures.push(flat_texture("n", [128, 128, 255, 255]));
    vkrt::scene::tangents::fill_missing_tangents(&mut scene);
    assert_eq!(scene.tangents[0], given);
    assert!((scene.tangents[1][0].truncate() - Vec3::X).length() < 1e-4);
    let mut plain = Scene { triangles: uv_quad(0.0, 0).to_vec(), materials: vec![Material::default()], ..Scene::default() };
    vkrt::scene::tangents::fill_missing_tangents(&mut plain);
    assert!(plain.tangents.is_empty());
}

#[test]
fn a_constant_normal_map_shades_as_a_tilted_lambert_surface() {
    // The texel (r, g, b) is the tangent-space normal (2 c - 1) with x along u (= +x here);
    // scale 0.8 shortens its x and y. Under a directional light of irradiance E from
    // direction l, the path tracer gives rho / pi * E * (n'.l) and Whitted rho * E * (n'.l)
    // (scene::Light's units). Without the map the floor would be 22 % darker.
    let rgba = [190u8, 120, 230, 255];
    let scale = 0.8;
    let c = |b: u8| b as f32 / 255.0 * 2.0 - 1.0;
    let n = Vec3::new(c(rgba[0]) * scale, c(rgba[1]) * scale, c(rgba[2])).normalize();
    let l = Vec3::new(0.6, 0.0, 0.8);
    let (rho, e) = (0.5f32, 2.0f32);
    let material = Material { diffuse: Vec3::splat(rho), normal_texture: Some(0), normal_scale: scale, ..Material::default() };
    let mut scene =
        top_view(uv_quad(0.0, 0).to_vec(), vec![material], vec![flat_texture("normal", rgba)], Light::Directional { direction: l, intensity: Vec3::splat(e) });
    vkrt::scene::tangents::fill_missing_tangents(&mut scene);
    let path = common::render_path(&scene, &common::path_settings(8, 8, 4)).image();
    let want = rho / PI * e * n.dot(l);
    let flat = rho / PI * e * l.z;
    for px in path.pixels.iter().flatten() {
        assert!((px / want - 1.0).abs() < 0.01, "path tracer: {px} vs {want} (unmapped: {flat})");
    }
    let w = whitted_image(&scene);
    let want = rho * e * n.dot(l);
    for px in w.pixels.iter().flatten() {
        assert!((px / want - 1.0).abs() < 0.01, "Whitted: {px} vs {want}");
    }
}

#[test]
fn a_normal_map_that_tilts_below_the_surface_lets_no_light_through() {
    // A map whose normal lies in the surface's plane, pointing toward a light that grazes the
    // floor from below its horizon: the bent normal (surface.glsl) stays above the geometric
    // surface and the light, behind the floor, adds nothing. The light from above does.
    let material = Material { diffuse: Vec3::splat(0.5), normal_texture: Some(0), ..Material::default() };
    let below = Light::Directional { direction: Vec3::new(0.8, 0.0, -0.6), intensity: Vec3::splat(2.0) };
    let mut scene = top_view(uv_quad(0.0, 0).to_vec(), vec![material], vec![flat_texture("normal", [255, 128, 128, 255])], below);
    vkrt::scene::tangents::fill_missing_tangents(&mut scene);
    let path = common::render_path(&scene, &common::path_settings(8, 8, 4)).image();
    assert_eq!(mean(&path), 0.0, "light from behind the floor leaks through a normal-mapped surface");
    assert_eq!(mean(&whitted_image(&scene)), 0.0, "Whitted: light from behind the floor leaks through");
}

/// A black quad at z = 1 over a floor of albedo 0.5, lit from straight above (E = 2); the
/// quad's alpha texture has alpha `alpha` and its material the given mode.
fn veiled_floor(alpha: u8, blend: bool, cutoff: f32) -> Scene {
    let floor = Material { name: "floor".into(), diffuse: Vec3::splat(0.5), ..Material::default() };
    let veil = Material { name: "veil".into(), diffuse: Vec3::ZERO, alpha_texture: Some(0), alpha_blend: blend, alpha_cutoff: cutoff, ..Material::default() };
    let mut triangles = uv_quad(0.0, 0).to_vec();
    triangles.extend(uv_quad(1.0, 1));
    top_view(
        triangles,
        vec![floor, veil],
        vec![flat_texture("alpha", [0, 0, 0, alpha])],
        Light::Directional { direction: Vec3::Z, intensity: Vec3::splat(2.0) },
    )
}

#[test]
fn blend_is_stochastic_coverage_in_the_path_tracer_and_a_half_cut_out_in_whitted() {
    // Alpha 64/255 = 0.25: the path tracer sees the floor through the veil 75 % of the time,
    // and the floor sees the light through it 75 % of the time: 0.75^2 rho / pi E.
    let lit = 0.5 / PI * 2.0;
    let a = 64.0 / 255.0;
    let blend = veiled_floor(64, true, 0.5);
    let path = common::render_path(&blend, &common::path_settings(8, 8, 256)).image();
    let want = (1.0 - a) * (1.0 - a) * lit;
    let got = mean(&path);
    assert!((got / want - 1.0).abs() < 0.03, "BLEND in the path tracer: {got} vs {want}");
    // Whitted cuts BLEND out at 0.5: alpha 0.25 is see-through, the floor fully lit (rho E).
    assert!((mean(&whitted_image(&blend)) - 1.0).abs() < 1e-4);
    // With alpha 0.75 it is opaque, and black.
    assert_eq!(mean(&whitted_image(&veiled_floor(191, true, 0.5))), 0.0);
}

#[test]
fn mask_cuts_out_at_the_materials_own_cutoff_in_shadows_too() {
    // Alpha 0.25: see-through at cutoff 0.3, opaque at the lab's 0.2. Opaque, the veil hides
    // the floor and shadows it; see-through, neither.
    let lit = 0.5 / PI * 2.0;
    let open = veiled_floor(64, false, 0.3);
    assert!((mean(&common::render_path(&open, &common::path_settings(8, 8, 4)).image()) / lit - 1.0).abs() < 1e-3);
    assert!((mean(&whitted_image(&open)) - 1.0).abs() < 1e-4);
    let shut = veiled_floor(64, false, 0.2);
    assert_eq!(mean(&common::render_path(&shut, &common::path_settings(8, 8, 4)).image()), 0.0);
    // The floor under an opaque veil, seen from below the veil: a camera between them.
    let mut under = shut.clone();
    under.camera = Camera { eye: Vec3::new(0.0, 0.0, 0.5), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 10.0, ..Camera::default() };
    assert_eq!(mean(&common::render_path(&under, &common::path_settings(8, 8, 4)).image()), 0.0, "the opaque veil casts no shadow");
    let mut under_open = open.clone();
    under_open.camera = under.camera;
    assert!((mean(&common::render_path(&under_open, &common::path_settings(8, 8, 4)).image()) / lit - 1.0).abs() < 1e-3, "a cut-out casts a shadow");
}

#[test]
fn whitted_maps_metallic_roughness_onto_its_shading_model() {
    // A rough dielectric (metallic 0, roughness 1) is Lambert with Kd = base colour and a
    // faint highlight (Ks 0.04, Ns 0): rho E cos + 0.04 E (n.h)^0 = (rho cos + 0.04) E, seen
    // from above with the light from above. A rough metal has no diffuse term: Ks = base.
    let mr = |base: f32, metallic: f32| Material {
        diffuse: Vec3::splat(base),
        metallic_roughness: Some(MetallicRoughness { metallic, roughness: 1.0, texture: None }),
        ..Material::default()
    };
    let light = Light::Directional { direction: Vec3::Z, intensity: Vec3::splat(2.0) };
    let dielectric = top_view(uv_quad(0.0, 0).to_vec(), vec![mr(0.5, 0.0)], vec![], light);
    let got = mean(&whitted_image(&dielectric));
    assert!((got - (0.5 + 0.04) * 2.0).abs() < 1e-3, "rough dielectric: {got}");
    let metal = top_view(uv_quad(0.0, 0).to_vec(), vec![mr(0.5, 1.0)], vec![], light);
    let got = mean(&whitted_image(&metal));
    assert!((got - 0.5 * 2.0).abs() < 1e-3, "rough metal: {got}");
}
