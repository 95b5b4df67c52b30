//! `vkrt render`: a scene to an image with the Whitted integrator or the path tracer.
//!
//! Everything that can be checked is checked before any work: flags that do not apply, sizes
//! beyond what the device and the machine can hold, an unwritable output. A resumed path-traced
//! run takes its scene, size, camera and sampling settings from its checkpoint.

use super::args::{at_least_one, exposure, fov, non_negative, vec3, whole};
use super::progress::{Progress, Status};
use super::render_path::{self, PathArgs, PathRun};
use super::shard;
use super::DeviceArgs;
use crate::accel::LayoutKind;
use crate::bvh::{BuildConfig, BuilderKind};
use crate::gpu::{Context, DeviceInfo};
use crate::integrator::path::checkpoint::{camera_flags, Checkpoint, Identity, CAMERA_NUMBERS};
use crate::integrator::path::connections::{self, Connections};
use crate::integrator::path::shard::Shard;
use crate::integrator::path::Stop;
use crate::integrator::{whitted, Image, RenderSettings};
use crate::output;
use crate::output::display::{Display, Exposure, Tonemap};
use crate::prepare::cache::{prepare_scene, Cache, CacheOutcome, Prepared, Storing};
use crate::prepare::{Features, GpuScene, PrepareOptions, SceneArrays, SceneInfo};
use crate::scene::camera::Lens;
use crate::scene::{Camera, SceneSummary};
use anyhow::{bail, Context as _, Result};
use clap::{Args, ValueEnum};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorKind {
    /// Whitted-style ray tracing: Blinn-Phong, hard shadows, mirrors, refraction.
    Whitted,
    /// Progressive unbiased path tracing: light sampling with MIS, Russian roulette.
    Path,
}

/// `--cache off`: no prepared-scene or shader cache.
const CACHE_OFF: &str = "off";

/// Default image size, both sides.
pub const DEFAULT_SIZE: u32 = 512;
/// The Whitted integrator's defaults.
pub const WHITTED_DEFAULT_DEPTH: u32 = 7;

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file: Wavefront .obj (with its .mtl), a course-lab .yaml or glTF 2.0 (.gltf, .glb). Not needed with
    /// --resume, whose checkpoint names it.
    pub scene: Option<PathBuf>,
    /// The image to write, exactly this file; the extension picks the format: .png (8-bit
    /// sRGB, after --exposure and --tonemap), .exr or .pfm (linear float radiance). With
    /// --resume, default: the checkpoint's.
    #[arg(help_heading = "Output", short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Image width in pixels [default: 512].
    #[arg(help_heading = "Image", long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "PIXELS")]
    pub width: Option<u32>,
    /// Image height in pixels [default: 512].
    #[arg(help_heading = "Image", long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "PIXELS")]
    pub height: Option<u32>,
    /// Integrator [default: whitted, or path when a path-tracer flag such as --time or
    /// --resume is given].
    #[arg(help_heading = "Image", long, value_enum)]
    pub integrator: Option<IntegratorKind>,
    /// Rays per path (1 = primary rays only). Whitted: 1 to 15 (its ray tree lives on a fixed
    /// stack), default 7. Path tracer: default unbounded (Russian roulette ends paths).
    #[arg(help_heading = "Image", long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "RAYS")]
    pub max_depth: Option<u32>,
    /// Samples per pixel, at least 1. Whitted (default 1): 1 samples the pixel centre, more are
    /// jittered. Path tracer: the total to stop at (default 16 when no --time or
    /// --target-relmse).
    #[arg(help_heading = "Image", long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "N")]
    pub spp: Option<u32>,
    /// Seed of the samples: the same seed gives the same image, bit for bit [default: 0].
    #[arg(hide = true, long, value_parser = whole, allow_negative_numbers = true)]
    pub seed: Option<u32>,
    /// BVH builder: median, sah (binned SAH), sweep-sah or reinsertion (binned SAH, refined) [default: reinsertion].
    #[arg(hide = true, long, value_enum)]
    pub builder: Option<BuilderKind>,
    /// BVH layout the shaders walk [default: threaded; a scene with instances is walked
    /// through a two-level BVH, one copy of each mesh, both levels in the layout asked for];
    /// none changes the image beyond rounding.
    #[arg(hide = true, long, value_enum)]
    pub layout: Option<LayoutKind>,
    /// Put every triangle in the BVH, none in the triangle list that the scene's few largest
    /// triangles (a room's walls) otherwise join, tested by every ray before its walk.
    #[arg(hide = true, long)]
    pub no_triangle_list: bool,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Also write an 8-bit PNG preview of the image here (after --exposure and --tonemap).
    #[arg(help_heading = "Output", long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,
    /// Print scene and timing details, the camera used and which shader variant ran and why.
    #[arg(help_heading = "Output", short, long)]
    pub verbose: bool,
    /// Print nothing but errors: no progress, no warnings, no summary.
    #[arg(help_heading = "Output", short, long, conflicts_with = "verbose")]
    pub quiet: bool,
    /// What rays that leave the scene see, as linear RGB radiance `R,G,B` (e.g. `1,1,1`):
    /// replaces the scene's sky box; lights the scene in the path tracer. Default: the scene's
    /// sky box if it has one, else black.
    #[arg(help_heading = "Lights", long, value_name = "R,G,B")]
    pub sky: Option<String>,
    #[command(flatten)]
    pub envmap: super::sky::EnvmapArgs,
    /// Run the all-features shader instead of the variant specialised to what the scene uses
    /// (same image, slower; for comparisons and benchmarks).
    #[arg(hide = true, long)]
    pub all_features: bool,
    #[command(flatten)]
    pub path: PathArgs,
    /// Keep prepared scenes (BVH, shading arrays, textures) in this folder and reuse them
    /// while the scene's files and the build settings are unchanged [default: the user's cache
    /// folder, $XDG_CACHE_HOME/vkrt or ~/.cache/vkrt, for scenes that take 0.5 s or more to
    /// prepare, at most 16 GiB]. With a folder given, every scene is kept and none evicted.
    /// Compiled shaders are kept in its `shaders` folder (devices with shader objects, such as
    /// lavapipe: ~0.13 s less start-up per render there). `off`: prepare the scene and compile
    /// the shaders from their files, and keep nothing (a folder named off: `./off`).
    #[arg(help_heading = "Device", long, value_name = "DIR|off", env = "VKRT_CACHE")]
    pub cache: Option<PathBuf>,
    /// Prepare the scene and compile the shaders from their files, and keep nothing (as
    /// `--cache off`).
    #[arg(hide = true, long, conflicts_with = "cache")]
    pub no_cache: bool,
    #[command(flatten)]
    pub device: DeviceArgs,
}

