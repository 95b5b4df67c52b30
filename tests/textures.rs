//! Textures, alpha cut-outs and sky boxes, on scenes built in code so that every expected pixel
//! follows from the numbers: a camera with a 90-degree field of view one unit in front of the
//! square [-1, 1]^2 sees pixel (i, j) of a W x W image at x = (i + 0.5) / W * 2 - 1,
//! y = 1 - (j + 0.5) / W * 2 (host/scene/camera.rs).

mod common;

use glam::{Vec2, Vec3};
use vkrt::accel::LayoutKind;
use vkrt::bvh::BuilderKind;
use vkrt::integrator::path::{PathSettings, Stop};
use vkrt::integrator::{whitted, Image, RenderSettings};
use vkrt::prepare::{EnvLight, PrepareOptions};
use vkrt::scene::{Camera, Light, Material, Scene, Sky, Texture, Triangle};

const W: u32 = 8;

/// The quad p0 + s*e1 + t*e2 (s, t in [0, 1]) with uv = uv0 + (s, t) * uv_scale, counter-clockwise
/// seen from the side e1 x e2 points to.
fn uv_quad(p0: Vec3, e1: Vec3, e2: Vec3, uv0: Vec2, uv_scale: Vec2, material: u32) -> [Triangle; 2] {
    let p = [p0, p0 + e1, p0 + e1 + e2, p0 + e2];
    let uv = [uv0, uv0 + Vec2::new(uv_scale.x, 0.0), uv0 + uv_scale, uv0 + Vec2::new(0.0, uv_scale.y)];
    [
        Triangle { p: [p[0], p[1], p[2]], n: None, uv: Some([uv[0], uv[1], uv[2]]), material },
        Triangle { p: [p[0], p[2], p[3]], n: None, uv: Some([uv[0], uv[2], uv[3]]), material },
    ]
}

fn front_camera() -> Camera {
    Camera { eye: Vec3::new(0.0, 0.0, 1.0), target: Vec3::ZERO, up: Vec3::Y, fov_y_deg: 90.0, ..Camera::default() }
}

/// An unlit scene: ambient 1 and no lights, so Whitted shows each surface's albedo.
fn albedo_scene(triangles: Vec<Triangle>, materials: Vec<Material>, textures: Vec<Texture>) -> Scene {
    Scene { triangles, materials, textures, camera: front_camera(), ambient: Vec3::ONE, ..Scene::default() }
}

fn whitted_image(scene: &Scene, layout: LayoutKind, size: (u32, u32), all_features: bool) -> Image {
    whitted_image_lit(scene, None, layout, size, all_features)
}

fn path_image(scene: &Scene, size: (u32, u32), spp: u64, max_depth: Option<u32>, all_features: bool) -> Image {
    path_image_lit(scene, None, size, spp, max_depth, all_features)
}

fn whitted_image_lit(scene: &Scene, env: Option<&EnvLight>, layout: LayoutKind, size: (u32, u32), all_features: bool) -> Image {
    let ctx = common::gpu_context();
    let gpu = common::upload_lit(&ctx, scene, env, &PrepareOptions { builder: BuilderKind::Sah, layout, ..Default::default() });
    let settings = RenderSettings { width: size.0, height: size.1, spp: 1, max_depth: 3, all_features, ..RenderSettings::default() };
    let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(&ctx);
    image
}

fn path_image_lit(scene: &Scene, env: Option<&EnvLight>, size: (u32, u32), spp: u64, max_depth: Option<u32>, all_features: bool) -> Image {
    let settings = PathSettings {
        image: RenderSettings { width: size.0, height: size.1, all_features, ..RenderSettings::default() },
        max_depth,
        stop: Stop { spp: Some(spp), ..Stop::default() },
        ..PathSettings::default()
    };
    let ctx = common::gpu_context();
    let gpu = common::upload_lit(&ctx, scene, env, &PrepareOptions::default());
    common::render_path_on(&ctx, &gpu, &settings).image()
}

