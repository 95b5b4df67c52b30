//! Helpers shared by the integration tests.
#![allow(dead_code)]

use vkrt::gpu::{Context, ContextOptions, Validation};

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

/// A path in the repository.
pub fn repo_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A path in the shared data folder beside the repository.
pub fn shared_path(rel: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared").join(rel)
}

/// A scratch folder under target/ for files a test writes (kept for inspection on failure).
pub fn scratch_dir(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-output").join(name);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// The library's generator, under the name the tests use.
#[allow(unused_imports)]
pub use vkrt::rng::Pcg32 as Pcg;

/// Renders `scene` with the path tracer on a fresh context; fails the test on validation
/// messages or NaN/Inf samples.
pub fn render_path(
    scene: &vkrt::scene::Scene,
    settings: &vkrt::integrator::path::PathSettings,
) -> vkrt::integrator::accumulation::Accumulation {
    use vkrt::integrator::gpu_scene::{GpuScene, PreparedScene};
    let ctx = gpu_context();
    let prepared = PreparedScene::new(scene, vkrt::bvh::BuilderKind::Sah, &vkrt::bvh::BuildConfig::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let (acc, stats) =
        vkrt::integrator::path::render(&ctx, scene, &gpu, settings, None, &mut Default::default()).unwrap();
    assert_eq!(stats.nonfinite_samples, 0, "NaN/Inf samples");
    assert_no_validation_messages(&ctx);
    acc
}

/// Path tracer settings for a `width` x `height` render of `spp` samples.
pub fn path_settings(width: u32, height: u32, spp: u64) -> vkrt::integrator::path::PathSettings {
    use vkrt::integrator::path::{PathSettings, Stop};
    let mut s = PathSettings::default();
    s.image.width = width;
    s.image.height = height;
    s.stop = Stop { spp: Some(spp), ..Stop::default() };
    s
}