impl RenderArgs {
    /// The prepared-scene cache this run uses, if any.
    fn scene_cache(&self) -> Option<Cache> {
        if self.no_cache || self.cache.as_deref() == Some(Path::new(CACHE_OFF)) {
            return None;
        }
        match &self.cache {
            Some(dir) => Some(Cache::at(dir.clone())),
            None => Cache::default_for_user(),
        }
    }
}

/// Which camera renders: the scene file's (or its N-th), with any of its parts replaced.
#[derive(Debug, Args, Default)]
pub struct CameraArgs {
    /// Render from the scene file's camera N (0 is the first, in file order).
    #[arg(help_heading = "Camera", long, value_parser = whole, allow_negative_numbers = true, value_name = "N")]
    pub camera: Option<u32>,
    /// Camera position, replacing the scene camera's.
    #[arg(help_heading = "Camera", long, value_parser = vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub eye: Option<Vec3>,
    /// The point the camera looks at.
    #[arg(help_heading = "Camera", long, value_parser = vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub target: Option<Vec3>,
    /// The camera's up direction.
    #[arg(hide = true, long, value_parser = vec3, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(help_heading = "Camera", long, value_parser = fov, value_name = "DEGREES")]
    pub fov: Option<f32>,
    /// Thin-lens depth of field: the aperture's radius in scene units [default: 0, a pinhole].
    /// The Whitted integrator blurs only with --spp above 1.
    #[arg(hide = true, long, value_parser = non_negative, value_name = "R")]
    pub aperture: Option<f32>,
    /// Distance from the eye to the plane in focus [default: the distance to the target].
    #[arg(hide = true, long, value_parser = non_negative, value_name = "D")]
    pub focus_distance: Option<f32>,
}

/// How the image becomes an 8-bit picture (PNG outputs and previews; float outputs stay
/// linear and scene-referred).
#[derive(Debug, Args, Default)]
pub struct DisplayArgs {
    /// Exposure in stops: the image is scaled by 2^EV before the display transform; `auto`
    /// maps the image's log-average luminance to middle grey 0.18, unless that would push the
    /// brightest 5 % of pixels past 1; 0 shows the radiance as it is [default: auto].
    #[arg(help_heading = "Output", long, value_parser = exposure, allow_negative_numbers = true, value_name = "EV|auto")]
    pub exposure: Option<Exposure>,
    /// Display transform for 8-bit outputs: neutral (Khronos PBR Neutral: colours below 0.76
    /// unchanged, highlights rolled off, never clipped), aces (filmic S-curve) or clamp (clip
    /// at 1) [default: neutral].
    #[arg(help_heading = "Output", long, value_enum)]
    pub tonemap: Option<Tonemap>,
}

