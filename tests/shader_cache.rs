//! Shader objects and the shader cache (host/gpu/shader_objects.rs, host/pipeline/shader_cache.rs):
//! a shader made as a compute pipeline, as a shader object from SPIR-V, and as one from the
//! binary a run before kept, renders the same bytes; a damaged binary is made again from the
//! SPIR-V and written over. Validation stays off here: Debian 12's layers (1.3.239) predate
//! VK_EXT_shader_object, which is why a context with them on uses pipelines.

mod common;

use vkrt::gpu::{Context, ContextOptions, ShaderObjectUse, Validation};
use vkrt::integrator::path::Accumulation;
use vkrt::integrator::{whitted, Image, RenderSettings};
use vkrt::pipeline::ShaderOrigin;
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};

fn context(shader_objects: ShaderObjectUse, cache: &std::path::Path) -> Context {
    let options = ContextOptions { validation: Some(Validation::Off), shader_objects, shader_cache: Some(cache.to_path_buf()), ..ContextOptions::from_env() };
    Context::new(&options).expect("a Vulkan device (run tools/ensure-deps.sh)")
}

/// The path tracer's sums and the Whitted image of cornell-measured (64², 4 spp) on `ctx`, and
/// where each shader came from.
fn render(ctx: &Context, prepared: &PreparedScene) -> (Accumulation, Image, String, String) {
    let gpu = GpuScene::upload(ctx, prepared).unwrap();
    let (acc, path_stats) = vkrt::integrator::path::render(ctx, &gpu, &common::path_settings(64, 64, 4), None, &mut Default::default()).unwrap();
    assert_eq!(path_stats.nonfinite_samples, 0);
    let settings = RenderSettings { width: 64, height: 64, spp: 2, max_depth: 7, ..RenderSettings::default() };
    let (image, whitted_stats) = whitted::render(ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    (acc, image, path_stats.shader_origin, whitted_stats.shader_origin)
}

fn binaries(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(dir).map(|d| d.map(|e| e.unwrap().path()).collect()).unwrap_or_default();
    files.sort();
    files
}

#[test]
fn pipelines_shader_objects_and_cached_binaries_render_the_same_bytes() {
    let dir = common::scratch_dir("shader_cache");
    let _ = std::fs::remove_dir_all(&dir);
    let prepared = PreparedScene::new(&common::cornell_measured(), &PrepareOptions::default()).unwrap();

    let pipelines = context(ShaderObjectUse::Never, &dir);
    assert!(pipelines.shader_objects.is_none(), "shader objects off by the options");
    let (acc_p, image_p, path_p, whitted_p) = render(&pipelines, &prepared);
    drop(pipelines);
    let pipeline = ShaderOrigin::Pipeline.to_string();
    assert_eq!((path_p.as_str(), whitted_p.as_str()), (pipeline.as_str(), pipeline.as_str()));
    assert!(binaries(&dir).is_empty(), "pipelines keep nothing");

    let ctx = context(ShaderObjectUse::Always, &dir);
    if ctx.info.name.contains("llvmpipe") {
        // Mesa 25's lavapipe (tools/ensure-deps.sh) has the extension: the cache is exercised,
        // and it is what the default (auto) picks there.
        assert!(ctx.shader_objects.is_some(), "lavapipe without shader objects: {}", ctx.info.name);
        assert!(context(ShaderObjectUse::Auto, &dir).shader_objects.is_some(), "auto picks shader objects on lavapipe");
    }
    let Some(_) = ctx.shader_objects else {
        // A device without shader objects makes pipelines whatever the options say.
        let (acc, image, path, _) = render(&ctx, &prepared);
        assert_eq!(path, pipeline);
        assert!(acc.even == acc_p.even && acc.odd == acc_p.odd && image.pixels == image_p.pixels);
        return;
    };
    let from_spirv = ShaderOrigin::SpirvShaderObject { kept: Some(Ok(())) }.to_string();
    let cached = ShaderOrigin::CachedShaderObject.to_string();

    // First run: compiled from SPIR-V, both binaries kept.
    let (acc_s, image_s, path_s, whitted_s) = render(&ctx, &prepared);
    assert_eq!((path_s.as_str(), whitted_s.as_str()), (from_spirv.as_str(), from_spirv.as_str()));
    let files = binaries(&dir);
    assert_eq!(files.len(), 2, "one binary per shader: {files:?}");
    let sizes: Vec<u64> = files.iter().map(|f| std::fs::metadata(f).unwrap().len()).collect();
    assert!(sizes.iter().all(|&s| s > 1000), "whole binaries: {sizes:?}");

    // Second run: both from the cache, nothing rewritten.
    let (acc_c, image_c, path_c, whitted_c) = render(&ctx, &prepared);
    assert_eq!((path_c.as_str(), whitted_c.as_str()), (cached.as_str(), cached.as_str()));
    assert_eq!(binaries(&dir), files);

    // A damaged binary: refused by the driver, made again from SPIR-V, written over whole.
    let damaged = &files[0];
    let mut bytes = std::fs::read(damaged).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0xff;
    bytes.truncate(bytes.len() - 7);
    std::fs::write(damaged, &bytes).unwrap();
    let (acc_d, image_d, path_d, whitted_d) = render(&ctx, &prepared);
    let mut origins = [path_d, whitted_d];
    origins.sort();
    let mut expected = [from_spirv.clone(), cached.clone()];
    expected.sort();
    assert_eq!(origins, expected, "the damaged one from SPIR-V, the other from the cache");
    let after: Vec<u64> = files.iter().map(|f| std::fs::metadata(f).unwrap().len()).collect();
    assert_eq!(after, sizes, "the damaged binary written over whole");
    let (_, _, path_r, whitted_r) = render(&ctx, &prepared);
    assert_eq!((path_r.as_str(), whitted_r.as_str()), (cached.as_str(), cached.as_str()), "the rewritten binary is used");

    for (acc, image, how) in [(&acc_s, &image_s, "from SPIR-V"), (&acc_c, &image_c, "cached"), (&acc_d, &image_d, "after the damage")] {
        assert!(acc.even == acc_p.even && acc.odd == acc_p.odd, "path tracer sums differ from the pipeline's ({how})");
        assert!(image.pixels == image_p.pixels, "Whitted image differs from the pipeline's ({how})");
    }
    assert!(acc_p.even.iter().any(|s| s.iter().any(|&v| v > 0)), "the renders are not black");
}