fn srgb(b: u8) -> f32 {
    (b as f32 / 255.0).powf(2.2)
}

/// The texture lookup the shaders are meant to do, written independently: repeat wrapping,
/// row 0 at v = 1, each texel decoded before bilinear blending.
fn expected_bilinear(t: &Texture, uv: Vec2) -> [f32; 3] {
    let (w, h) = (t.width as i64, t.height as i64);
    let sx = uv.x.rem_euclid(1.0) * w as f32 - 0.5;
    let sy = (1.0 - uv.y.rem_euclid(1.0)) * h as f32 - 0.5;
    let (x0, y0) = (sx.floor(), sy.floor());
    let (fx, fy) = (sx - x0, sy - y0);
    let texel = |x: i64, y: i64| {
        let b = t.texels[(y.rem_euclid(h) * w + x.rem_euclid(w)) as usize].to_le_bytes();
        [srgb(b[0]), srgb(b[1]), srgb(b[2])]
    };
    let (x0, y0) = (x0 as i64, y0 as i64);
    let mut out = [0.0; 3];
    for c in 0..3 {
        let top = texel(x0, y0)[c] * (1.0 - fx) + texel(x0 + 1, y0)[c] * fx;
        let bottom = texel(x0, y0 + 1)[c] * (1.0 - fx) + texel(x0 + 1, y0 + 1)[c] * fx;
        out[c] = top * (1.0 - fy) + bottom * fy;
    }
    out
}

fn assert_close(what: &str, got: [f32; 3], want: [f32; 3], tol: f32) {
    for c in 0..3 {
        assert!((got[c] - want[c]).abs() <= tol, "{what}: got {got:?}, want {want:?} (tolerance {tol})");
    }
}

/// A 4x2 texture of eight different colours.
fn colour_texture() -> Texture {
    let rgba: Vec<[u8; 4]> = (0..8u8).map(|i| [30 * i + 10, 255 - 25 * i, if i % 2 == 0 { 200 } else { 40 }, 255]).collect();
    Texture::from_rgba("colours", 4, 2, &rgba).unwrap()
}

fn textured_material() -> Material {
    Material { name: "textured".into(), diffuse: Vec3::ZERO, diffuse_texture: Some(0), ..Material::default() }
}

#[test]
fn texture_lookup_is_bilinear_srgb_with_repeat_and_v_up() {
    // uv runs over [-0.25, 1.75]^2: two periods, starting off the texture, so repeat wrapping,
    // negative coordinates and blending across the wrap all show up in a 16 x 16 image.
    let tex = colour_texture();
    let (uv0, scale) = (Vec2::splat(-0.25), Vec2::splat(2.0));
    let quad = uv_quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, uv0, scale, 0);
    let scene = albedo_scene(quad.to_vec(), vec![textured_material()], vec![tex.clone()]);
    let n = 16;
    for layout in LayoutKind::ALL {
        let image = whitted_image(&scene, layout, (n, n), false);
        for j in 0..n {
            for i in 0..n {
                let x = (i as f32 + 0.5) / n as f32 * 2.0 - 1.0;
                let y = 1.0 - (j as f32 + 0.5) / n as f32 * 2.0;
                let uv = uv0 + Vec2::new((x + 1.0) / 2.0, (y + 1.0) / 2.0) * scale;
                let want = expected_bilinear(&tex, uv);
                assert_close(&format!("{} pixel ({i}, {j}) at uv {uv}", layout.name()), image.get(i, j), want, 2e-3);
            }
        }
    }
}

