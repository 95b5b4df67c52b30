//! The path tracer's command line: `vkrt render --integrator path` and its progressive flags,
//! `vkrt merge` and `vkrt compare`.

use crate::integrator::accumulation::Accumulation;
use crate::integrator::checkpoint::{hash_file, Checkpoint, RunSettings};
use crate::integrator::gpu_scene::GpuScene;
use crate::integrator::path::{self, Hooks, PathSettings, SamplerKind, Stop};
use crate::integrator::{Image, RenderSettings, RenderStats};
use crate::gpu::Context;
use crate::layout::constants::PATH_DEPTH_UNBOUNDED;
use crate::output::compare::compare;
use crate::{output, scene};
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

fn run_settings(run: &PathRun, settings: &PathSettings) -> Result<RunSettings> {
    Ok(RunSettings {
        scene_path: run.scene_path.display().to_string(),
        scene_hash: hash_file(run.scene_path)?,
        width: run.width,
        height: run.height,
        seeds: vec![run.seed],
        integrator: "path".into(),
        sampler: settings.sampler.gpu_value(),
        sample_rate: settings.sample_rate,
        max_depth: settings.max_depth.unwrap_or(PATH_DEPTH_UNBOUNDED),
        nee: settings.nee as u32,
        coherence: settings.coherence,
    })
}

/// Renders with the path tracer and writes the image (plus a PNG preview beside a float image).
pub fn render(ctx: &Context, scene: &scene::Scene, gpu: &GpuScene, run: &PathRun) -> Result<(Image, RenderStats)> {
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
    let ours = run_settings(run, &settings)?;
    let resume = match &a.resume {
        Some(p) => {
            let c = Checkpoint::read(p)?;
            c.settings.check_same_render(&ours).with_context(|| format!("cannot resume {}", p.display()))?;
            if c.settings.seeds != ours.seeds {
                bail!("cannot resume {}: it holds seeds {:?}, this run uses seed {}", p.display(), c.settings.seeds, run.seed);
            }
            Some(c.accum)
        }
        None => None,
    };
    let bar = indicatif::ProgressBar::new(1000);
    if let Ok(style) = indicatif::ProgressStyle::with_template("[{bar:30}] {msg}") {
        bar.set_style(style.progress_chars("=> "));
    }
    let mut progress = |p: &path::PathProgress| {
        bar.set_position((p.fraction * 1000.0) as u64);
        let err = p.relmse.map_or(String::from("-"), |e| format!("{e:.2e}"));
        bar.set_message(format!("{} spp, {:.2} Msamples/s, est. relMSE {err}, {:.1} s", p.samples, p.samples_per_second / 1e6, p.seconds));
    };
    let mut save = |acc: &Accumulation| -> Result<()> {
        match &a.checkpoint {
            Some(p) => Checkpoint { settings: ours.clone(), accum: acc.clone() }.write(p),
            None => Ok(()),
        }
    };
    let interrupt = interrupt_flag();
    let mut hooks = Hooks {
        progress: Some(&mut progress),
        checkpoint: if a.checkpoint.is_some() { Some(&mut save) } else { None },
        checkpoint_interval_s: a.checkpoint_interval,
        interrupt,
    };
    let (acc, stats) = path::render(ctx, scene, gpu, &settings, resume, &mut hooks)?;
    bar.finish_and_clear();
    let image = acc.image();
    write_with_preview(run.output, &image)?;
    let err = acc.estimate_relmse().map_or(String::new(), |e| format!(", estimated relMSE {e:.3e}"));
    let mean = if acc.per_pixel { " (mean over the pixels, adaptive)" } else { "" };
    eprintln!("path tracer: {} spp{mean}{err}", acc.samples);
    if stats.interrupted {
        let saved = a.checkpoint.as_ref().map_or(String::new(), |p| format!(" and checkpoint {}", p.display()));
        bail!("interrupted after {} spp; wrote {}{saved}", acc.samples, run.output.display());
    }
    Ok((image, stats))
}

