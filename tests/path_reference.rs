//! The path tracer against an independent reference (tests/refs/SOURCE.md: Mitsuba 3, 4096 spp)
//! and its determinism.
//!
//! Bound, from ../shared/refs/README.md: a correct path tracer with next-event estimation has
//! relMSE about 0.175 / spp on this scene; we allow twice that plus 1e-4 (the reference's own
//! noise is 4.3e-5), and per-channel means within 1 %. Measured on lavapipe: Sobol 7.0e-3 at
//! 16 spp (bound 2.2e-2), means within 0.11 %; with coherence 8, 6.8e-3, means within 0.1 %.

mod common;

use vkrt::integrator::path::SamplerKind;
use vkrt::output::compare::compare;
use vkrt::output::read_image;

const SPP: u64 = 16;

fn cornell() -> vkrt::scene::Scene {
    vkrt::scene::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap()
}

#[test]
fn cornell_converges_to_the_mitsuba_reference_with_every_sampler() {
    let reference = read_image(&common::repo_path("tests/refs/cornell-256.exr")).unwrap();
    let scene = cornell();
    let bound = 2.0 * 0.175 / SPP as f64 + 1e-4;
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Stratified] {
        let mut settings = common::path_settings(reference.width, reference.height, SPP);
        settings.sampler = sampler;
        let image = common::render_path(&scene, &settings).image();
        let c = compare(&image, &reference).unwrap();
        let means = reference.mean();
        eprintln!("{sampler:?}: relMSE {:.3e} (bound {bound:.3e}), mean diff {:?}", c.relmse, c.mean_diff);
        if c.relmse > bound || (0..3).any(|k| c.mean_diff[k].abs() > 0.01 * means[k]) {
            let dir = common::scratch_dir("path_reference");
            vkrt::output::write_image(&dir.join(format!("cornell-{sampler:?}.exr")), &image).unwrap();
        }
        assert!(c.relmse <= bound, "{sampler:?}: relMSE {:.4e} > {bound:.4e}", c.relmse);
        for k in 0..3 {
            let rel = c.mean_diff[k] / means[k];
            assert!(rel.abs() <= 0.01, "{sampler:?}: channel {k} mean off by {:.3} %", rel * 100.0);
        }
    }
}

/// Pearson correlation of the error (image minus reference, summed over channels) between
/// horizontal neighbours (x, x + 1): those in the same block of `block` pixels, and those on
/// either side of a block boundary.
fn neighbour_error_correlation(image: &vkrt::integrator::Image, reference: &vkrt::integrator::Image, block: u32) -> (f64, f64) {
    let err = |x: u32, y: u32| -> f64 {
        let (a, b) = (image.get(x, y), reference.get(x, y));
        (0..3).map(|k| f64::from(a[k] - b[k])).sum()
    };
    let correlation = |pairs: &[(f64, f64)]| -> f64 {
        let n = pairs.len() as f64;
        let (ma, mb) = (pairs.iter().map(|p| p.0).sum::<f64>() / n, pairs.iter().map(|p| p.1).sum::<f64>() / n);
        let cov: f64 = pairs.iter().map(|p| (p.0 - ma) * (p.1 - mb)).sum();
        let va: f64 = pairs.iter().map(|p| (p.0 - ma).powi(2)).sum();
        let vb: f64 = pairs.iter().map(|p| (p.1 - mb).powi(2)).sum();
        cov / (va * vb).sqrt()
    };
    let (mut within, mut across) = (Vec::new(), Vec::new());
    for y in 0..image.height {
        for x in 0..image.width - 1 {
            let pair = (err(x, y), err(x + 1, y));
            if (x + 1) % block == 0 { across.push(pair) } else { within.push(pair) }
        }
    }
    (correlation(&within), correlation(&across))
}

