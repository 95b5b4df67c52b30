//! Helpers shared by the integration tests, and the test scenes they generate.
#![allow(dead_code)]

pub mod closed_meshes;
pub mod gltf_writer;
pub mod noise;
pub mod procedural;

use vkrt::gpu::{Context, ContextOptions, Validation};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};

/// A Vulkan context for tests: the device from `VKRT_DEVICE` (default: the best one, lavapipe on
/// CI), with the validation layers on whenever they are installed.
pub fn gpu_context() -> Context {
    let mut options = ContextOptions::from_env();
    options.validation.get_or_insert(Validation::IfAvailable);
    Context::new(&options).expect("a Vulkan device (run tools/ensure-deps.sh)")
}

/// Fails the test if the validation layers said anything.
pub fn assert_no_validation_messages(ctx: &Context) {
    let messages = ctx.validation_messages();
    assert!(messages.is_empty(), "{} validation message(s):\n{}", messages.len(), messages.join("\n"));
}

/// The repository: `VKRT_REPO` if set (a test binary carried to a machine without Rust with
/// `tools/device-check --pack`), else where the test was built.
pub fn repo_root() -> std::path::PathBuf {
    std::env::var_os("VKRT_REPO").map(Into::into).unwrap_or_else(|| env!("CARGO_MANIFEST_DIR").into())
}

/// A path in the repository.
pub fn repo_path(rel: &str) -> std::path::PathBuf {
    repo_root().join(rel)
}

/// A path in the shared data folder beside the repository (`VKRT_SHARED` if set).
pub fn shared_path(rel: &str) -> std::path::PathBuf {
    std::env::var_os("VKRT_SHARED").map(std::path::PathBuf::from).unwrap_or_else(|| repo_root().join("../shared")).join(rel)
}

/// The `vkrt` binary the CLI tests run: `VKRT_BIN` if set, else the one cargo built.
pub fn vkrt_bin() -> std::path::PathBuf {
    std::env::var_os("VKRT_BIN").map(Into::into).unwrap_or_else(|| env!("CARGO_BIN_EXE_vkrt").into())
}

/// `rel` in the shared data folder, or None, with the reason printed, when the folder is not
/// there (a bare clone): tests that need `../shared` skip themselves then, by name, and run
/// everywhere the data is (CI has it).
pub fn shared_or_skip(test: &str, rel: &str) -> Option<std::path::PathBuf> {
    let path = shared_path(rel);
    if path.exists() {
        return Some(path);
    }
    // Written to the stderr handle, not through eprintln!, which the test harness captures: the
    // reason shows in the test log even when the test passes.
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: needs {} (the shared test data beside the repository), which is absent", path.display());
    None
}

/// True, after printing why, when `../shared` (the shared test data beside the repository) is
/// absent: a test that needs it is named `shared_*` and returns at once then, so that `cargo
/// test` passes in a bare clone; CI, which has the data, runs it.
pub fn skip_without_shared(test: &str) -> bool {
    shared_or_skip(test, "scenes").is_none()
}

/// The SPIR-V of a test probe (host/pipeline/variants.rs, role Probe): built by host/build.rs
/// into `$OUT_DIR/probes/`, never embedded in the library.
pub fn probe_spirv(name: &str) -> Vec<u8> {
    // VKRT_PROBES: where `tools/device-check --pack` put them, on a machine without the build.
    let dir = std::env::var_os("VKRT_PROBES").map_or_else(|| std::path::Path::new(env!("OUT_DIR")).join("probes"), std::path::PathBuf::from);
    let path = dir.join(format!("{name}.spv"));
    std::fs::read(&path).unwrap_or_else(|e| panic!("probe {}: {e}", path.display()))
}

/// Builds the default BVH (binned SAH, threaded), prepares and uploads `scene`.
pub fn upload<'a>(ctx: &'a Context, scene: &vkrt::scene::Scene) -> GpuScene<'a> {
    upload_with(ctx, scene, &PrepareOptions::default())
}

/// The same with other build and layout options.
pub fn upload_with<'a>(ctx: &'a Context, scene: &vkrt::scene::Scene, options: &PrepareOptions) -> GpuScene<'a> {
    let prepared = PreparedScene::new(scene, options).expect("prepare the scene");
    GpuScene::upload(ctx, &prepared).expect("upload the scene")
}

/// A scratch folder under target/ for files a test writes (kept for inspection on failure).
pub fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = repo_root().join("target/test-output").join(name);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// The library's generator, under the name the tests use.
#[allow(unused_imports)]
pub use vkrt::rng::Pcg32 as Pcg;

/// Renders `scene` with the path tracer on a fresh context; fails the test on validation
/// messages or NaN/Inf samples.
pub fn render_path(scene: &vkrt::scene::Scene, settings: &vkrt::integrator::path::PathSettings) -> vkrt::integrator::path::Accumulation {
    let ctx = gpu_context();
    let gpu = upload(&ctx, scene);
    render_path_on(&ctx, &gpu, settings)
}