#[test]
fn texel_row_zero_is_the_top_of_the_image() {
    // A 1x2 texture, red on top (row 0) and blue below, on a quad with v = 1 at the top: the
    // upper pixels are red. Pixel centres of a 4-pixel column hit v = 7/8 and 1/8, a quarter
    // texel from the texel centres, so they blend 3:1 towards their own row.
    let rgba = [[255, 0, 0, 255], [0, 0, 255, 255]];
    let tex = Texture::from_rgba("red over blue", 1, 2, &rgba).unwrap();
    let quad = uv_quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, Vec2::ZERO, Vec2::ONE, 0);
    let scene = albedo_scene(quad.to_vec(), vec![textured_material()], vec![tex]);
    let image = whitted_image(&scene, LayoutKind::Threaded, (4, 4), false);
    let top = image.get(1, 0);
    let bottom = image.get(1, 3);
    assert!(top[0] > 0.5 && top[2] < 0.5, "top pixel should be mostly red: {top:?}");
    assert!(bottom[2] > 0.5 && bottom[0] < 0.5, "bottom pixel should be mostly blue: {bottom:?}");
}

/// An 8x8 alpha mask in four 4x4 blocks: opaque top-left and bottom-right, see-through (alpha 0.1,
/// just under the cut-off) elsewhere; colour red.
fn checker_alpha() -> Texture {
    let mut rgba = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let opaque = (x < 4) == (y < 4);
            rgba.push([255, 0, 0, if opaque { 255 } else { 25 }]);
        }
    }
    Texture::from_rgba("checker", 8, 8, &rgba).unwrap()
}

fn cutout_material() -> Material {
    Material { name: "leaf".into(), diffuse: Vec3::ZERO, diffuse_texture: Some(0), alpha_texture: Some(0), ..Material::default() }
}

#[test]
fn see_through_texels_show_what_is_behind_in_every_layout() {
    let green = Material { name: "green".into(), diffuse: Vec3::new(0.0, 1.0, 0.0), ..Material::default() };
    let mut tris = uv_quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, Vec2::ZERO, Vec2::ONE, 0).to_vec();
    tris.extend(uv_quad(Vec3::new(-4.0, -4.0, -1.0), Vec3::X * 8.0, Vec3::Y * 8.0, Vec2::ZERO, Vec2::ONE, 1));
    let scene = albedo_scene(tris, vec![cutout_material(), green], vec![checker_alpha()]);
    assert!(vkrt::prepare::features::Features::of(&scene).has(vkrt::prepare::features::ALPHA));
    for layout in LayoutKind::ALL {
        let image = whitted_image(&scene, layout, (W, W), false);
        for j in 0..W {
            for i in 0..W {
                // Pixel (i, j) hits texel (i, j) at its centre: no blending.
                let opaque = (i < 4) == (j < 4);
                let want = if opaque { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
                assert_close(&format!("{} pixel ({i}, {j})", layout.name()), image.get(i, j), want, 1e-4);
            }
        }
    }
}

/// The same cut-out quad as an instance of a mesh (after the backdrop, so its primitive ids are
/// not its mesh's own), walked through the two-level BVH: its texels are the copy's, and a
/// mirrored copy shows them mirrored.
#[test]
fn see_through_texels_of_instances_are_the_copy_s() {
    use vkrt::scene::instance::{add_group, Placement};
    let green = Material { name: "green".into(), diffuse: Vec3::new(0.0, 1.0, 0.0), ..Material::default() };
    let backdrop = uv_quad(Vec3::new(-4.0, -4.0, -1.0), Vec3::X * 8.0, Vec3::Y * 8.0, Vec2::ZERO, Vec2::ONE, 1).to_vec();
    let quad = uv_quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, Vec2::ZERO, Vec2::ONE, 0);
    for mirror in [false, true] {
        let mut scene = albedo_scene(backdrop.clone(), vec![cutout_material(), green.clone()], vec![checker_alpha()]);
        let scale = Vec3::new(if mirror { -1.0 } else { 1.0 }, 1.0, 1.0);
        add_group(&mut scene, &quad, vec![Placement::from_trs(Vec3::ZERO, Vec3::ZERO, scale).unwrap()]);
        assert_eq!(scene.instances.len(), 1);
        let image = whitted_image(&scene, LayoutKind::Threaded, (W, W), false);
        for j in 0..W {
            for i in 0..W {
                let texel_x = if mirror { W - 1 - i } else { i };
                let opaque = (texel_x < 4) == (j < 4);
                let want = if opaque { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
                assert_close(&format!("mirror {mirror} pixel ({i}, {j})"), image.get(i, j), want, 1e-4);
            }
        }
    }
}