impl DisplayArgs {
    pub fn display(&self) -> Display {
        Display { exposure: self.exposure.unwrap_or_default(), tonemap: self.tonemap.unwrap_or_default() }
    }
}

/// A camera as the numbers a checkpoint stores.
pub fn camera_numbers(c: &Camera) -> [f32; CAMERA_NUMBERS] {
    let (l, t, u) = (c.lens, c.target, c.up);
    [c.eye.x, c.eye.y, c.eye.z, t.x, t.y, t.z, u.x, u.y, u.z, c.fov_y_deg, l.aperture_radius, l.focus_distance]
}

pub fn camera_from(n: &[f32; CAMERA_NUMBERS]) -> Camera {
    Camera {
        eye: Vec3::new(n[0], n[1], n[2]),
        target: Vec3::new(n[3], n[4], n[5]),
        up: Vec3::new(n[6], n[7], n[8]),
        fov_y_deg: n[9],
        lens: Lens { aperture_radius: n[10], focus_distance: n[11] },
    }
}

impl CameraArgs {
    /// The camera to render with: `base` (the scene's, or a resumed run's), or the scene file's
    /// camera `--camera N`, with the parts given on the command line replaced.
    pub fn choose(&self, scene: &SceneSummary, base: Camera) -> Result<Camera> {
        let mut cam = match self.camera {
            Some(n) => *scene.cameras.get(n as usize).with_context(|| {
                let count = scene.cameras.len();
                if count == 0 {
                    format!("--camera {n}: the scene file defines no camera")
                } else {
                    format!("--camera {n}: the scene file defines {count} camera(s), numbered 0 to {}", count - 1)
                }
            })?,
            None => base,
        };
        cam.eye = self.eye.unwrap_or(cam.eye);
        cam.target = self.target.unwrap_or(cam.target);
        cam.up = self.up.unwrap_or(cam.up);
        cam.fov_y_deg = self.fov.unwrap_or(cam.fov_y_deg);
        cam.lens.aperture_radius = self.aperture.unwrap_or(cam.lens.aperture_radius);
        cam.lens.focus_distance = self.focus_distance.unwrap_or(cam.lens.focus_distance);
        cam.frame().with_context(|| format!("the camera {} cannot render", camera_flags(&camera_numbers(&cam))))?;
        Ok(cam)
    }
}

/// The prepared scene as a render sees it, uploaded: the sky (`sky`, as `sky::sky_text` gives
/// it) and the camera (`base`, with `camera`'s parts replaced) set in `scene`, the shader
/// features they imply (an environment map replaces the default light, in the variant too),
/// and the environment map's light table. Shared by `vkrt render` and the Python package
/// (python/src/scene.rs), so that both render the same bytes.
pub fn view_and_upload<'a>(
    ctx: &'a Context,
    arrays: &SceneArrays,
    info: &SceneInfo,
    scene: &mut SceneSummary,
    sky: &str,
    camera: &CameraArgs,
    base: Camera,
) -> Result<GpuScene<'a>> {
    let env = super::sky::apply(sky, scene)?;
    scene.camera = camera.choose(scene, base)?;
    let mut info = info.with_view(&scene.camera, &scene.sky);
    if env.is_some() && scene.stats.default_light {
        info.features = info.features.without_default_light();
    }
    let mut gpu = GpuScene::upload_arrays(ctx, arrays, &info)?;
    if let Some(env) = &env {
        gpu.set_environment(ctx, env, arrays.picks, arrays.total_weight, scene.stats.default_light)?;
    }
    Ok(gpu)
}

/// Prints a line on stderr unless `--quiet`.
struct Say {
    quiet: bool,
}

impl Say {
    fn line(&self, text: &str) {
        if !self.quiet {
            eprintln!("{text}");
        }
    }
}

/// The integrator to use: as asked, or the path tracer when a flag only it reads is given.
fn choose_integrator(args: &RenderArgs, say: &Say) -> Result<IntegratorKind> {
    let path_flags = args.path.given();
    match (args.integrator, path_flags.first()) {
        (Some(IntegratorKind::Whitted), Some(flag)) => {
            bail!("{flag} needs --integrator path (the Whitted integrator renders its samples once, with no progressive run)")
        }
        (Some(kind), _) => Ok(kind),
        (None, Some(flag)) => {
            // A checkpoint can only be the path tracer's: no need to say so.
            if *flag != "--resume" {
                say.line(&format!("note: {flag} selects the path tracer (--integrator path)"));
            }
            Ok(IntegratorKind::Path)
        }
        (None, None) => Ok(IntegratorKind::Whitted),
    }
}