/// The same for a scene already on the device (one with an environment map, say).
pub fn render_path_on(ctx: &Context, gpu: &GpuScene, settings: &vkrt::integrator::path::PathSettings) -> vkrt::integrator::path::Accumulation {
    let (acc, stats) = vkrt::integrator::path::render(ctx, gpu, settings, None, &mut Default::default()).unwrap();
    assert_eq!(stats.nonfinite_samples, 0, "NaN/Inf samples");
    assert_no_validation_messages(ctx);
    acc
}

/// `scene` on the device with `options`, lit by `env` as its environment map when given (as
/// `--envmap` does: the map replaces a bare model's default light).
pub fn upload_lit<'a>(ctx: &'a Context, scene: &vkrt::scene::Scene, env: Option<&vkrt::prepare::EnvLight>, options: &PrepareOptions) -> GpuScene<'a> {
    let prepared = PreparedScene::new(scene, options).expect("prepare the scene");
    let mut gpu = GpuScene::upload(ctx, &prepared).expect("upload the scene");
    if let Some(env) = env {
        let a = prepared.arrays();
        gpu.set_environment(ctx, env, a.picks, a.total_weight, scene.stats.default_light).expect("set the environment map");
    }
    gpu
}

/// Path tracer settings for a `width` x `height` render of `spp` samples.
pub fn path_settings(width: u32, height: u32, spp: u64) -> vkrt::integrator::path::PathSettings {
    use vkrt::integrator::path::{zsobol_log2, PathSettings, Stop};
    let mut s = PathSettings::default();
    s.image.width = width;
    s.image.height = height;
    s.stop = Stop { spp: Some(spp), ..Stop::default() };
    s.zsobol_log2 = zsobol_log2(Some(spp));
    s
}

/// `scene` scaled by `s` about the origin: every vertex and the camera's eye and target (the
/// scale tests: a scale-free estimator renders the same image).
pub fn scaled(scene: &vkrt::scene::Scene, s: f32) -> vkrt::scene::Scene {
    let mut scene = scene.clone();
    for t in &mut scene.triangles {
        for p in &mut t.p {
            *p *= s;
        }
    }
    scene.camera.eye *= s;
    scene.camera.target *= s;
    scene
}

/// The measured Cornell box (scenes/cornell-measured), the scene of the path tracer's
/// reference images (tests/refs/cornell-256.exr).
pub fn cornell_measured() -> vkrt::scene::Scene {
    vkrt::scene::load_scene(&repo_path("scenes/cornell-measured/cornell.yaml")).unwrap()
}

/// `scene` with a 0.9 mirror (illum 3) on its non-emissive triangles k with k % every == phase:
/// a mirror scene made from any other (the mirror builds and the mirror probe run on it).
pub fn with_mirrors(mut scene: vkrt::scene::Scene, every: usize, phase: usize) -> vkrt::scene::Scene {
    let mirror = scene.materials.len() as u32;
    scene.materials.push(vkrt::scene::Material { name: "mirror".into(), specular: glam::Vec3::splat(0.9), illum: 3, ..Default::default() });
    for (k, t) in scene.triangles.iter_mut().enumerate() {
        if k % every == phase && !scene.materials[t.material as usize].is_emissive() {
            t.material = mirror;
        }
    }
    scene
}

/// The independent reference of the measured Cornell box (tests/refs/cornell-256.exr: Mitsuba 3,
/// 4096 spp, 256²).
pub fn cornell_reference() -> vkrt::integrator::Image {
    vkrt::output::read_image(&repo_path("tests/refs/cornell-256.exr")).unwrap()
}

/// The relMSE a correct path tracer with next-event estimation stays under at `spp` against an
/// independent reference: ../shared/refs/README.md measures about 0.175 / spp on the Cornell
/// box; allowed twice that plus 1e-4 (the reference's own noise, 4.3e-5 for cornell-256.exr).
pub fn reference_relmse_bound(spp: u64) -> f64 {
    2.0 * 0.175 / spp as f64 + 1e-4
}

/// `vkrt trace`'s arguments for a closest-hit run of `rays` through `scene` into `output`, with
/// the default builder and order and `layout` (None: the command's default).
#[allow(dead_code)]
pub fn trace_args(
    scene: &std::path::Path,
    rays: &std::path::Path,
    output: &std::path::Path,
    layout: Option<vkrt::accel::LayoutKind>,
) -> vkrt::cli::trace::TraceArgs {
    vkrt::cli::trace::TraceArgs {
        scene: scene.to_path_buf(),
        rays: rays.to_path_buf(),
        output: output.to_path_buf(),
        builder: vkrt::bvh::BuilderKind::Reinsertion,
        layout,
        no_triangle_list: false,
        any_hit: false,
        order: vkrt::query::ray_order::RayOrder::Auto,
        device: vkrt::cli::DeviceArgs { device: None },
    }
}