/// A white floor at z = 0 lit by a directional light from (1, 0, 0.5); a cut-out caster at
/// z = 0.5, out of the camera's view (x in [1, 3]), whose top half is opaque. Its shadow falls on
/// x in [0, 1], top half only: light passes through the see-through half.
fn shadow_scene() -> Scene {
    let white = Material { name: "white".into(), diffuse: Vec3::splat(0.8), ..Material::default() };
    let mut rgba = Vec::new();
    for y in 0..8 {
        for _ in 0..8 {
            rgba.push([255, 255, 255, if y < 4 { 255 } else { 0 }]);
        }
    }
    let mask = Texture::from_rgba("top half", 8, 8, &rgba).unwrap();
    let mut tris = uv_quad(Vec3::new(1.0, -1.0, 0.5), Vec3::X * 2.0, Vec3::Y * 2.0, Vec2::ZERO, Vec2::ONE, 0).to_vec();
    tris.extend(uv_quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0, Vec2::ZERO, Vec2::ONE, 1));
    let caster = Material { diffuse_texture: None, diffuse: Vec3::splat(0.5), ..cutout_material() };
    let mut scene = albedo_scene(tris, vec![caster, white], vec![mask]);
    scene.ambient = Vec3::ZERO;
    scene.lights = vec![Light::Directional { direction: Vec3::new(1.0, 0.0, 0.5), intensity: Vec3::ONE }];
    scene
}

#[test]
fn shadows_pass_through_cut_outs_in_whitted_and_path() {
    let scene = shadow_scene();
    let cos = 0.5 / Vec3::new(1.0, 0.0, 0.5).length();
    for layout in LayoutKind::ALL {
        let image = whitted_image(&scene, layout, (W, W), false);
        let lit = 0.8 * cos;
        assert_close(&format!("{} left, lit", layout.name()), image.get(1, 1), [lit; 3], 1e-4);
        assert_close(&format!("{} right top, shadowed", layout.name()), image.get(6, 1), [0.0; 3], 1e-6);
        assert_close(&format!("{} right bottom, lit through the cut-out", layout.name()), image.get(6, 6), [lit; 3], 1e-4);
    }
    // The path tracer's shadow rays (next-event estimation of the directional light) too:
    // Lambert 0.8 / pi times the irradiance cos.
    let image = path_image(&scene, (W, W), 4, Some(2), false);
    let lit = 0.8 / std::f32::consts::PI * cos;
    assert_close("path left, lit", image.get(1, 1), [lit; 3], 1e-4);
    assert_close("path right top, shadowed", image.get(6, 1), [0.0; 3], 1e-6);
    assert_close("path right bottom, lit through the cut-out", image.get(6, 6), [lit; 3], 1e-4);
}

/// Six 8x8 faces, each its own colour, the +x face with its top two rows white.
fn cube_faces() -> Vec<Texture> {
    let colours = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 0], [0, 255, 255], [255, 0, 255]];
    colours
        .iter()
        .enumerate()
        .map(|(f, c)| {
            let texel = [c[0], c[1], c[2], 255];
            let top = if f == 0 { [255, 255, 255, 255] } else { texel };
            let rgba: Vec<[u8; 4]> = (0..64).map(|i| if i < 16 { top } else { texel }).collect();
            Texture::from_rgba(format!("face {f}"), 8, 8, &rgba).unwrap()
        })
        .collect()
}