/// Bytes per pixel of a render: the largest buffer bound whole (an accumulation buffer or plane),
/// all the device's buffers, and what the host holds at the end (sums read back, the image,
/// the encoded picture), for each integrator.
fn bytes_per_pixel(integrator: IntegratorKind) -> (u64, u64, u64) {
    match integrator {
        IntegratorKind::Whitted => (16, 16, 16 + 12 + 12 + 4),
        // Seven planes of 8 bytes (fixed-point sums, counts), ray counts and, in scenes with
        // mirrors, the mirror probe; on the host two copies of the sums while one is read back,
        // the image and the picture.
        IntegratorKind::Path => (8, 7 * 8 + 4 + 4, 2 * 56 + 12 + 12 + 4),
    }
}

/// Memory the system says is available now (Linux: /proc/meminfo's MemAvailable).
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Fails, naming the limit, if a `width` x `height` image cannot be rendered on `device` with
/// the memory this machine has: before any work, instead of an allocation failure later.
pub fn check_image_size(device: &DeviceInfo, width: u32, height: u32, integrator: IntegratorKind) -> Result<()> {
    let pixels = width as u64 * height as u64;
    let (binding, device_total, host_total) = bytes_per_pixel(integrator);
    let mib = |b: u64| b >> 20;
    let side = |px: u64| (px as f64).sqrt() as u64;
    let binding_limit = device.max_storage_buffer_range as u64 / binding;
    if pixels > binding_limit {
        bail!(
            "--width {width} --height {height} is {pixels} pixels; {} binds at most {} MiB in one buffer, which holds \
             {binding_limit} pixels of accumulation ({binding} bytes each), e.g. {}x{}",
            device.name,
            mib(device.max_storage_buffer_range as u64),
            side(binding_limit),
            side(binding_limit)
        );
    }
    if device.device_local_bytes > 0 && pixels * device_total > device.device_local_bytes {
        bail!(
            "--width {width} --height {height} needs {} MiB of device memory for its buffers; {} has {} MiB",
            mib(pixels * device_total),
            device.name,
            mib(device.device_local_bytes)
        );
    }
    if let Some(free) = available_memory() {
        if pixels * host_total > free {
            bail!("--width {width} --height {height} needs about {} MiB of memory for the image; {} MiB are available", mib(pixels * host_total), mib(free));
        }
    }
    Ok(())
}

/// `path` made absolute against the current folder (checkpoints record absolute paths, so a
/// run resumes from anywhere).
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// A render's settings, resolved before any work: each from its flag, else from a resumed
/// checkpoint, else the default; and the part of a sharded run this is, asked for or held.
struct RenderPlan {
    integrator: IntegratorKind,
    resumed: Option<Checkpoint>,
    shard: Option<Shard>,
    scene_path: PathBuf,
    output: PathBuf,
    width: u32,
    height: u32,
    seed: u32,
    builder: BuilderKind,
    layout: LayoutKind,
    display: Display,
}