/// Coherent sampling (`PathSettings::coherence`): each pixel's estimate is distributed as
/// without it, so the image meets the same bound; and the pixels of a block really do share
/// their numbers, which shows as correlated errors inside blocks and not across them.
#[test]
fn coherent_sampling_meets_the_same_bound_and_correlates_only_within_blocks() {
    let reference = read_image(&common::repo_path("tests/refs/cornell-256.exr")).unwrap();
    let scene = cornell();
    let bound = 2.0 * 0.175 / SPP as f64 + 1e-4;
    let means = reference.mean();
    let mut settings = common::path_settings(reference.width, reference.height, SPP);
    let plain = common::render_path(&scene, &settings).image();
    settings.coherence = 8;
    let coherent = common::render_path(&scene, &settings).image();
    let c = compare(&coherent, &reference).unwrap();
    eprintln!("coherence 8: relMSE {:.3e} (bound {bound:.3e}), mean diff {:?}", c.relmse, c.mean_diff);
    assert!(c.relmse <= bound, "relMSE {:.4e} > {bound:.4e}", c.relmse);
    for k in 0..3 {
        let rel = c.mean_diff[k] / means[k];
        assert!(rel.abs() <= 0.01, "channel {k} mean off by {:.3} %", rel * 100.0);
    }
    let (within, across) = neighbour_error_correlation(&coherent, &reference, 8);
    let (plain_within, _) = neighbour_error_correlation(&plain, &reference, 8);
    eprintln!("error correlation of neighbours: coherent within {within:.3}, across {across:.3}; plain {plain_within:.3}");
    assert!(within > 0.5, "coherent neighbours in a block: correlation {within:.3}");
    // Neighbours in different blocks draw independent numbers (measured 0.15: they still see
    // alike surroundings).
    assert!(across < within - 0.4, "coherent neighbours across a block boundary: correlation {across:.3}");
    assert!(plain_within < 0.2, "plain neighbours: correlation {plain_within:.3}");
}

#[test]
fn same_seed_same_image_bit_for_bit() {
    let scene = cornell();
    let mut settings = common::path_settings(64, 64, 4);
    settings.image.seed = 7;
    let a = common::render_path(&scene, &settings);
    let b = common::render_path(&scene, &settings);
    assert!(a.even == b.even && a.odd == b.odd && a.counts == b.counts, "two runs with the same seed differ");
    settings.image.seed = 8;
    let c = common::render_path(&scene, &settings);
    assert!(a.even != c.even, "another seed gave the same image");
}

/// Adaptive sampling (integrator::adaptive) at the same mean spp: unbiased, so the means stay
/// within 1 % and the relMSE bound holds, and it puts the samples where the error is, so its
/// relMSE is below the uniform run's with the same sampler, seed and coherence. Measured at
/// 256x256, 32 spp, coherence 8: 2.36e-3 against uniform 2.67e-3 (the pilot's 8 spp are a
/// quarter of the budget here; at 512x512 and 64 spp the gain is 12 %).
#[test]
fn adaptive_sampling_meets_the_bound_with_less_error_than_uniform() {
    const MEAN_SPP: u64 = 32;
    let reference = read_image(&common::repo_path("tests/refs/cornell-256.exr")).unwrap();
    let scene = cornell();
    let bound = 2.0 * 0.175 / MEAN_SPP as f64 + 1e-4;
    let means = reference.mean();
    let mut settings = common::path_settings(reference.width, reference.height, MEAN_SPP);
    settings.coherence = 8;
    let uniform = compare(&common::render_path(&scene, &settings).image(), &reference).unwrap();
    settings.adaptive = true;
    let acc = common::render_path(&scene, &settings);
    let total: u64 = (0..acc.even.len()).map(|p| acc.counts(p).0).sum();
    let c = compare(&acc.image(), &reference).unwrap();
    eprintln!("adaptive: relMSE {:.3e} (uniform {:.3e}, bound {bound:.3e}), mean diff {:?}, {total} samples", c.relmse, uniform.relmse, c.mean_diff);
    let pixels = (reference.width * reference.height) as u64;
    assert!(total >= MEAN_SPP * pixels && total <= (MEAN_SPP + 1) * pixels, "{total} samples for a mean of {MEAN_SPP} spp");
    assert!(c.relmse <= bound, "relMSE {:.4e} > {bound:.4e}", c.relmse);
    for k in 0..3 {
        let rel = c.mean_diff[k] / means[k];
        assert!(rel.abs() <= 0.01, "channel {k} mean off by {:.3} %", rel * 100.0);
    }
    assert!(c.relmse < uniform.relmse, "adaptive relMSE {:.4e} is not below uniform {:.4e}", c.relmse, uniform.relmse);
}