/// Writes `image`; beside a float image also a PNG preview (same name, `.png`).
pub fn write_with_preview(path: &Path, image: &Image) -> Result<()> {
    output::write_image(path, image)?;
    if output::ImageFormat::from_path(path)? != output::ImageFormat::Png {
        output::write_image(&path.with_extension("png"), image)?;
    }
    Ok(())
}

/// `vkrt merge`: adds checkpoints of runs with different seeds.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Checkpoints written by `vkrt render --integrator path --checkpoint`.
    #[arg(required = true, num_args = 2..)]
    pub inputs: Vec<PathBuf>,
    /// The merged result: an image (.png, .exr, .pfm; float images get a PNG preview) or, with
    /// any other extension, a checkpoint that can be merged or resumed again.
    #[arg(short, long)]
    pub output: PathBuf,
}

pub fn merge(args: &MergeArgs) -> Result<()> {
    let mut iter = args.inputs.iter();
    let Some(first) = iter.next() else { bail!("nothing to merge") };
    let mut merged = Checkpoint::read(first)?;
    for p in iter {
        let c = Checkpoint::read(p)?;
        merged.merge(&c).with_context(|| format!("merging {} into {}", p.display(), first.display()))?;
    }
    if output::ImageFormat::from_path(&args.output).is_ok() {
        write_with_preview(&args.output, &merged.accum.image())?;
    } else {
        merged.write(&args.output)?;
    }
    eprintln!(
        "merged {} runs (seeds {:?}): {} spp into {}",
        args.inputs.len(),
        merged.settings.seeds,
        merged.accum.samples,
        args.output.display()
    );
    Ok(())
}

/// `vkrt compare`: error metrics of an image against a reference.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The image to judge (.exr, .pfm or .png).
    pub image: PathBuf,
    /// The reference.
    pub reference: PathBuf,
    /// Exit with an error if relMSE exceeds this.
    #[arg(long)]
    pub max_relmse: Option<f64>,
}

pub fn compare_images(args: &CompareArgs) -> Result<()> {
    let a = output::read_image(&args.image)?;
    let b = output::read_image(&args.reference)?;
    let c = compare(&a, &b).with_context(|| format!("comparing {} with {}", args.image.display(), args.reference.display()))?;
    let (ma, mb) = (a.mean(), b.mean());
    println!("rmse      {:.6e}", c.rmse);
    println!("relmse    {:.6e}   (mean((a-b)^2 / (b^2 + 0.01)))", c.relmse);
    println!("psnr      {:.3} dB", c.psnr);
    for (k, name) in ["r", "g", "b"].iter().enumerate() {
        let rel = if mb[k] != 0.0 { format!(" ({:+.3} %)", 100.0 * c.mean_diff[k] / mb[k]) } else { String::new() };
        println!("mean {name}    {:.6} vs {:.6}: {:+.6e}{rel}", ma[k], mb[k], c.mean_diff[k]);
    }
    if let Some(max) = args.max_relmse {
        if !(c.relmse <= max) {
            bail!("relMSE {:.6e} exceeds --max-relmse {max:e}", c.relmse);
        }
    }
    Ok(())
}

/// Raised by the first Ctrl-C or SIGTERM; a second one ends the process at once. None if the
/// handler could not be installed (then the signals keep their default effect).
fn interrupt_flag() -> Option<&'static std::sync::atomic::AtomicBool> {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::OnceLock;
    static FLAG: AtomicBool = AtomicBool::new(false);
    static INSTALLED: OnceLock<bool> = OnceLock::new();
    let installed = *INSTALLED.get_or_init(|| {
        ctrlc::set_handler(|| {
            if FLAG.swap(true, Ordering::SeqCst) {
                // Second signal: the user wants out now. 130 = 128 + SIGINT.
                std::process::exit(130);
            }
            eprintln!("\ninterrupted: finishing the current batch, then writing the checkpoint and image");
        })
        .is_ok()
    });
    installed.then_some(&FLAG)
}