/// A tiny triangle behind the camera keeps the scene non-empty; every pixel sees the sky.
fn sky_scene(dir: Vec3, up: Vec3) -> Scene {
    let speck =
        Triangle { p: [Vec3::new(0.0, 0.0, 0.0) - dir * 50.0, -dir * 50.0 + up * 0.01, -dir * 50.0 + up.cross(dir) * 0.01], n: None, uv: None, material: 0 };
    Scene {
        triangles: vec![speck],
        materials: vec![Material::default()],
        textures: cube_faces(),
        sky: Sky::CubeMap { first_texture: 0, scale: Vec3::ONE },
        camera: Camera { eye: Vec3::ZERO, target: dir, up, fov_y_deg: 90.0, ..Camera::default() },
        ..Scene::default()
    }
}

#[test]
fn escaping_rays_see_the_cube_face_in_their_direction() {
    let decoded = |c: [u8; 3]| [srgb(c[0]), srgb(c[1]), srgb(c[2])];
    let faces = [
        (Vec3::X, Vec3::Y, [255, 0, 0]),
        (-Vec3::X, Vec3::Y, [0, 255, 0]),
        (Vec3::Y, Vec3::Z, [0, 0, 255]),
        (-Vec3::Y, Vec3::Z, [255, 255, 0]),
        (Vec3::Z, Vec3::Y, [0, 255, 255]),
        (-Vec3::Z, Vec3::Y, [255, 0, 255]),
    ];
    for (dir, up, colour) in faces {
        let scene = sky_scene(dir, up);
        let image = whitted_image(&scene, LayoutKind::Threaded, (9, 9), false);
        // Pixel row 7 of 9 looks at face row 6.17 of 8 (90-degree view): clear of the white rows.
        assert_close(&format!("looking along {dir}"), image.get(4, 7), decoded(colour), 1e-4);
        let path = path_image(&scene, (9, 9), 1, None, false);
        assert_close(&format!("path tracer looking along {dir}"), path.get(4, 7), decoded(colour), 1e-4);
    }
    // The +x face seen upright: its top rows (white) are at the top of the view (pixel row 1
    // looks at face row 0.83).
    let image = whitted_image(&sky_scene(Vec3::X, Vec3::Y), LayoutKind::Threaded, (9, 9), false);
    assert_close("top of the +x face", image.get(4, 1), [1.0; 3], 1e-4);
}

#[test]
fn a_diffuse_plane_under_a_constant_sky_reflects_albedo_times_sky() {
    // Every ray leaving the plane's upper side escapes to the sky of radiance L, so the plane's
    // radiance is a * L exactly (Lambert sampled by cosine: every path carries exactly a).
    let l = Vec3::new(0.5, 1.0, 2.0);
    let a = 0.6;
    let plane = uv_quad(Vec3::new(-5.0, -5.0, 0.0), Vec3::X * 10.0, Vec3::Y * 10.0, Vec2::ZERO, Vec2::ONE, 0);
    let scene = Scene {
        triangles: plane.to_vec(),
        materials: vec![Material { name: "grey".into(), diffuse: Vec3::splat(a), ..Material::default() }],
        sky: Sky::Constant(l),
        camera: front_camera(),
        ..Scene::default()
    };
    let image = path_image(&scene, (W, W), 16, None, false);
    for p in &image.pixels {
        assert_close("plane under the sky", *p, (l * a).to_array(), 1e-4);
    }
}

fn max_abs_diff(a: &Image, b: &Image) -> f32 {
    a.pixels.iter().zip(&b.pixels).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs())).fold(0.0, f32::max)
}

/// A scene of the repository's `scenes/`.
fn load(rel: &str) -> Scene {
    vkrt::scene::load_scene(&common::repo_path(rel)).unwrap()
}

