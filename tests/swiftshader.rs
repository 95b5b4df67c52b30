//! vkrt on a second, independent Vulkan implementation (issue 43): SwiftShader (Google's CPU
//! Vulkan 1.3, its own Subzero compiler, 4-wide subgroups, 256 invocations per workgroup, 2^16
//! texel-buffer elements), installed without Chromium by `tools/ensure-deps.sh
//! --with-swiftshader` and made visible beside lavapipe by `VK_ADD_DRIVER_FILES` (tools/test's
//! SwiftShader leg). Where no SwiftShader device is installed these tests say so and check
//! nothing, unless `VKRT_REQUIRE_SWIFTSHADER=1` (the leg), which makes that a failure.
//!
//! What must hold there, and why the tolerances are what they are:
//! - the agreement chain, for every layout: t bit for bit and the traversal counters equal the
//!   CPU twin's (the traversal uses only operations Vulkan rounds exactly, and the division is
//!   corrected where a device's is not IEEE: `division.glsl`);
//! - Whitted renders of every scene kind (lab YAML, an OBJ with a texture and cut-outs, the
//!   glTF showcase, an environment map) equal lavapipe's within a stated bound per channel:
//!   shading uses `pow`, `sqrt`, `normalize`, `exp2` and the sRGB decode, which Vulkan lets an
//!   implementation compute a few ulps off (2e-5 relative), and the map's lookup `atan` and
//!   `acos`, which it lets be far more (1e-3 relative, measured 4.6e-4);
//! - path-traced renders estimate the same image as lavapipe's and as the independent Mitsuba
//!   reference: equal means (within 1 %) and a difference no larger than the runs' noise. Not the same bytes: a transcendental function a few
//!   ulps off can send one sample down another branch (a lobe, the roulette), after which its
//!   path differs altogether (on cornell-measured 32², 4 spp: 93 % of the values differ, the
//!   channel means by 0.005-0.012 %);
//! - the same bytes twice on SwiftShader itself (determinism), and the device's limits read,
//!   not assumed: a scene over its texel-buffer limit is refused with the limit named.

mod common;

use vkrt::accel::LayoutKind;
use vkrt::gpu::{Context, ContextOptions, Validation};
use vkrt::gpu_abi::GpuRay;
use vkrt::integrator::{whitted, Image, RenderSettings};
use vkrt::output::compare::compare;
use vkrt::prepare::{GpuBvh, PrepareOptions, PreparedScene};
use vkrt::query::{rays, trace_rays};

/// A context on the device whose name contains `name`, with validation where installed.
fn context(name: &str) -> Option<Context> {
    let options = ContextOptions { device: Some(name.into()), validation: Some(Validation::IfAvailable), ..ContextOptions::default() };
    Context::new(&options).ok()
}

/// SwiftShader's context, or None (with a line saying why) where it is not installed.
fn swiftshader(test: &str) -> Option<Context> {
    let ctx = context("swiftshader");
    if ctx.is_none() {
        assert!(
            std::env::var("VKRT_REQUIRE_SWIFTSHADER").as_deref() != Ok("1"),
            "{test}: no SwiftShader device (tools/ensure-deps.sh --with-swiftshader, and VK_ADD_DRIVER_FILES)"
        );
        eprintln!("{test}: no SwiftShader device installed; nothing checked");
    }
    ctx
}

fn whitted_image(ctx: &Context, scene: &vkrt::scene::Scene, size: u32) -> Image {
    whitted_image_lit(ctx, scene, None, size)
}

