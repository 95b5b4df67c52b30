//! Light-vertex connections (host/integrator/path/connections.rs): the estimator with them
//! converges to the same image as without, against the independent Mitsuba reference, with
//! less error per sample where diffuse interreflection lights the scene; off, the samples are
//! those of the plain path tracer. The furnace check with them is in path_furnace.rs.
//!
//! Measured on lavapipe (cornell-measured 256², 16 spp, Z-ordered Sobol): relMSE 3.03e-3 with
//! connections, 6.03e-3 without (tests/refs/cornell-256.exr, whose own noise is 4.3e-5); 32²
//! at 1024 spp, the worst lit block 0.28 % from the plain path tracer's; image means at scales
//! 1e-3 and 1e3 within 3e-6 of scale 1's.

mod common;

use vkrt::integrator::path::connections::Connections;
use vkrt::output::compare::compare;

const SPP: u64 = 16;

#[test]
fn connections_converge_to_the_reference_with_less_error_per_sample() {
    let reference = common::cornell_reference();
    let scene = common::cornell_measured();
    let bound = common::reference_relmse_bound(SPP);
    let mut relmse = Vec::new();
    for mode in [Connections::On, Connections::Off] {
        let mut settings = common::path_settings(reference.width, reference.height, SPP);
        settings.connections = mode;
        let image = common::render_path(&scene, &settings).image();
        let c = compare(&image, &reference).unwrap();
        let means = reference.mean();
        eprintln!("connections {:?}: relMSE {:.3e}, mean diff {:?}", mode, c.relmse, c.mean_diff);
        assert!(c.relmse <= bound, "connections {:?}: relMSE {:.4e} > {bound:.4e}", mode, c.relmse);
        for k in 0..3 {
            let rel = c.mean_diff[k] / means[k];
            assert!(rel.abs() <= 0.01, "connections {:?}: channel {k} mean off by {:.3} %", mode, rel * 100.0);
        }
        relmse.push(c.relmse);
    }
    // Half measured; a weighting that threw the connections away (or counted a path twice,
    // which the bound above and the furnace catch) would not get under 0.75.
    assert!(relmse[0] <= 0.75 * relmse[1], "connections: relMSE {:.3e} against {:.3e} without", relmse[0], relmse[1]);
}

#[test]
fn connections_agree_with_the_plain_path_tracer_block_by_block() {
    // Both unbiased, so at many samples every 8x8 block's mean agrees within the noise (a
    // weight that did not sum to one over the three strategies shows as a bias where one of
    // them dominates: near the lamp, in corners). 32x32, 1024 spp each, every pixel its own
    // numbers.
    let scene = common::cornell_measured();
    let mut images = Vec::new();
    for mode in [Connections::On, Connections::Off] {
        let mut settings = common::path_settings(32, 32, 1024);
        settings.coherence = 1;
        settings.connections = mode;
        images.push(common::render_path(&scene, &settings).image());
    }
    let (a, b) = (&images[0], &images[1]);
    let mut worst = 0.0f64;
    for by in (0..32).step_by(8) {
        for bx in (0..32).step_by(8) {
            let mean = |img: &vkrt::integrator::Image| {
                let mut s = 0.0f64;
                for y in by..by + 8 {
                    for x in bx..bx + 8 {
                        s += img.get(x, y).iter().map(|&c| f64::from(c)).sum::<f64>();
                    }
                }
                s / 192.0
            };
            let (ma, mb) = (mean(a), mean(b));
            if mb > 0.05 {
                worst = worst.max((ma / mb - 1.0).abs());
            }
        }
    }
    let (ma, mb) = (a.mean(), b.mean());
    eprintln!("worst lit 8x8 block {:.2} %; means {ma:?} vs {mb:?}", worst * 100.0);
    assert!(worst <= 0.03, "a block differs by {:.2} % between the estimators (max 3 %)", worst * 100.0);
    for k in 0..3 {
        assert!((ma[k] / mb[k] - 1.0).abs() <= 0.005, "channel {k}: mean {} with connections, {} without", ma[k], mb[k]);
    }
}

