//! Long progressive runs: thousands of short batches through scenes with glass, water, mirrors
//! and glossy surfaces, where a NaN or Inf sample would most likely appear. The NaN/Inf counter
//! (samples kept out of the sums) must stay 0, and every pixel must be finite.

mod common;

use vkrt::integrator::path::{self, Hooks};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};

#[test]
fn shared_thousands_of_batches_produce_no_nan_or_inf() {
    if common::skip_without_shared("shared_thousands_of_batches_produce_no_nan_or_inf") {
        return;
    }
    let ctx = common::gpu_context();
    let mut total_batches = 0;
    for (name, batches) in [("CornellBox-Water.obj", 1000u64), ("CornellBox-Sphere.obj", 1000), ("CornellBox-Glossy.obj", 1000)] {
        let scene = vkrt::scene::load_scene(&common::shared_path(&format!("scenes/cornell-box/{name}"))).unwrap();
        let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: vkrt::bvh::BuilderKind::Sah, ..Default::default() }).unwrap();
        let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
        // One sample per batch: as many submissions as samples.
        let mut settings = common::path_settings(12, 12, batches);
        settings.image.samples_per_batch = 1;
        let (acc, stats) = path::render(&ctx, &gpu, &settings, None, &mut Hooks::default()).unwrap();
        println!("{name}: {} batches, {} submissions, {} NaN/Inf samples", acc.samples, stats.submissions, stats.nonfinite_samples);
        assert_eq!(acc.samples, batches);
        assert!(stats.submissions as u64 >= batches, "fewer submissions than batches");
        assert_eq!(stats.nonfinite_samples, 0, "{name}: NaN/Inf samples");
        let image = acc.image();
        assert!(image.pixels.iter().flatten().all(|c| c.is_finite() && *c >= 0.0), "{name}: a pixel is not finite");
        assert!(image.mean().iter().all(|&m| m > 0.0), "{name}: black image");
        total_batches += batches;
    }
    assert!(total_batches >= 3000);
    common::assert_no_validation_messages(&ctx);
}
