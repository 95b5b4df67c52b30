//! Progressive runs: resuming a checkpoint continues the very same samples, merging runs with
//! different seeds is exact, the stop conditions hold, and `vkrt compare` / `vkrt merge` work
//! from the command line.

mod common;

use std::process::Command;
use vkrt::integrator::path::accumulation::Accumulation;
use vkrt::integrator::path::checkpoint::Checkpoint;
use vkrt::integrator::path::{self, Hooks, PathSettings, Stop};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};

const SCENE: &str = "scenes/cornell-measured/cornell.yaml";

fn cornell() -> vkrt::scene::Scene {
    vkrt::scene::load_scene(&common::repo_path(SCENE)).unwrap()
}

fn try_render(settings: &PathSettings, resume: Option<Accumulation>) -> anyhow::Result<Accumulation> {
    let scene = cornell();
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: vkrt::bvh::BuilderKind::Sah, ..Default::default() }).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let result = path::render(&ctx, &gpu, settings, resume, &mut Hooks::default());
    common::assert_no_validation_messages(&ctx);
    result.map(|(acc, _)| acc)
}

fn render(settings: &PathSettings, resume: Option<Accumulation>) -> Accumulation {
    try_render(settings, resume).unwrap()
}

#[test]
fn resuming_continues_the_same_samples_bit_for_bit() {
    let straight = render(&common::path_settings(32, 32, 8), None);
    // The 8-spp run stopped after 4 (interrupted): the Z-ordered sampler's sets are the run's
    // spp (`PathSettings::zsobol_log2`), so the first half belongs to the same run.
    let mut first = common::path_settings(32, 32, 8);
    first.stop.spp = Some(4);
    let half = render(&first, None);
    assert_eq!(half.samples, 4);
    let resumed = render(&common::path_settings(32, 32, 8), Some(half));
    assert_eq!(resumed.samples, 8);
    assert!(
        resumed.even == straight.even && resumed.odd == straight.odd && resumed.counts == straight.counts,
        "4 + 4 resumed spp differ from 8 spp in one run"
    );
}

/// An adaptive run resumed inside its pilot and after it takes the very same samples as one
/// run straight through (the rates travel in the sums, and each block goes on from its own
/// count), with blocks in rows (`coherence_block` 0) and with the coherence squares, on an image
/// whose edges cut squares; every pixel of a host block took its block's count, so the shader's
/// block keys are the host's.
fn adaptive_run_resumes_bit_for_bit(width: u32, height: u32, coherence_block: u32) {
    use vkrt::integrator::path::adaptive::BlockGrid;
    let settings = |spp: u64| {
        let mut s = common::path_settings(width, height, spp);
        s.adaptive = true;
        s.coherence = 8;
        s.coherence_block = coherence_block;
        // All parts of one 24-spp run: the Z-ordered sampler's sets are the run's spp.
        s.zsobol_log2 = vkrt::integrator::path::zsobol_log2(Some(24));
        s
    };
    let straight = render(&settings(24), None);
    assert!(straight.per_pixel && !straight.rates.is_empty());
    let counts: Vec<u64> = (0..straight.even.len()).map(|p| straight.counts(p).0).collect();
    assert!(counts.iter().any(|&n| n != counts[0]), "every pixel took the same count: nothing adapted");
    assert!(counts.iter().all(|&n| n >= 8 && n % 2 == 0), "a pixel missed its pilot or has an odd count");
    let grid = BlockGrid::new(width, height, 8, coherence_block);
    assert_eq!(straight.rates.len(), grid.count());
    for key in 0..grid.count() {
        let b = grid.pixels(key);
        let first = counts[(b.ys.start * width + b.xs.start) as usize];
        for y in b.ys.clone() {
            for x in b.xs.clone() {
                assert_eq!(counts[(y * width + x) as usize], first, "pixel ({x}, {y}) of block {key} took another count");
            }
        }
    }
    let in_pilot = render(&settings(8), None);
    assert!(in_pilot.rates.is_empty() || (0..in_pilot.even.len()).all(|p| in_pilot.counts(p).0 == 8));
    let resumed = render(&settings(24), Some(in_pilot));
    assert!(resumed.even == straight.even && resumed.odd == straight.odd && resumed.counts == straight.counts, "8 + 16 resumed spp differ from 24 in one run");
    let past_pilot = render(&settings(16), None);
    let resumed = render(&settings(24), Some(past_pilot));
    assert!(resumed.even == straight.even && resumed.odd == straight.odd && resumed.counts == straight.counts, "16 + 8 resumed spp differ from 24 in one run");
    assert!(try_render(&common::path_settings(width, height, 32), Some(straight)).is_err(), "an adaptive run resumed as a uniform one");
}