impl RenderPlan {
    fn resolve(args: &RenderArgs, say: &Say) -> Result<Self> {
        let integrator = choose_integrator(args, say)?;
        let resumed = match &args.path.resume {
            Some(p) => Some(Checkpoint::read(p)?),
            None => None,
        };
        let stored = resumed.as_ref().map(|c| &c.settings);
        if let Some(c) = &resumed {
            if c.settings.seeds.len() > 1 {
                bail!(
                    "cannot resume a merged checkpoint (seeds {:?}): its runs cannot go on as one; turn it into an image \
                     with `vkrt merge`",
                    c.settings.seeds
                );
            }
        }
        let defaults = stored.map(|s| &s.resume).filter(|r| !r.output.is_empty());
        // A shard: asked for now, or the resumed checkpoint's (a preempted shard goes on).
        let requested = args.path.shard.requested(&|name| std::env::var(name).ok())?;
        let timed = if args.path.time.is_some() {
            Some("--time")
        } else if args.path.target_relmse.is_some() {
            Some("--target-relmse")
        } else {
            None
        };
        let mut shard = shard::resolve(requested, args.spp.map(u64::from), args.path.adaptive, timed)?;
        if let Some(set) = stored.and_then(|s| s.shards.as_ref()) {
            let &[index] = set.indices.as_slice() else {
                bail!("cannot resume merged shards ({:?} of {}): merge the rest with `vkrt merge`", set.indices, set.count);
            };
            let held = Shard::new(index, set.count, set.total_spp)?;
            if shard.is_some_and(|s| s != held) {
                bail!("the checkpoint is shard {} of a {}-spp run; this command asks for another part", held.label(), held.total_spp);
            }
            shard = Some(held);
        }
        let scene_path = match (&args.scene, stored) {
            (Some(p), _) => p.clone(),
            (None, Some(s)) => PathBuf::from(&s.scene_path),
            (None, None) => bail!("no scene file given (vkrt render SCENE -o OUTPUT)"),
        };
        let output = match (&args.output, defaults) {
            (Some(p), _) => p.clone(),
            (None, Some(d)) => PathBuf::from(&d.output),
            (None, None) if resumed.is_some() => bail!("the checkpoint does not record its output (an older vkrt wrote it): give -o"),
            (None, None) => bail!("no output given: -o FILE (.png, .exr or .pfm)"),
        };
        let output = shard::output_path(&output, shard)?;
        let width = args.width.or(stored.map(|s| s.width)).unwrap_or(DEFAULT_SIZE);
        let height = args.height.or(stored.map(|s| s.height)).unwrap_or(DEFAULT_SIZE);
        let seed = args.seed.or(stored.and_then(|s| s.seeds.first().copied())).unwrap_or(0);
        let builder = args.builder.or_else(|| defaults.and_then(|d| BuilderKind::from_str(&d.builder, false).ok())).unwrap_or_default();
        let layout = args.layout.or_else(|| defaults.and_then(|d| LayoutKind::from_str(&d.layout, false).ok())).unwrap_or_default();
        let display = args.display.display();
        Ok(Self { integrator, resumed, shard, scene_path, output, width, height, seed, builder, layout, display })
    }
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let say = Say { quiet: args.quiet };
    let RenderPlan { integrator, resumed, shard, scene_path, output, width, height, seed, builder, layout, display } = RenderPlan::resolve(args, &say)?;
    let stored = resumed.as_ref().map(|c| &c.settings);

    // Checks that need no scene.
    if shard.is_some() {
        if args.preview.is_some() || args.path.preview_every.is_some() {
            bail!("a shard writes only its sums (-o .ckpt): --preview and --preview-every show an image, which shards do not have");
        }
        if args.path.checkpoint.as_ref().is_some_and(|c| *c != output) {
            bail!("a shard writes its sums to -o {}: leave out --checkpoint", output.display());
        }
    } else {
        output::check_writable(&output)?;
    }
    if let Some(p) = &args.preview {
        if output::ImageFormat::from_path(p).ok() != Some(output::ImageFormat::Png) {
            bail!("--preview {}: a preview is an 8-bit picture; name a .png", p.display());
        }
        output::check_writable(p)?;
    }
    if integrator == IntegratorKind::Whitted && args.max_depth.is_some_and(|d| d > whitted::MAX_DEPTH) {
        bail!("--max-depth {}: the Whitted integrator traces 1 to {} rays per path", args.max_depth.unwrap_or(0), whitted::MAX_DEPTH);
    }
    if integrator == IntegratorKind::Path {
        render_path::check_coherence(&args.path, stored)?;
    }
    let cache = args.scene_cache();
    // Compiled shaders go where prepared scenes do, and nowhere with --no-cache.
    let ctx = args.device.context_with_shader_cache(cache.as_ref().map(|c| super::shader_cache_in(&c.dir)))?;
    check_image_size(&ctx.info, width, height, integrator)?;

    let options = PrepareOptions { builder, layout, build: BuildConfig::default(), triangle_list: !args.no_triangle_list };
    let t0 = Instant::now();
    let (prepared, cache_outcome, storing, parse_s) = prepare_scene(&scene_path, &options, cache.as_ref(), &mut |w| say.line(&format!("warning: {w}")))?;
    let prepare_s = t0.elapsed().as_secs_f64();
    let mut scene = prepared.summary().clone();
    for w in scene.stats.warnings.iter().chain(prepared.downsampled()) {
        say.line(&format!("warning: {w}"));
    }
    // The sky and the camera: the command line's, else a resumed run's, else the scene's.
    let stored_identity = stored.map(|s| &s.identity);
    let (stored_sky, stored_camera) = match stored_identity {
        Some(Identity::Inputs { sky, camera, .. }) => (Some(sky.clone()), Some(camera_from(camera))),
        _ => (None, None),
    };
    let sky = super::sky::sky_text(&args.sky, &args.envmap, stored_sky)?;
    let t1 = Instant::now();
    let base = stored_camera.unwrap_or(scene.camera);
    let gpu = view_and_upload(&ctx, &prepared.arrays()?, &prepared.info(), &mut scene, &sky, &args.camera, base)?;
    let upload_s = t1.elapsed().as_secs_f64();
    if args.verbose {
        report(args, &scene_path, &scene, &prepared, &gpu, &ctx.info, (parse_s, prepare_s, upload_s), &cache_outcome, integrator);
    }
    // What the cache just checked, for a checkpoint's identity; then the mapping can go.
    let input_hashes = prepared.input_hashes().map(<[_]>::to_vec);
    drop(prepared);

