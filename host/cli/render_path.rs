//! The path tracer's half of `vkrt render` (`--integrator path`): its progressive flags, the
//! run's identity for checkpoints, resuming, and the hooks that save checkpoints, show progress
//! and catch Ctrl-C.

use super::interrupt::interrupt_flag;
use crate::gpu::Context;
use crate::gpu_abi::constants::PATH_DEPTH_UNBOUNDED;
use crate::integrator::path::checkpoint::{fnv1a_file, hash_inputs, Checkpoint, Identity, RunSettings};
use crate::integrator::path::{self, Accumulation, Hooks, PathProgress, PathSettings, SamplerKind, Stop};
use crate::integrator::{Image, RenderSettings, RenderStats};
use crate::prepare::GpuScene;
use crate::scene::Scene;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

/// Samples per pixel when a path-traced render names no stop condition.
pub const DEFAULT_PATH_SPP: u64 = 16;

/// Flags of `vkrt render` that only the path tracer reads.
#[derive(Debug, Args)]
pub struct PathArgs {
    /// Path tracer: sample generator.
    #[arg(long, value_enum, default_value_t = SamplerKind::Sobol)]
    pub sampler: SamplerKind,
    /// Path tracer, stratified sampler: strata per pixel side (SampleRate^2 strata).
    #[arg(long, default_value_t = 4)]
    pub sample_rate: u32,
    /// Path tracer: stop after this many seconds (with --spp or --target-relmse, the first to hold).
    #[arg(long)]
    pub time: Option<f64>,
    /// Path tracer: stop once the relMSE estimated from two half-images is at most this.
    #[arg(long)]
    pub target_relmse: Option<f64>,
    /// Path tracer: write the running sums, sample count and settings here every few seconds
    /// (and at the end), atomically.
    #[arg(long)]
    pub checkpoint: Option<PathBuf>,
    /// Path tracer: seconds between checkpoints.
    #[arg(long, default_value_t = 10.0)]
    pub checkpoint_interval: f64,
    /// Path tracer: continue the run saved in this checkpoint (same scene, size and settings).
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Path tracer: samples per pixel per submission.
    #[arg(long, default_value_t = 4)]
    pub samples_per_batch: u32,
    /// Path tracer: BSDF sampling only, no light sampling (for checking the estimators).
    #[arg(long)]
    pub no_nee: bool,
    /// Path tracer: pixels in a row that draw the same sample numbers (coherent path tracing).
    /// 8 makes lavapipe's SIMD lanes trace alike: about 2x faster at the same expected error,
    /// with the noise in short horizontal streaks. 1: every pixel its own numbers.
    #[arg(long, default_value_t = 1)]
    pub coherence: u32,
    /// Path tracer: adaptive sampling. After a uniform pilot of 8 spp, each block of pixels in
    /// a row (8, or whole --coherence blocks) takes samples in proportion to the noise the
    /// pilot showed around it (not in it, which keeps the image unbiased); --spp is then the
    /// mean over the pixels.
    #[arg(long)]
    pub adaptive: bool,
}

/// What the render command passes on.
pub struct PathRun<'a> {
    pub scene_path: &'a Path,
    /// The scene as loaded: its input files make the run's identity.
    pub scene: &'a Scene,
    /// The `--sky` override, as given ("" for the scene's own sky).
    pub sky: &'a str,
    pub output: &'a Path,
    pub width: u32,
    pub height: u32,
    pub seed: u32,
    pub spp: Option<u32>,
    pub max_depth: Option<u32>,
    /// Run the all-features shader rather than the scene's specialised one.
    pub all_features: bool,
    pub args: &'a PathArgs,
}

/// This run's settings as a checkpoint records them: `identity` says which scene.
fn run_settings(run: &PathRun, settings: &PathSettings, identity: Identity) -> RunSettings {
    RunSettings {
        scene_path: run.scene_path.display().to_string(),
        identity,
        width: run.width,
        height: run.height,
        seeds: vec![run.seed],
        integrator: "path".into(),
        sampler: settings.sampler.gpu_value(),
        sample_rate: settings.sample_rate,
        max_depth: settings.max_depth.unwrap_or(PATH_DEPTH_UNBOUNDED),
        nee: settings.nee as u32,
        coherence: settings.coherence,
    }
}