/// Whitted and path-traced images of `scene` from the specialised and the all-features shader
/// agree within 1e-5 absolute (the same arithmetic, only dead branches removed).
fn assert_specialised_matches_all_features(name: &str, scene: &Scene, env: Option<&EnvLight>) {
    let w_spec = whitted_image_lit(scene, env, LayoutKind::Threaded, (32, 32), false);
    let w_all = whitted_image_lit(scene, env, LayoutKind::Threaded, (32, 32), true);
    let d = max_abs_diff(&w_spec, &w_all);
    assert!(d <= 1e-5, "{name}: Whitted specialised vs all-features differ by {d}");
    let p_spec = path_image_lit(scene, env, (32, 32), 2, Some(5), false);
    let p_all = path_image_lit(scene, env, (32, 32), 2, Some(5), true);
    let d = max_abs_diff(&p_spec, &p_all);
    assert!(d <= 1e-5, "{name}: path specialised vs all-features differ by {d}");
}

/// The shader specialised to a scene and the all-features shader give the same image on
/// scenes that together use every feature.
#[test]
fn specialised_and_all_features_shaders_agree() {
    // The shadow scene with its caster's mask as a diffuse texture too.
    let mut textured = shadow_scene();
    textured.materials[0].diffuse_texture = Some(0);
    let mut scenes: Vec<(&str, Scene)> = vec![
        ("cut-outs", shadow_scene()),
        ("cut-outs + diffuse texture", textured),
        ("sky box", sky_scene(Vec3::X, Vec3::Y)),
        ("lab Box_ver_path: emitters", load("scenes/lab/Box_ver_path/Box_ver_path.yaml")),
        ("lab cornell_box: point light", load("scenes/lab/cornell_box/cornell_box.yaml")),
    ];
    // Mirror, glass, a glossy lobe and a spot light.
    let mut special = load("scenes/lab/cornell_box/cornell_box.yaml");
    let n = special.materials.len();
    special.materials.push(Material { name: "mirror".into(), specular: Vec3::splat(0.9), illum: 3, ..Material::default() });
    special.materials.push(Material { name: "glass".into(), illum: 7, ..Material::default() });
    special.materials.push(Material { name: "glossy".into(), specular: Vec3::splat(0.3), shininess: 40.0, ..Material::default() });
    for (k, t) in special.triangles.iter_mut().enumerate() {
        if k % 5 == 0 {
            t.material = n as u32 + (k % 3) as u32;
        }
    }
    let b = special.bounds();
    special.lights.push(Light::Spot { position: b.center(), direction: -Vec3::Y, intensity: Vec3::ONE, radius: 0.1 * b.extent().length() });
    special.lights.push(Light::Cone { position: b.center(), direction: -Vec3::Y, intensity: Vec3::ONE, cos_inner: 0.9, cos_outer: 0.7 });
    scenes.push(("mirror, glass, glossy, spot and cone lights", special));
    // Emitters, a glossy lobe and a mirror alone: the lean build with the mirror code
    // (Box_ver_path itself runs the lean build without it).
    let lean_mirror = common::with_mirrors(load("scenes/lab/Box_ver_path/Box_ver_path.yaml"), 4, 1);
    scenes.push(("lab Box_ver_path with a mirror: lean", lean_mirror));
    // glTF materials: metallic-roughness (textured, and a smooth metal that Whitted mirrors),
    // an emission texture and a normal map with MikkTSpace tangents, on the textured shadow scene.
    let mut gltf = shadow_scene();
    let t = gltf.textures.len() as u32;
    gltf.textures.push(
        vkrt::scene::Texture::from_rgba("normal", 2, 2, &[[170, 100, 230, 255], [90, 140, 240, 255], [128, 128, 255, 255], [200, 60, 200, 255]]).unwrap(),
    );
    gltf.textures.push(vkrt::scene::Texture::from_rgba("mr", 2, 2, &[[0, 200, 255, 255], [0, 40, 0, 255], [0, 120, 128, 255], [0, 255, 60, 255]]).unwrap());
    let mr = |metallic, roughness, texture| Some(vkrt::scene::MetallicRoughness { metallic, roughness, texture });
    let n = gltf.materials.len() as u32;
    gltf.materials.push(Material {
        name: "gltf rough".into(),
        diffuse: Vec3::new(0.9, 0.6, 0.3),
        metallic_roughness: mr(0.7, 0.8, Some(t + 1)),
        normal_texture: Some(t),
        normal_scale: 0.7,
        ..Material::default()
    });
    gltf.materials.push(Material {
        name: "gltf metal".into(),
        diffuse: Vec3::splat(0.9),
        metallic_roughness: mr(1.0, 0.05, None),
        diffuse_texture: Some(0),
        emission: Vec3::splat(0.5),
        emission_texture: Some(t + 1),
        ..Material::default()
    });
    for (k, tri) in gltf.triangles.iter_mut().enumerate() {
        if k % 3 != 0 {
            tri.material = n + (k % 2) as u32;
        }
    }
    vkrt::scene::tangents::fill_missing_tangents(&mut gltf);
    scenes.push(("glTF metallic-roughness, normal map, emission texture", gltf));
    for (name, scene) in &scenes {
        assert_specialised_matches_all_features(name, scene, None);
    }
    // The envmap test's sky-and-sun map over the textured shadow scene: a map is bound at
    // upload, so it is not one of the `scenes` above (whose all-features renders must not see
    // one: a 0 x 0 map once made the all-features shader search its CDF forever).
    let mut lit = shadow_scene();
    lit.sky = Sky::Environment { scale: 0.5, rotation_deg: 30.0 };
    let map = vkrt::scene::envmap::EnvMap::load(&common::repo_path("tests/refs/envmap-sun.exr")).unwrap();
    let env = EnvLight::new(&map, 0.5, 30.0);
    assert_specialised_matches_all_features("environment map", &lit, Some(&env));
    scenes.push(("environment map", lit));
    // Every feature is on in at least one scene, so each one's removal is covered; the lean
    // builds (every feature but mirrors, glossy lobes and emitters compiled out) are compared
    // with and without their mirror code.
    use vkrt::prepare::features::{Features, MIRROR};
    for f in vkrt::prepare::features::ALL {
        assert!(scenes.iter().any(|(_, s)| Features::of(s).has(f)), "no scene uses {}", f.name);
    }
    for mirrors in [false, true] {
        assert!(scenes.iter().any(|(_, s)| Features::of(s).lean() && Features::of(s).has(MIRROR) == mirrors), "no lean scene with mirrors {mirrors}");
    }
}