#[test]
fn adaptive_runs_in_rows_resume_bit_for_bit() {
    adaptive_run_resumes_bit_for_bit(32, 32, 0);
    // Rows that do not fill a square number of rounds: the 16-spp run stops mid-round.
    adaptive_run_resumes_bit_for_bit(72, 40, 0);
}

#[test]
fn adaptive_runs_in_coherence_squares_resume_bit_for_bit() {
    adaptive_run_resumes_bit_for_bit(72, 40, 16);
}

/// The stop rules themselves are unit-tested without a clock (integrator::path::stop); here a
/// render with only a time limit takes samples and returns, and one with a target error stops
/// once its estimate reaches it.
#[test]
fn stops_on_time_and_on_target_error() {
    let mut s = common::path_settings(32, 32, 0);
    s.stop = Stop { spp: None, seconds: Some(0.5), target_relmse: None };
    let acc = render(&s, None);
    assert!(acc.samples > 0, "no samples in the time given");
    s.stop = Stop { spp: Some(100_000), seconds: None, target_relmse: Some(0.02) };
    let acc = render(&s, None);
    let est = acc.estimate_relmse().unwrap_or(f64::NAN);
    assert!(est <= 0.02, "stopped at estimated relMSE {est}");
    assert!(acc.samples < 100_000, "target error never reached");
}

fn vkrt(args: &[&str]) -> std::process::Output {
    Command::new(common::vkrt_bin()).args(args).output().unwrap()
}

#[test]
fn cli_checkpoints_merge_exactly_and_compare_gates_on_relmse() {
    let dir = common::scratch_dir("progressive");
    let p = |name: &str| dir.join(name).display().to_string();
    let scene = common::repo_path(SCENE).display().to_string();
    for seed in ["1", "2"] {
        let out = vkrt(&[
            "render",
            &scene,
            "-o",
            &p(&format!("s{seed}.exr")),
            "--integrator",
            "path",
            "--width",
            "32",
            "--height",
            "32",
            "--spp",
            "4",
            "--seed",
            seed,
            "--checkpoint",
            &p(&format!("s{seed}.ckpt")),
        ]);
        assert!(out.status.success(), "render: {}", String::from_utf8_lossy(&out.stderr));
    }
    let out = vkrt(&["merge", &p("s1.ckpt"), &p("s2.ckpt"), "-o", &p("merged.ckpt")]);
    assert!(out.status.success(), "merge: {}", String::from_utf8_lossy(&out.stderr));
    let a = Checkpoint::read(&dir.join("s1.ckpt")).unwrap();
    let b = Checkpoint::read(&dir.join("s2.ckpt")).unwrap();
    let m = Checkpoint::read(&dir.join("merged.ckpt")).unwrap();
    assert_eq!(m.accum.samples, 8);
    assert_eq!(m.settings.seeds, vec![1, 2]);
    for i in 0..m.accum.even.len() {
        for c in 0..3 {
            assert_eq!(m.accum.even[i][c], a.accum.even[i][c] + b.accum.even[i][c], "merged even sum of pixel {i}");
            assert_eq!(m.accum.odd[i][c], a.accum.odd[i][c] + b.accum.odd[i][c], "merged odd sum of pixel {i}");
        }
    }
    // The same seed twice would count its samples twice.
    assert!(!vkrt(&["merge", &p("s1.ckpt"), &p("s1.ckpt"), "-o", &p("bad.ckpt")]).status.success());
    // A checkpoint of another size cannot be resumed.
    let out = vkrt(&[
        "render",
        &scene,
        "-o",
        &p("r.exr"),
        "--integrator",
        "path",
        "--width",
        "16",
        "--height",
        "16",
        "--spp",
        "8",
        "--seed",
        "1",
        "--resume",
        &p("s1.ckpt"),
    ]);
    assert!(!out.status.success(), "resumed a 32x32 checkpoint at 16x16");
    assert!(String::from_utf8_lossy(&out.stderr).contains("size differs"), "{}", String::from_utf8_lossy(&out.stderr));
    // compare gates on relMSE: two 4-spp images of one scene differ (at 32x32 a pixel half on the
    // light differs by ~17, so their relMSE is about 1), identical ones do not.
    let ok = vkrt(&["compare", &p("s1.exr"), &p("s1.exr"), "--max-relmse", "0"]);
    assert!(ok.status.success(), "compare: {}", String::from_utf8_lossy(&ok.stderr));
    assert!(String::from_utf8_lossy(&ok.stdout).contains("relmse"));
    let far = vkrt(&["compare", &p("s1.exr"), &p("s2.exr"), "--max-relmse", "0.01"]);
    assert!(!far.status.success(), "compare passed two different images: {}", String::from_utf8_lossy(&far.stdout));
}

