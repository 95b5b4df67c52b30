//! The `vkrt` command line.

use crate::bvh::{BuildConfig, BuilderKind};
use crate::gpu::{Context, ContextOptions};
use crate::integrator::gpu_scene::{GpuScene, PreparedScene};
use crate::integrator::{whitted, RenderSettings};
use crate::layout::LayoutKind;
use crate::{output, scene};
use anyhow::{Context as _, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// vkrt: a GPU-agnostic ray and path tracer on Vulkan compute shaders.
///
/// Runs headless on any Vulkan 1.2 device, including Mesa's lavapipe on a machine with no GPU.
#[derive(Debug, Parser)]
#[command(name = "vkrt", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene (.obj or lab .yaml) to an image (.png, .exr or .pfm).
    Render(RenderArgs),
    /// List the Vulkan devices and the limits that matter to vkrt.
    Info(DeviceArgs),
    /// Batch ray queries without rendering: rays from an .npy file, hits to an .npy file.
    Trace(crate::bench::trace_cmd::TraceArgs),
    /// Compare every BVH builder x layout on scenes: a table, CSV or JSON, and a heat map.
    Bvh(crate::bench::bvh_table::BvhArgs),
    /// Add path-traced checkpoints made with different seeds into one image or checkpoint.
    Merge(crate::cli_path::MergeArgs),
    /// Print RMSE, relMSE, PSNR and per-channel mean differences of an image against a reference.
    Compare(crate::cli_path::CompareArgs),
}

#[derive(Debug, Args)]
pub struct DeviceArgs {
    /// Vulkan device: an index from `vkrt info` or part of its name. Default: a discrete GPU
    /// if present, else the best other device (lavapipe on a machine without a GPU).
    #[arg(long, env = "VKRT_DEVICE", global = true)]
    pub device: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorKind {
    /// Whitted-style ray tracing: Blinn-Phong, hard shadows, mirrors, refraction.
    Whitted,
    /// Progressive unbiased path tracing: light sampling with MIS, Russian roulette.
    Path,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file: Wavefront .obj (with its .mtl) or a course-lab .yaml.
    pub scene: PathBuf,
    /// Output image; the extension picks the format: .png (sRGB 8-bit), .exr or .pfm (linear float).
    #[arg(short, long)]
    pub output: PathBuf,
    #[arg(long, default_value_t = 512)]
    pub width: u32,
    #[arg(long, default_value_t = 512)]
    pub height: u32,
    #[arg(long, value_enum, default_value_t = IntegratorKind::Whitted)]
    pub integrator: IntegratorKind,
    /// Rays per path (1 = primary rays only). Default: 7 for Whitted, unbounded for the path tracer.
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Samples per pixel. Whitted (default 1): 1 samples the pixel centre, more are jittered.
    /// Path tracer: the total to stop at (default 16 when no --time or --target-relmse).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Seed for the jittered samples: the same seed gives the same image.
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// BVH builder: median split (fast build) or binned SAH (faster rendering).
    #[arg(long, value_enum, default_value_t = BuilderKind::Sah)]
    pub builder: BuilderKind,
    /// BVH layout the shaders walk: threaded (escape links), multi-order (six threaded orders,
    /// one per dominant ray direction), parent-link (ordered, Hapala et al. 2011) or compact
    /// (threaded in 16-byte quantised nodes).
    #[arg(long, value_enum, default_value_t = LayoutKind::Threaded)]
    pub layout: LayoutKind,
    /// Print scene and timing details, and which shader variant ran and why.
    #[arg(short, long)]
    pub verbose: bool,
    /// What rays that leave the scene see, as linear RGB radiance `R,G,B` (e.g. `1,1,1`):
    /// replaces the scene's sky box; lights the scene in the path tracer. Default: the scene's
    /// sky box if it has one, else black.
    #[arg(long, value_name = "R,G,B")]
    pub sky: Option<String>,
    /// Run the all-features shader instead of the variant specialised to what the scene uses
    /// (same image, slower; for comparisons and benchmarks).
    #[arg(long)]
    pub all_features: bool,
    #[command(flatten)]
    pub device: DeviceArgs,
    #[command(flatten)]
    pub path: crate::cli_path::PathArgs,
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render(&args),
        Command::Info(args) => info(&args),
        Command::Trace(args) => crate::bench::trace_cmd::run(&args).map(|_| ()),
        Command::Bvh(args) => crate::bench::bvh_table::run(&args),
        Command::Merge(args) => crate::cli_path::merge(&args),
        Command::Compare(args) => crate::cli_path::compare_images(&args),
    }
}

fn info(args: &DeviceArgs) -> Result<()> {
    let devices = crate::gpu::context::list_devices()?;
    let chosen = crate::gpu::context::choose_device(&devices, args.device.as_deref()).ok();
    for d in &devices {
        let mark = if Some(d.index) == chosen { "  <- vkrt uses this one" } else { "" };
        println!("{d}{mark}");
    }
    if devices.is_empty() {
        println!("no Vulkan devices found");
    }
    Ok(())
}