    let mut progress = Progress::new("rendering", args.quiet);
    let write_outputs = |image: &Image| -> Result<()> {
        // A shard's output is its checkpoint, written by the run.
        if shard.is_some() {
            return Ok(());
        }
        output::write_render(&output, image, &display)?;
        if let Some(p) = &args.preview {
            output::write_render(p, image, &display)?;
        }
        Ok(())
    };
    let (image, stats, interrupted_at, relmse) = match integrator {
        IntegratorKind::Whitted => {
            let settings = RenderSettings {
                width,
                height,
                spp: args.spp.unwrap_or(1),
                max_depth: args.max_depth.unwrap_or(WHITTED_DEFAULT_DEPTH),
                seed,
                all_features: args.all_features,
                ..RenderSettings::default()
            };
            let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |done, total| {
                progress.update(&Status { fraction: done as f64 / total.max(1) as f64, count: Some((done, Some(total), "tiles")), ..Status::default() })
            })?;
            progress.finish();
            (image, stats, None, None)
        }
        IntegratorKind::Path => {
            let image = RenderSettings {
                width,
                height,
                seed,
                samples_per_batch: args.path.samples_per_batch.unwrap_or(render_path::DEFAULT_SAMPLES_PER_BATCH),
                all_features: args.all_features,
                ..RenderSettings::default()
            };
            let stop = render_path::stop_rules(args.spp, &args.path, stored.map(|s| &s.resume));
            let mut settings = render_path::path_settings(&args.path, image, args.max_depth, stored, stop);
            settings.adaptive |= resumed.as_ref().is_some_and(|c| c.accum.per_pixel);
            if let Some(s) = shard {
                let (first, n) = s.range();
                settings.first_sample = first;
                settings.stop = Stop { spp: Some(n), ..Stop::default() };
            }
            let run = PathRun {
                scene: &scene,
                input_hashes,
                scene_path: absolute(&scene_path).display().to_string(),
                sky,
                camera: camera_numbers(&scene.camera),
                settings,
                seed,
                output: absolute(&output).display().to_string(),
                builder: builder.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default(),
                layout: layout.name().to_string(),
                // A shard saves into -o; a resumed run keeps saving into its checkpoint unless
                // told otherwise.
                checkpoint: if shard.is_some() { Some(output.clone()) } else { args.path.checkpoint.clone().or_else(|| args.path.resume.clone()) },
                checkpoint_interval: args.path.checkpoint_interval.unwrap_or(render_path::DEFAULT_CHECKPOINT_INTERVAL_S),
                resume: resumed,
                resume_path: args.path.resume.clone(),
                preview_every: args.path.preview_every,
                shard,
            };
            if run.settings.connections == Connections::On {
                if let Some(why) = connections::unavailable(&run.settings, &gpu) {
                    say.line(&format!("warning: --connections on: no light-vertex connections here: {why}"));
                }
            }
            let mut preview = |image: &Image| write_outputs(image);
            let out = render_path::render(&ctx, &gpu, &run, &mut progress, &mut preview, &|line| say.line(line))?;
            let interrupted = out.stats.interrupted.then_some(out.samples);
            (out.image, out.stats, interrupted, out.relmse.map(|e| (out.samples, e)))
        }
    };
    // The one place a render's outputs are written.
    write_outputs(&image)?;
    if let Some(samples) = interrupted_at {
        let checkpoint = args.path.checkpoint.as_ref().or(args.path.resume.as_ref());
        let saved = checkpoint.map_or(String::new(), |p| format!(" and checkpoint {}", p.display()));
        bail!("interrupted after {samples} spp; wrote {}{saved}", output.display());
    }
    ctx.check_validation().context("Vulkan validation")?;
    // The prepared-scene entry, written while the render ran.
    match storing.map(Storing::finish) {
        Some(CacheOutcome::Stored { entry, seconds }) if args.verbose => {
            eprintln!("prepared-scene cache: stored {} ({seconds:.3} s, beside the render)", entry.display())
        }
        Some(CacheOutcome::NotStored { why }) => say.line(&format!("warning: prepared-scene cache: {why}")),
        _ => {}
    }
    if args.verbose {
        // The path tracer's batches grow on cheap scenes (integrator::path::batch): this shows how far.
        eprintln!(
            "{} submissions to the device; pipeline creation {:.3} s of the render time (shader build {}, {})",
            stats.submissions, stats.pipeline_seconds, stats.shader, stats.shader_origin
        );
        if integrator == IntegratorKind::Path {
            eprintln!("light-vertex connections {} (--connections)", if stats.light_connections { "on" } else { "off" });
            eprintln!("{} rays traced ({:.2} M rays/s of the render time)", stats.rays, stats.rays as f64 / stats.seconds.max(1e-9) / 1e6);
        }
        if stats.estimates > 0 {
            eprintln!("{} error estimates (read-back and pass over the sums) took {:.3} s of it", stats.estimates, stats.estimate_seconds);
        }
    }
    let what = match (integrator, relmse) {
        (IntegratorKind::Whitted, _) => format!("{} spp, depth {}", args.spp.unwrap_or(1), args.max_depth.unwrap_or(WHITTED_DEFAULT_DEPTH)),
        (IntegratorKind::Path, est) => {
            let depth = args.max_depth.map_or("unbounded".into(), |d| d.to_string());
            let est = est.map_or(String::new(), |(spp, e)| format!("{spp} spp, estimated relMSE {e:.3e}, "));
            format!("{est}depth {depth}")
        }
    };
    let dropped = if stats.nonfinite_samples > 0 { format!(" ({} NaN/Inf samples dropped)", stats.nonfinite_samples) } else { String::new() };
    say.line(&format!("rendered {} at {width}x{height}, {what} in {:.3} s on {}{dropped}", output.display(), stats.seconds, ctx.info.name));
    Ok(())
}