/// The same on the course's floor scene (a texture, a glossy lobe, a point light). Needs
/// `../shared`: skipped, saying so, where it is absent.
#[test]
fn shared_lab_floor_specialised_and_all_features_agree() {
    let test = "shared_lab_floor_specialised_and_all_features_agree";
    let Some(path) = common::shared_or_skip(test, "scenes/lab/floor/floor.yaml") else { return };
    let floor = vkrt::scene::load_scene(&path).unwrap();
    assert_specialised_matches_all_features("lab floor", &floor, None);
}

#[test]
fn a_diffuse_only_scene_turns_every_optional_feature_off() {
    let scene = load("scenes/lab/cornell_box/cornell_box.yaml");
    let f = vkrt::prepare::features::Features::of(&scene);
    use vkrt::prepare::features::*;
    for off in [TEXTURES, ALPHA, DIELECTRIC, MIRROR, EMITTERS, SKY, SPOT, DIRECTIONAL] {
        assert!(!f.has(off), "{} should be off:\n{}", off.name, f.report());
    }
    assert!(f.has(POINT));
    // A point light is beyond the lean build; the course's emitter-lit box is within it.
    assert!(!f.lean());
    assert!(Features::of(&load("scenes/lab/Box_ver_path/Box_ver_path.yaml")).lean());
    assert!(!Features::all().lean());
}

/// Writes a one-quad OBJ whose material names `texture` as its map_Kd; returns the OBJ's path.
fn obj_with_texture(dir: &str, texture: &str) -> std::path::PathBuf {
    let dir = common::scratch_dir(dir);
    std::fs::write(dir.join("scene.mtl"), format!("newmtl bark\nKd 1 1 1\nmap_Kd {texture}\n")).unwrap();
    let obj = "mtllib scene.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl bark\nf 1/1 2/2 3/3\n";
    std::fs::write(dir.join("scene.obj"), obj).unwrap();
    dir.join("scene.obj")
}

