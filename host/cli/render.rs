//! `vkrt render`: a scene to an image with the Whitted integrator or the path tracer.

use super::progress::DelayedProgress;
use super::render_path::{self, PathArgs, PathRun};
use super::DeviceArgs;
use crate::accel::LayoutKind;
use crate::bvh::{BuildConfig, BuilderKind};
use crate::integrator::{whitted, RenderSettings};
use crate::prepare::{Features, GpuScene, PrepareOptions, PreparedScene};
use crate::{output, scene};
use anyhow::{bail, Context as _, Result};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::time::Instant;

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
    /// Rays per path (1 = primary rays only). Default: 7 for Whitted (at most 15), unbounded for
    /// the path tracer.
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
    /// BVH layout the shaders walk.
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
    pub path: PathArgs,
}

pub fn run(args: &RenderArgs) -> Result<()> {
    // Fail on an unwritable output before spending time on the render.
    output::check_writable(&args.output)?;
    if args.width == 0 || args.height == 0 {
        bail!("--width and --height must be positive");
    }
    let t0 = Instant::now();
    let mut scene = scene::load_scene(&args.scene)?;
    if let Some(sky) = &args.sky {
        scene.sky = scene::Sky::parse_constant(sky)?;
    }
    let load_s = t0.elapsed().as_secs_f64();
    let options = PrepareOptions { builder: args.builder, layout: args.layout, build: BuildConfig::default() };
    let prepared = PreparedScene::new(&scene, &options)?;
    let ctx = args.device.context()?;
    let t1 = Instant::now();
    let gpu = GpuScene::upload(&ctx, &prepared)?;
    let upload_s = t1.elapsed().as_secs_f64();
    if args.verbose {
        report(args, &scene, &prepared, &gpu, &ctx.info, load_s, upload_s);
    }
    let mut progress = DelayedProgress::new("rendering");
    let (image, stats, interrupted_at) = match args.integrator {
        IntegratorKind::Whitted => {
            let settings = RenderSettings {
                width: args.width,
                height: args.height,
                spp: args.spp.unwrap_or(1),
                max_depth: args.max_depth.unwrap_or(7),
                seed: args.seed,
                all_features: args.all_features,
                ..RenderSettings::default()
            };
            let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |d, t| progress.update(d, t))?;
            (image, stats, None)
        }
        IntegratorKind::Path => {
            let run = PathRun {
                scene_path: &args.scene,
                scene: &scene,
                sky: args.sky.as_deref().unwrap_or(""),
                output: &args.output,
                width: args.width,
                height: args.height,
                seed: args.seed,
                spp: args.spp,
                max_depth: args.max_depth,
                all_features: args.all_features,
                args: &args.path,
            };
            let out = render_path::render(&ctx, &gpu, &run)?;
            let interrupted = out.stats.interrupted.then_some(out.samples);
            (out.image, out.stats, interrupted)
        }
    };
    progress.finish();
    // The one place a render's output is written. The path tracer's float images get a PNG
    // preview beside them.
    output::write_render(&args.output, &image, args.integrator == IntegratorKind::Path)?;
    if let Some(samples) = interrupted_at {
        let saved = args.path.checkpoint.as_ref().map_or(String::new(), |p| format!(" and checkpoint {}", p.display()));
        bail!("interrupted after {samples} spp; wrote {}{saved}", args.output.display());
    }
    ctx.check_validation().context("Vulkan validation")?;
    eprintln!(
        "rendered {} at {}x{}, {} in {:.3} s on {}{}",
        args.output.display(),
        args.width,
        args.height,
        match args.integrator {
            IntegratorKind::Whitted => format!("{} spp, depth {}", args.spp.unwrap_or(1), args.max_depth.unwrap_or(7)),
            IntegratorKind::Path => format!("depth {}", args.max_depth.map_or("unbounded".into(), |d| d.to_string())),
        },
        stats.seconds,
        ctx.info.name,
        if stats.nonfinite_samples > 0 { format!(" ({} NaN/Inf samples dropped)", stats.nonfinite_samples) } else { String::new() }
    );
    Ok(())
}

/// `--verbose`: what was loaded, how long each stage took, and which shader variant runs and why.
fn report(
    args: &RenderArgs,
    scene: &scene::Scene,
    prepared: &PreparedScene,
    gpu: &GpuScene,
    device: &crate::gpu::DeviceInfo,
    load_s: f64,
    upload_s: f64,
) {
    eprintln!(
        "scene {}: {} triangles, {} materials, {} lights, {} emissive triangles, {} dropped as degenerate",
        args.scene.display(),
        scene.triangles.len(),
        scene.materials.len(),
        scene.lights.len(),
        gpu.emitter_count,
        scene.stats.dropped_degenerate
    );
    eprintln!("device: {} ({})", device.name, device.driver_info);
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
    let features = if args.all_features { Features::all() } else { prepared.info.features.clone() };
    let how = if args.all_features { "unspecialised, --all-features" } else { "specialised to the scene" };
    eprintln!("shader variant: {:?} {} ({how}): {}", args.integrator, args.layout.name(), features.variant_name());
    eprint!("{}", features.report());
}