/// `--verbose`: what was loaded, how long each stage took, the camera in the flags' own
/// syntax, and which shader variant runs and why.
#[allow(clippy::too_many_arguments)]
fn report(
    args: &RenderArgs,
    scene_path: &Path,
    scene: &SceneSummary,
    prepared: &Prepared,
    gpu: &GpuScene,
    device: &DeviceInfo,
    (parse_s, prepare_s, upload_s): (f64, f64, f64),
    cache: &CacheOutcome,
    integrator: IntegratorKind,
) {
    eprintln!(
        "scene {}: {} triangles, {} materials, {} lights, {} emissive triangles, {} dropped as degenerate",
        scene_path.display(),
        scene.triangles,
        scene.materials,
        scene.lights,
        gpu.emitter_count,
        scene.stats.dropped_degenerate
    );
    eprintln!("camera: {}", camera_flags(&camera_numbers(&scene.camera)));
    eprintln!("device: {} ({})", device.name, device.driver_info);
    let nodes = gpu.bvh.push.node_count;
    match cache {
        CacheOutcome::Hit { entry, seconds } => {
            eprintln!("load {seconds:.3} s from the prepared-scene cache ({nodes} nodes; {}), upload {upload_s:.3} s", entry.display());
        }
        _ => {
            let t = prepared.times();
            eprintln!(
                "load {parse_s:.3} s, BVH build {:.3} s (boxes {:.3}, tree {:.3} on {} threads, layout {:.3}; {nodes} nodes), shading arrays {:.3} s, upload {upload_s:.3} s",
                t.bvh(),
                t.boxes,
                t.tree,
                BuildConfig::default().thread_count(),
                t.flatten,
                t.shading,
            );
            match cache {
                CacheOutcome::Storing { entry } => {
                    eprintln!("prepared-scene cache: storing {} beside the render ({prepare_s:.3} s to load and prepare)", entry.display())
                }
                CacheOutcome::NotStored { why } => eprintln!("prepared-scene cache: not stored ({why})"),
                _ => eprintln!("prepared-scene cache: off"),
            }
        }
    }
    let arrays = prepared.arrays().ok();
    if let Some(a) = &arrays {
        let mib = |bytes: usize| bytes as f64 / f64::from(1 << 20);
        let bvh = a.nodes.len() + std::mem::size_of_val(a.triangles) + std::mem::size_of_val(a.instances);
        let shading = std::mem::size_of_val(a.shading) + std::mem::size_of_val(a.uvs) + std::mem::size_of_val(a.tangents);
        eprintln!(
            "device arrays: BVH {:.1} MiB (nodes and triangles in leaf order), shading {:.1} MiB (normals, texture coordinates, tangents)",
            mib(bvh),
            mib(shading)
        );
        if !a.textures.is_empty() {
            eprintln!("textures: {} ({} MiB of texels)", a.textures.len(), std::mem::size_of_val(a.texels) >> 20);
        }
    }
    let features = if args.all_features { Features::all() } else { gpu.info.features.clone() };
    let how = if args.all_features { "unspecialised, --all-features" } else { "specialised to the scene" };
    let name = integrator.to_possible_value().map(|v| v.get_name().to_string()).unwrap_or_default();
    let walk = super::walk_name(gpu.bvh.layout, arrays.as_ref().map_or(0, |a| a.instances.len()));
    eprintln!("shader variant: {name} {walk} ({how}): {}", features.variant_name());
    eprint!("{}", features.report());
    // The list's walls (accel::walls): shadow rays skip them.
    eprintln!("triangle list: {} triangles, {} of them walls that shadow rays skip", gpu.bvh.list_count, gpu.list_walls.count_ones());
    if integrator == IntegratorKind::Path {
        // What the path tracer samples beyond lights and BSDFs (prepare::mirrors, prepare::casters).
        eprintln!(
            "planar mirror planes light is sampled through: {}; caustic casters diffuse bounces are aimed at: {}",
            gpu.mirror_plane_count, gpu.caster_count
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser as _;

    /// The plan `vkrt render ARGS...` resolves to (no device, no scene file read).
    fn plan(args: &[&str]) -> Result<RenderPlan> {
        let cli = crate::cli::Cli::try_parse_from(["vkrt", "render"].iter().chain(args)).map_err(|e| anyhow::anyhow!("{e}"))?;
        let crate::cli::Command::Render(render) = cli.command else { bail!("not a render command") };
        RenderPlan::resolve(&render, &Say { quiet: true })
    }

    #[test]
    fn a_plan_takes_the_defaults_where_no_flag_says_otherwise() {
        let p = plan(&["room.obj", "-o", "room.png"]).unwrap();
        assert_eq!(p.integrator, IntegratorKind::Whitted);
        assert_eq!((p.width, p.height, p.seed), (DEFAULT_SIZE, DEFAULT_SIZE, 0));
        assert_eq!((p.builder, p.layout), (BuilderKind::default(), LayoutKind::default()));
        assert_eq!((p.scene_path, p.output), (PathBuf::from("room.obj"), PathBuf::from("room.png")));
        assert!(p.shard.is_none() && p.resumed.is_none());
    }

    #[test]
    fn a_plan_takes_each_flag_given() {
        let p = plan(&["room.obj", "-o", "x.exr", "--width", "64", "--height", "48", "--seed", "7", "--layout", "wide", "--builder", "sah"]).unwrap();
        assert_eq!((p.width, p.height, p.seed, p.layout, p.builder), (64, 48, 7, LayoutKind::Wide, BuilderKind::Sah));
    }

    #[test]
    fn a_path_tracer_flag_selects_the_path_tracer_and_whitted_refuses_it() {
        assert_eq!(plan(&["room.obj", "-o", "x.png", "--time", "5"]).unwrap().integrator, IntegratorKind::Path);
        let err = plan(&["room.obj", "-o", "x.png", "--time", "5", "--integrator", "whitted"]).err().unwrap().to_string();
        assert!(err.contains("--time needs --integrator path"), "{err}");
    }

    #[test]
    fn a_plan_without_scene_or_output_names_what_is_missing() {
        let err = plan(&["-o", "x.png"]).err().unwrap().to_string();
        assert!(err.contains("no scene file given"), "{err}");
        let err = plan(&["room.obj"]).err().unwrap().to_string();
        assert!(err.contains("no output given"), "{err}");
        let err = plan(&["--resume", "/nonexistent/run.ckpt"]).err().unwrap();
        assert!(format!("{err:#}").contains("/nonexistent/run.ckpt"), "{err:#}");
    }

    #[test]
    fn a_shard_plan_writes_its_sums_to_its_own_checkpoint() {
        let p = plan(&["room.obj", "--integrator", "path", "--spp", "64", "--shard", "1/4", "-o", "part-{shard}.ckpt"]).unwrap();
        let shard = p.shard.unwrap();
        assert_eq!((shard.index, shard.count, shard.total_spp), (1, 4, 64));
        assert_eq!(p.output, PathBuf::from("part-1.ckpt"));
        let err = plan(&["room.obj", "--integrator", "path", "--spp", "64", "--shard", "1/4", "-o", "x.png"]).err().unwrap().to_string();
        assert!(err.contains("a shard writes its sums"), "{err}");
    }
}