/// A progress bar that appears only once the work has taken over a second.
struct DelayedProgress {
    bar: indicatif::ProgressBar,
    start: Instant,
    shown: bool,
}

impl DelayedProgress {
    fn new(what: &str) -> Self {
        let bar = indicatif::ProgressBar::hidden();
        if let Ok(style) = indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {percent}% {elapsed} (eta {eta})") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(what.to_string());
        Self { bar, start: Instant::now(), shown: false }
    }
    fn update(&mut self, done: u64, total: u64) {
        if !self.shown && self.start.elapsed() > Duration::from_secs(1) {
            self.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        self.bar.set_length(total);
        self.bar.set_position(done);
    }
    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

fn render(args: &RenderArgs) -> Result<()> {
    // Fail on an unwritable output before spending time on the render.
    output::check_writable(&args.output)?;
    if args.width == 0 || args.height == 0 {
        anyhow::bail!("--width and --height must be positive");
    }
    let t0 = Instant::now();
    let mut scene = scene::load_scene(&args.scene)?;
    if let Some(sky) = &args.sky {
        scene.sky = scene::Sky::parse_constant(sky)?;
    }
    let load_s = t0.elapsed().as_secs_f64();
    let prepared = PreparedScene::with_layout(&scene, args.builder, args.layout, &BuildConfig::default())?;
    let options = ContextOptions { device: args.device.device.clone(), ..ContextOptions::from_env() };
    let ctx = Context::new(&options)?;
    let t1 = Instant::now();
    let gpu = GpuScene::upload(&ctx, &prepared)?;
    let upload_s = t1.elapsed().as_secs_f64();
    if args.verbose {
        eprintln!(
            "scene {}: {} triangles, {} materials, {} lights, {} emissive triangles, {} dropped as degenerate",
            args.scene.display(),
            scene.triangles.len(),
            scene.materials.len(),
            scene.lights.len(),
            gpu.emitter_count,
            scene.stats.dropped_degenerate
        );
        eprintln!("device: {} ({})", ctx.info.name, ctx.info.driver_info);
        eprintln!(
            "load {:.3} s, {:?} BVH build {:.3} s ({} nodes), upload {:.3} s",
            load_s,
            args.builder,
            prepared.build_seconds,
            prepared.flat.node_count(),
            upload_s
        );
        if !prepared.atlas.table.is_empty() {
            eprintln!(
                "textures: {} ({} MiB of texels)",
                prepared.atlas.table.len(),
                std::mem::size_of_val(prepared.atlas.texels.as_slice()) >> 20
            );
        }
        let features = if args.all_features { scene::features::Features::all() } else { scene::features::Features::of(&scene) };
        let how = if args.all_features { "unspecialised, --all-features" } else { "specialised to the scene" };
        eprintln!("shader variant: {:?} {} ({how}): {}", args.integrator, args.layout.name(), features.variant_name());
        eprint!("{}", features.report());
    }
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        spp: args.spp.unwrap_or(1),
        max_depth: args.max_depth.unwrap_or(7),
        seed: args.seed,
        all_features: args.all_features,
        ..RenderSettings::default()
    };
    let mut progress = DelayedProgress::new("rendering");
    let (image, stats) = match args.integrator {
        IntegratorKind::Whitted => whitted::render(&ctx, &scene, &gpu, &settings, &mut |d, t| progress.update(d, t))?,
        IntegratorKind::Path => {
            let run = crate::cli_path::PathRun {
                scene_path: &args.scene,
                output: &args.output,
                width: args.width,
                height: args.height,
                seed: args.seed,
                spp: args.spp,
                max_depth: args.max_depth,
                all_features: args.all_features,
                args: &args.path,
            };
            crate::cli_path::render(&ctx, &scene, &gpu, &run)?
        }
    };
    progress.finish();
    if args.integrator == IntegratorKind::Whitted {
        output::write_image(&args.output, &image)?;
    }
    ctx.check_validation().context("Vulkan validation")?;
    eprintln!(
        "rendered {} at {}x{}, {} in {:.3} s on {}{}",
        args.output.display(),
        args.width,
        args.height,
        match args.integrator {
            IntegratorKind::Whitted => format!("{} spp, depth {}", settings.spp, settings.max_depth),
            IntegratorKind::Path => format!("depth {}", args.max_depth.map_or("unbounded".into(), |d| d.to_string())),
        },
        stats.seconds,
        ctx.info.name,
        if stats.nonfinite_samples > 0 { format!(" ({} NaN/Inf samples dropped)", stats.nonfinite_samples) } else { String::new() }
    );
    Ok(())
}