/// The same, lit by `env` as its environment map when given.
fn whitted_image_lit(ctx: &Context, scene: &vkrt::scene::Scene, env: Option<&vkrt::prepare::EnvLight>, size: u32) -> Image {
    let gpu = common::upload_lit(ctx, scene, env, &PrepareOptions::default());
    let settings = RenderSettings { width: size, height: size, spp: 1, ..RenderSettings::default() };
    let (image, stats) = whitted::render(ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(ctx);
    image
}

#[test]
fn swiftshader_reports_its_own_limits() {
    let Some(ctx) = swiftshader("swiftshader_reports_its_own_limits") else { return };
    assert!(ctx.info.name.contains("SwiftShader"), "{}", ctx.info.name);
    assert!(ctx.info.max_workgroup_invocations >= 64, "vkrt's 8x8 and 64-wide workgroups must fit");
    assert_eq!(ctx.info.max_texel_buffer_elements, 1 << 16, "the limit the next check is sized for");
    // 100k triangles: a BVH of ~200k nodes, 6 MiB, over its 2^16-texel (1 MiB) views: refused
    // with the limit named, at upload, not a crash or a validation message.
    let big = common::procedural::random_soup(100_000, 3);
    let prepared = PreparedScene::new(&big, &PrepareOptions::default()).unwrap();
    let e = format!("{:#}", GpuBvh::upload(&ctx, &prepared.flat).err().expect("a BVH over the texel-buffer limit was uploaded"));
    assert!(e.contains("texel-buffer limit") && e.contains("65536 texels"), "{e}");
}

/// The agreement chain on SwiftShader: every layout's GPU walk gives the CPU twin's t (bit for
/// bit), triangle and counters, for closest-hit and any-hit queries.
#[test]
fn the_agreement_chain_holds_for_every_layout() {
    let Some(ctx) = swiftshader("the_agreement_chain_holds_for_every_layout") else { return };
    let scene = common::cornell_measured();
    let mut set: Vec<GpuRay> = rays::primary(&scene, 48, 48).unwrap();
    set.extend(rays::incoherent(&scene, 2048, 7));
    for layout in LayoutKind::ALL {
        let prepared = PreparedScene::new(&scene, &PrepareOptions { layout, ..PrepareOptions::default() }).unwrap();
        let gpu = GpuBvh::upload(&ctx, &prepared.flat).unwrap();
        for any_hit in [false, true] {
            let hits = trace_rays(&ctx, &gpu, &set, any_hit).unwrap();
            let mut hit = 0;
            for (r, got) in set.iter().zip(&hits) {
                let twin = prepared.flat.trace(r, any_hit);
                let what = format!("{} any_hit={any_hit} ray {r:?}", layout.name());
                assert_eq!(got.prim, twin.prim, "{what}: triangle");
                if !any_hit {
                    assert_eq!(got.t.to_bits(), twin.t.to_bits(), "{what}: t {} vs {}", got.t, twin.t);
                }
                assert_eq!((got.nodes_visited, got.tris_tested), (twin.nodes_visited, twin.tris_tested), "{what}: counters");
                hit += (got.prim != vkrt::gpu_abi::constants::PRIM_NONE) as usize;
            }
            assert!(hit > set.len() / 2, "{}: only {hit} hits", layout.name());
        }
    }
    common::assert_no_validation_messages(&ctx);
}

/// Whitted on SwiftShader renders lavapipe's image of the lab's Cornell box (a YAML scene)
/// within 2e-5 relative (transcendental functions), and the same bytes twice.
#[test]
fn whitted_matches_lavapipe_and_repeats_itself() {
    let Some(ss) = swiftshader("whitted_matches_lavapipe_and_repeats_itself") else { return };
    let lavapipe = context("llvmpipe").expect("lavapipe beside SwiftShader");
    let scene = vkrt::scene::load_scene(&common::repo_path("scenes/lab/cornell_box/cornell_box.yaml")).unwrap();
    let a = whitted_image(&ss, &scene, 48);
    let b = whitted_image(&lavapipe, &scene, 48);
    let worst = worst_relative(&a, &b);
    assert!(worst <= 2e-5, "SwiftShader's Whitted image differs from lavapipe's by {worst} (relative)");
    assert_eq!(a.pixels, whitted_image(&ss, &scene, 48).pixels, "two SwiftShader renders differ");
}

/// The path tracer on SwiftShader estimates lavapipe's image and the independent reference
/// (tests/refs/cornell-256.exr, Mitsuba 3, box-filtered down to the render's 64²): channel means
/// within 1 % of both, and relMSE within `reference_relmse_bound` of the reference (the
/// reference test's own bound) and within twice that of lavapipe's image (two runs' noise).
#[test]
fn the_path_tracer_estimates_lavapipe_s_image_and_the_reference() {
    let Some(ss) = swiftshader("the_path_tracer_estimates_lavapipe_s_image_and_the_reference") else { return };
    let lavapipe = context("llvmpipe").expect("lavapipe beside SwiftShader");
    let scene = common::cornell_measured();
    const SPP: u64 = 16;
    const SIZE: u32 = 64;
    let settings = common::path_settings(SIZE, SIZE, SPP);
    let render = |ctx: &Context| common::render_path_on(ctx, &common::upload(ctx, &scene), &settings).image();
    let (a, b) = (render(&ss), render(&lavapipe));
    let full = common::cornell_reference();
    let reference = full.box_downsample(full.width / SIZE);
    for (against, other, bound) in
        [("lavapipe", &b, 2.0 * common::reference_relmse_bound(SPP)), ("the reference", &reference, common::reference_relmse_bound(SPP))]
    {
        let c = compare(&a, other).unwrap();
        let means = other.mean();
        for k in 0..3 {
            assert!(c.mean_diff[k].abs() <= 0.01 * means[k], "against {against}, channel {k}: mean {} vs {}", a.mean()[k], means[k]);
        }
        eprintln!("SwiftShader's path tracer against {against}: relMSE {:.3e} (bound {bound:.3e})", c.relmse);
        assert!(c.relmse <= bound, "against {against}: relMSE {:.3e} > {bound:.3e}", c.relmse);
    }
}

/// The largest per-channel difference between two images, relative to max(1, |reference|).
fn worst_relative(a: &Image, b: &Image) -> f32 {
    let mut worst = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            worst = worst.max((p[c] - q[c]).abs() / q[c].abs().max(1.0));
        }
    }
    worst
}