#[test]
fn a_missing_or_corrupt_texture_is_one_clear_error_naming_file_and_material() {
    let path = obj_with_texture("texture-missing", "nowhere.png");
    let err = format!("{:#}", vkrt::scene::load_scene(&path).unwrap_err());
    assert!(err.contains("nowhere.png") && err.contains("'bark'"), "message: {err}");

    let path = obj_with_texture("texture-corrupt", "broken.png");
    std::fs::write(path.with_file_name("broken.png"), b"\x89PNG\r\n\x1a\n not really a png").unwrap();
    let err = format!("{:#}", vkrt::scene::load_scene(&path).unwrap_err());
    assert!(err.contains("broken.png") && err.contains("'bark'"), "message: {err}");
}

#[test]
fn a_png_texture_loads_through_the_obj_loader_with_its_alpha_as_a_cut_out() {
    let path = obj_with_texture("texture-png", "leaf.png");
    let mut img = image::RgbaImage::new(2, 1);
    img.put_pixel(0, 0, image::Rgba([10, 20, 30, 255]));
    img.put_pixel(1, 0, image::Rgba([40, 50, 60, 0]));
    img.save(path.with_file_name("leaf.png")).unwrap();
    let scene = vkrt::scene::load_scene(&path).unwrap();
    let m = &scene.materials[scene.triangles[0].material as usize];
    let t = &scene.textures[m.diffuse_texture.unwrap() as usize];
    assert_eq!((t.width, t.height), (2, 1));
    assert_eq!(t.texels[0].to_le_bytes(), [10, 20, 30, 255]);
    assert_eq!(m.alpha_texture, m.diffuse_texture, "the diffuse texture's alpha cuts out");
    assert_eq!(scene.triangles[0].uv.unwrap()[1], Vec2::new(1.0, 0.0));
}

/// The lab scenes' textured cases, small: White Oak's leaves are cut out (more background shows
/// through the crown than with the leaf quads opaque), and the lab floor shows its wood texture.
#[test]
fn shared_lab_white_oak_leaves_are_cut_out_and_the_floor_is_textured() {
    let test = "shared_lab_white_oak_leaves_are_cut_out_and_the_floor_is_textured";
    let Some(path) = common::shared_or_skip(test, "scenes/lab/white_oak/white_oak.yaml") else { return };
    let oak = vkrt::scene::load_scene(&path).unwrap();
    let mut opaque = oak.clone();
    for m in &mut opaque.materials {
        m.alpha_texture = None;
    }
    let background = |img: &Image| img.pixels.iter().filter(|p| p.iter().all(|&c| c == 0.0)).count();
    let cut = whitted_image(&oak, LayoutKind::Threaded, (64, 48), false);
    let solid = whitted_image(&opaque, LayoutKind::Threaded, (64, 48), false);
    let (b_cut, b_solid) = (background(&cut), background(&solid));
    assert!(b_cut > b_solid + 64, "background pixels: {b_cut} with cut-outs, {b_solid} without");

    let floor = vkrt::scene::load_scene(&common::shared_path("scenes/lab/floor/floor.yaml")).unwrap();
    let img = whitted_image(&floor, LayoutKind::Threaded, (32, 24), false);
    // Wood: red above green above blue, and the planks vary from pixel to pixel.
    let lit: Vec<&[f32; 3]> = img.pixels.iter().filter(|p| p[0] > 0.0).collect();
    assert!(lit.len() > 100);
    assert!(lit.iter().all(|p| p[0] >= p[1] && p[1] >= p[2]), "not wood-coloured");
    let distinct: std::collections::HashSet<u32> = lit.iter().map(|p| (p[0] / p[1].max(1e-6) * 100.0) as u32).collect();
    assert!(distinct.len() > 5, "the floor looks untextured");
}