/// A checkpoint knows every file its scene was read from and the sky: resuming (or merging) it
/// after any of them changed is an error naming what changed, not a silent mix of two renders.
#[test]
fn resume_refuses_a_changed_scene_file_or_sky() {
    let dir = common::scratch_dir("identity");
    for f in ["cornell.yaml", "cornell.obj", "cornell.mtl"] {
        std::fs::copy(common::repo_path(&format!("scenes/cornell-measured/{f}")), dir.join(f)).unwrap();
    }
    let p = |name: &str| dir.join(name).display().to_string();
    let scene = p("cornell.yaml");
    let image = p("r.pfm");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", scene.as_str(), "-o", image.as_str(), "--integrator", "path", "--width", "16", "--height", "16"];
        args.extend_from_slice(extra);
        vkrt(&args)
    };
    let ckpt = p("a.ckpt");
    let out = render(&["--spp", "4", "--checkpoint", &ckpt]);
    assert!(out.status.success(), "render: {}", String::from_utf8_lossy(&out.stderr));
    // The material library is not the file named on the command line, and it changed.
    let mtl = dir.join("cornell.mtl");
    let original = std::fs::read_to_string(&mtl).unwrap();
    std::fs::write(&mtl, original.replace("Kd 0.63", "Kd 0.64")).unwrap();
    assert_ne!(std::fs::read_to_string(&mtl).unwrap(), original, "the edit changed nothing");
    let out = render(&["--spp", "8", "--resume", &ckpt]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("cornell.mtl changed"), "resumed after the .mtl changed: {err}");
    std::fs::write(&mtl, &original).unwrap();
    // Another sky is another render too.
    let out = render(&["--spp", "8", "--resume", &ckpt, "--sky", "1,1,1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("sky differs"), "resumed with another sky: {err}");
    let out = render(&["--spp", "8", "--resume", &ckpt]);
    assert!(out.status.success(), "the unchanged scene did not resume: {}", String::from_utf8_lossy(&out.stderr));
}

/// Each dispatch deals its workgroups to the tile's regions in a scattered order (lavapipe
/// splits a dispatch among its threads in order: `integrator::tiles::group_stride`), at a
/// stride that depends on the dispatch's group count. The sums must not depend on it: tiles of
/// 64 pixels (3 x 3 per batch, the last column and row 8 pixels wide) and one tile over the
/// whole image (one dispatch of 17 x 17 workgroups, against 8 x 8 and cut ones: other strides)
/// give the same bytes in every sampling mode. A region dealt twice or missed would show in one
/// of the two.
#[test]
fn the_sums_do_not_depend_on_how_workgroups_are_dealt_to_tiles() {
    for (coherence, block) in [(1, 0), (8, 0), (8, 32)] {
        let mut settings = common::path_settings(136, 136, 4);
        settings.coherence = coherence;
        settings.coherence_block = block;
        settings.image.tile_size = 64;
        let tiled = render(&settings, None);
        settings.image.tile_size = 256;
        let whole = render(&settings, None);
        assert!(tiled.even == whole.even && tiled.odd == whole.odd, "coherence {coherence}/{block}: 64-pixel tiles and one tile differ");
    }
}

/// Batches that grow from measured batch times (`integrator::path::batch`, what `vkrt render`
/// does by default) take the same samples as one sample per batch: the same bytes. On this
/// small, cheap image the batches must actually grow (fewer submissions than samples), or
/// the comparison would test nothing.
#[test]
fn grown_batches_give_the_same_sums_as_single_sample_batches() {
    let scene = cornell();
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(&scene, &PrepareOptions { builder: vkrt::bvh::BuilderKind::Sah, ..Default::default() }).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let mut settings = common::path_settings(24, 24, 40);
    settings.image.samples_per_batch = 1;
    let (single, single_stats) = path::render(&ctx, &gpu, &settings, None, &mut Hooks::default()).unwrap();
    settings.grow_batches = true;
    let (grown, grown_stats) = path::render(&ctx, &gpu, &settings, None, &mut Hooks::default()).unwrap();
    assert_eq!((single.samples, grown.samples), (40, 40));
    assert_eq!(single_stats.submissions, 40, "one submission per sample (one tile)");
    assert!(grown_stats.submissions < 20, "batches did not grow: {} submissions for 40 spp", grown_stats.submissions);
    // The pipeline's creation is timed inside the render's time (render -v reports both).
    for s in [&single_stats, &grown_stats] {
        assert!(s.pipeline_seconds > 0.0 && s.pipeline_seconds < s.seconds, "pipeline {} s of a {} s render", s.pipeline_seconds, s.seconds);
    }
    assert!(single.even == grown.even && single.odd == grown.odd && single.counts == grown.counts, "grown batches changed the sums");
    common::assert_no_validation_messages(&ctx);
}