/// An OBJ whose front quad has an sRGB texture (map_Kd) and cut-outs (map_d: a checker of
/// opaque and see-through texels), in front of a plain back quad, lit by a point light.
fn textured_cutout_scene(dir: &std::path::Path) -> vkrt::scene::Scene {
    let texels: Vec<[u8; 4]> = (0..64).map(|i| if (i % 8 + i / 8) % 2 == 0 { [220, 120, 40, 255] } else { [40, 90, 200, 0] }).collect();
    std::fs::write(dir.join("checker.png"), common::gltf_writer::png(8, 8, &texels)).unwrap();
    std::fs::write(dir.join("cutout.mtl"), "newmtl front\nKd 1 1 1\nmap_Kd checker.png\nmap_d checker.png\nnewmtl back\nKd 0.6 0.6 0.6\n").unwrap();
    let obj = "mtllib cutout.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -2 -2 -1\nv 2 -2 -1\nv 2 2 -1\nv -2 2 -1\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl front\nf 1/1 2/2 3/3 4/4\nusemtl back\nf 5 6 7 8\n";
    std::fs::write(dir.join("cutout.obj"), obj).unwrap();
    let mut scene = vkrt::scene::load_scene(&dir.join("cutout.obj")).unwrap();
    scene.camera.eye = glam::Vec3::new(0.3, 0.2, 4.0);
    scene.camera.target = glam::Vec3::ZERO;
    scene
}