/// The sums of the checkpoint at `path`, if they are this run's (same render, same seed).
fn resumed_sums(path: &Path, run: &PathRun, ours: &RunSettings) -> Result<Accumulation> {
    let c = Checkpoint::read(path)?;
    let ours = match c.settings.identity {
        // An older vkrt hashed only the scene file: check that much, and say so.
        Identity::SceneFile { .. } => {
            eprintln!(
                "warning: {} was written by an older vkrt, which recorded only the scene file's hash: its meshes, \
                 textures and sky cannot be checked",
                path.display()
            );
            RunSettings { identity: Identity::SceneFile { fnv: fnv1a_file(run.scene_path)? }, ..ours.clone() }
        }
        Identity::Inputs { .. } => ours.clone(),
    };
    c.settings.check_same_render(&ours).with_context(|| format!("cannot resume {}", path.display()))?;
    if c.settings.seeds != ours.seeds {
        bail!("cannot resume {}: it holds seeds {:?}, this run uses seed {}", path.display(), c.settings.seeds, run.seed);
    }
    Ok(c.accum)
}

/// What a path-traced render returns to the render command, which writes the image.
pub struct PathOutcome {
    pub image: Image,
    pub stats: RenderStats,
    /// Samples per pixel taken (the mean over the pixels for an adaptive run).
    pub samples: u64,
}

/// Renders with the path tracer, saving checkpoints as asked.
pub fn render(ctx: &Context, gpu: &GpuScene, run: &PathRun) -> Result<PathOutcome> {
    let a = run.args;
    let mut stop = Stop { spp: run.spp.map(u64::from), seconds: a.time, target_relmse: a.target_relmse };
    if stop == Stop::default() {
        stop.spp = Some(DEFAULT_PATH_SPP);
    }
    let settings = PathSettings {
        image: RenderSettings {
            width: run.width,
            height: run.height,
            seed: run.seed,
            samples_per_batch: a.samples_per_batch,
            all_features: run.all_features,
            ..RenderSettings::default()
        },
        max_depth: run.max_depth,
        sampler: a.sampler,
        sample_rate: a.sample_rate,
        nee: !a.no_nee,
        coherence: a.coherence,
        adaptive: a.adaptive,
        stop,
    };
    // Hashing every input costs a read of each file: only runs that save or resume need it.
    let ours = if a.checkpoint.is_some() || a.resume.is_some() {
        let identity = Identity::Inputs { inputs: hash_inputs(&run.scene.stats.inputs)?, sky: run.sky.to_string() };
        Some(run_settings(run, &settings, identity))
    } else {
        None
    };
    let resume = match (&a.resume, &ours) {
        (Some(p), Some(ours)) => Some(resumed_sums(p, run, ours)?),
        _ => None,
    };
    let bar = indicatif::ProgressBar::new(1000);
    if let Ok(style) = indicatif::ProgressStyle::with_template("[{bar:30}] {msg}") {
        bar.set_style(style.progress_chars("=> "));
    }
    let mut progress = |p: &PathProgress| {
        bar.set_position((p.fraction * 1000.0) as u64);
        let err = p.relmse.map_or(String::from("-"), |e| format!("{e:.2e}"));
        bar.set_message(format!("{} spp, {:.2} Msamples/s, est. relMSE {err}, {:.1} s", p.samples, p.samples_per_second / 1e6, p.seconds));
    };
    let mut save = |acc: &Accumulation| -> Result<()> {
        match (&a.checkpoint, &ours) {
            (Some(p), Some(ours)) => Checkpoint { settings: ours.clone(), accum: acc.clone() }.write(p),
            _ => Ok(()),
        }
    };
    let mut hooks = Hooks {
        progress: Some(&mut progress),
        checkpoint: if a.checkpoint.is_some() { Some(&mut save) } else { None },
        checkpoint_interval_s: a.checkpoint_interval,
        interrupt: interrupt_flag(),
    };
    let (acc, stats) = path::render(ctx, gpu, &settings, resume, &mut hooks)?;
    bar.finish_and_clear();
    let err = acc.estimate_relmse().map_or(String::new(), |e| format!(", estimated relMSE {e:.3e}"));
    let mean = if acc.per_pixel { " (mean over the pixels, adaptive)" } else { "" };
    eprintln!("path tracer: {} spp{mean}{err}", acc.samples);
    Ok(PathOutcome { image: acc.image(), stats, samples: acc.samples })
}