#[test]
fn off_is_the_plain_path_tracer_and_auto_follows_the_materials() {
    // Off draws exactly the samples of a path tracer without the feature: the code is
    // compiled out, so scenes where auto turns it off render the same bytes as before it.
    let scene = common::cornell_measured();
    let mut settings = common::path_settings(24, 16, 4);
    settings.connections = Connections::Off;
    let off = common::render_path(&scene, &settings);
    let again = common::render_path(&scene, &settings);
    assert_eq!(off.even, again.even, "not deterministic");
    settings.connections = Connections::Auto;
    let auto = common::render_path(&scene, &settings);
    assert_ne!(auto.even, off.even, "auto did not connect in a Lambertian box lit by its lamp");
    settings.connections = Connections::On;
    let on = common::render_path(&scene, &settings);
    assert_eq!(auto.even, on.even, "auto and on differ on a Lambertian box");
}

#[test]
fn connections_are_the_same_at_any_scale() {
    // Their weights are ratios of area densities and their contribution G x Le pi / pA, all
    // scale-free: the box at 1e-3 and 1e3 times its size renders the same image (float
    // rounding aside; render_path_on also fails on any NaN or infinite sample).
    let base = common::cornell_measured();
    let ctx = common::gpu_context();
    let mut settings = common::path_settings(32, 32, 64);
    settings.connections = Connections::On;
    let mut means = Vec::new();
    for s in [1e-3f32, 1.0, 1e3] {
        let gpu = common::upload(&ctx, &common::scaled(&base, s));
        means.push(common::render_path_on(&ctx, &gpu, &settings).image().mean());
    }
    eprintln!("image means at scales 1e-3, 1, 1e3: {means:?}");
    for m in [&means[0], &means[2]] {
        for k in 0..3 {
            assert!((m[k] / means[1][k] - 1.0).abs() < 0.005, "channel {k}: {} against {} at scale 1", m[k], means[1][k]);
        }
    }
}

#[test]
fn a_run_counts_the_rays_it_traced_and_connections_add_theirs() {
    // RenderStats::rays sums the shader's per-pixel counts: at least every sample's camera ray,
    // and with connections also each sample's light ray and a shadow ray per connected vertex
    // (about 2.8 more rays per sample in this box: 8.8 against 6.1 at 512², 16 spp).
    let scene = common::cornell_measured();
    let ctx = common::gpu_context();
    let gpu = common::upload(&ctx, &scene);
    let mut settings = common::path_settings(24, 16, 4);
    let samples = 24 * 16 * 4;
    let mut rays = Vec::new();
    for mode in [Connections::Off, Connections::On] {
        settings.connections = mode;
        let (_, stats) = vkrt::integrator::path::render(&ctx, &gpu, &settings, None, &mut Default::default()).unwrap();
        rays.push(stats.rays);
    }
    eprintln!("rays without / with connections: {rays:?} for {samples} samples");
    assert!(rays[0] >= samples, "fewer rays than camera rays: {}", rays[0]);
    assert!(rays[1] > rays[0] + samples, "connections added fewer than one ray per sample: {rays:?}");
}

#[test]
fn a_mirror_scene_connects_when_asked() {
    // The lean mirror build leaves the connections' code out (light_connection.glsl), so a
    // mirror scene with connections on must run the full mirror build, and connect there; auto
    // leaves them off in a scene with a mirror and runs the lean build.
    let scene = common::with_mirrors(common::cornell_measured(), 3, 0);
    let ctx = common::gpu_context();
    let gpu = common::upload(&ctx, &scene);
    let mut settings = common::path_settings(24, 16, 4);
    let mut runs = Vec::new();
    for mode in [Connections::Auto, Connections::On] {
        settings.connections = mode;
        let (acc, stats) = vkrt::integrator::path::render(&ctx, &gpu, &settings, None, &mut Default::default()).unwrap();
        runs.push((acc, stats));
    }
    let (auto, on) = (&runs[0], &runs[1]);
    assert!(!auto.1.light_connections && auto.1.shader == "path_mirrors_lean", "auto: {} {}", auto.1.light_connections, auto.1.shader);
    assert!(on.1.light_connections && on.1.shader == "path_mirrors", "on: {} {}", on.1.light_connections, on.1.shader);
    assert_ne!(auto.0.even, on.0.even, "connections on did not change the samples");
    assert!(on.1.rays > auto.1.rays + 24 * 16 * 4, "connections on traced no light rays: {} against {}", on.1.rays, auto.1.rays);
}