/// A glTF file of the loader's kinds that fits SwiftShader's 2^16-texel views (the README's
/// showcase does not: its textures alone are 2^17 texels, which the limit test covers): a
/// base-colour-textured, metallic-roughness floor under a point light (KHR_lights_punctual) and a
/// perspective camera.
fn small_gltf_scene(dir: &std::path::Path) -> vkrt::scene::Scene {
    use common::gltf_writer::{mesh_node, png, Doc, Storage};
    use gltf_json as json;
    let mut doc = Doc::new();
    let texels: Vec<[u8; 4]> = (0..16).map(|i| if i % 3 == 0 { [250, 200, 60, 255] } else { [60, 160, 90, 255] }).collect();
    let tex = doc.png_texture(&png(4, 4, &texels));
    let material = doc.material(json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_texture: Some(json::texture::Info { index: tex, tex_coord: 0, extensions: None, extras: Default::default() }),
            metallic_factor: json::material::StrengthFactor(0.2),
            roughness_factor: json::material::StrengthFactor(0.6),
            ..Default::default()
        },
        ..Default::default()
    });
    use json::mesh::Semantic;
    let p = doc.vec3(&[[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]]);
    let n = doc.vec3(&[[0.0, 1.0, 0.0]; 4]);
    let uv = doc.vec2(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    let i = doc.indices(&[0, 2, 1, 0, 3, 2]);
    let prim =
        doc.primitive(&[(Semantic::Positions, p), (Semantic::Normals, n), (Semantic::TexCoords(0), uv)], Some(i), Some(material), json::mesh::Mode::Triangles);
    let mesh = doc.mesh(vec![prim]);
    let floor = doc.node(mesh_node(mesh));
    let light = doc.light(json::extensions::scene::khr_lights_punctual::Light {
        color: [1.0, 1.0, 1.0],
        extensions: None,
        extras: Default::default(),
        intensity: 20.0,
        name: None,
        range: None,
        spot: None,
        type_: json::validation::Checked::Valid(json::extensions::scene::khr_lights_punctual::Type::Point),
    });
    let lamp = doc.node(json::Node { translation: Some([0.3, 1.5, 0.2]), extensions: light, ..Default::default() });
    doc.scene(vec![floor, lamp]);
    let path = dir.join("small.gltf");
    doc.write_gltf(&path, Storage::DataUri);
    let mut scene = vkrt::scene::load_scene(&path).unwrap();
    scene.camera.eye = glam::Vec3::new(0.0, 2.0, 2.5);
    scene.camera.target = glam::Vec3::ZERO;
    scene
}

/// One Whitted render of each kind of scene on SwiftShader equals lavapipe's within 2e-5
/// relative per channel (transcendental functions and the sRGB decode, a few ulps apart), the
/// environment map's within 1e-3 (its lookup's inverse trigonometry, below).
#[test]
fn every_scene_kind_renders_as_on_lavapipe() {
    let Some(ss) = swiftshader("every_scene_kind_renders_as_on_lavapipe") else { return };
    let lavapipe = context("llvmpipe").expect("lavapipe beside SwiftShader");
    let dir = common::scratch_dir("swiftshader-scenes");
    let envmap = vkrt::scene::envmap::EnvMap::load(&common::repo_path("tests/refs/envmap-sun.exr")).unwrap();
    let env = vkrt::prepare::EnvLight::new(&envmap, 1.0, 0.0);
    let mut lit = vkrt::scene::load_scene(&common::repo_path("scenes/envmap/envmap-scene.obj")).unwrap();
    lit.sky = vkrt::scene::Sky::Environment { scale: 1.0, rotation_deg: 0.0 };
    let scenes = [
        ("an OBJ with a texture and cut-outs", textured_cutout_scene(&dir), None, 2e-5),
        ("a glTF file", small_gltf_scene(&dir), None, 2e-5),
        // The map is looked up through atan and acos (environment.glsl's env_grid), which Vulkan
        // lets be thousands of ulps off: a lookup direction off by that moves the bilinear
        // weights, and next to the sun's steep edge a pixel by a few 1e-4 (4.6e-4 measured).
        ("an environment map", lit, Some(&env), 1e-3),
    ];
    for (what, scene, env, bound) in &scenes {
        let a = whitted_image_lit(&ss, scene, *env, 32);
        let b = whitted_image_lit(&lavapipe, scene, *env, 32);
        let worst = worst_relative(&a, &b);
        eprintln!("{what}: SwiftShader vs lavapipe, worst {worst:e} relative");
        assert!(worst <= *bound, "{what}: SwiftShader's Whitted image differs from lavapipe's by {worst} (relative, bound {bound})");
        assert!(b.mean().iter().sum::<f64>() > 0.0, "{what}: a black image proves nothing");
    }
}
