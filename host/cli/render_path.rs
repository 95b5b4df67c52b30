//! The path tracer's half of `vkrt render`: its progressive flags, the run's identity for
//! checkpoints, what a resumed run takes from its checkpoint, and the hooks that save
//! checkpoints, rewrite the image while it converges, show progress and catch Ctrl-C.

use super::args::{at_least_one, positive};
use super::interrupt::interrupt_flag;
use super::progress::{Progress, Status};
use super::shard::ShardArgs;
use crate::gpu::Context;
use crate::gpu_abi::constants::{NEE_OFF, NEE_ON, NEE_WITH_CONNECTIONS, PATH_DEPTH_UNBOUNDED};
use crate::integrator::path::checkpoint::{hash_inputs, Checkpoint, Identity, InputHash, ResumeDefaults, RunSettings};
use crate::integrator::path::coherence::{DEFAULT_COHERENCE, DEFAULT_COHERENCE_BLOCK};
use crate::integrator::path::connections::Connections;
use crate::integrator::path::shard::{Shard, ShardSet};
use crate::integrator::path::{self, Accumulation, Hooks, PathProgress, PathSettings, SamplerKind, Stop};
use crate::integrator::{Image, RenderSettings, RenderStats};
use crate::prepare::GpuScene;
use crate::scene::SceneSummary;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

/// Samples per pixel when a path-traced render names no stop condition.
pub const DEFAULT_PATH_SPP: u64 = 16;
/// Defaults of the path tracer's flags.
pub const DEFAULT_SAMPLE_RATE: u32 = 4;
pub const DEFAULT_CHECKPOINT_INTERVAL_S: f64 = 10.0;
pub const DEFAULT_SAMPLES_PER_BATCH: u32 = path::batch::FIRST_BATCH_SPP;

/// Flags of `vkrt render` that only the path tracer reads. Giving one selects the path tracer
/// (an error with an explicit `--integrator whitted`).
#[derive(Debug, Args, Default)]
pub struct PathArgs {
    /// Path tracer: sample generator [default: zsobol].
    #[arg(hide = true, long, value_enum)]
    pub sampler: Option<SamplerKind>,
    /// Path tracer, stratified sampler: strata per pixel side (N^2 strata) [default: 4].
    #[arg(hide = true, long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "N")]
    pub sample_rate: Option<u32>,
    /// Path tracer: stop after this many seconds (with --spp or --target-relmse, the first to hold).
    #[arg(help_heading = "Progressive runs", long, value_parser = positive, allow_negative_numbers = true, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Path tracer: stop once the relMSE estimated from two half-images is at most this.
    #[arg(help_heading = "Progressive runs", long, value_parser = positive, allow_negative_numbers = true, value_name = "RELMSE")]
    pub target_relmse: Option<f64>,
    /// Path tracer: write the running sums, sample count and settings here every
    /// --checkpoint-interval seconds and at the end, atomically. With --resume, default: the
    /// resumed checkpoint itself.
    #[arg(help_heading = "Progressive runs", long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Path tracer: seconds between checkpoints [default: 10].
    #[arg(hide = true, long, value_parser = positive, allow_negative_numbers = true, value_name = "SECONDS")]
    pub checkpoint_interval: Option<f64>,
    /// Path tracer: continue the run saved in this checkpoint, with the scene, size, camera and
    /// sampling settings it records (flags that would change the image are an error); --spp,
    /// --time and --target-relmse given here replace its stop rules, -o its output.
    #[arg(help_heading = "Progressive runs", long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Path tracer: samples per pixel per submission (one submission per 128 x 128 tile on a
    /// CPU device). Default: 4 at first, then grown while a submission stays under 0.25 s and
    /// a batch of them under 1 s, up to 64: less per-batch overhead on small images, the same
    /// image.
    #[arg(hide = true, long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "N")]
    pub samples_per_batch: Option<u32>,
    /// Path tracer: BSDF sampling only, no light sampling (for checking the estimators).
    #[arg(hide = true, long)]
    pub no_nee: bool,
    /// Path tracer: light-vertex connections [default: auto]. Each sample also follows light
    /// from an emissive triangle to the first surface it hits and joins every vertex of the
    /// camera path to that point (bidirectional path tracing's s = 2 paths, weighted by MIS):
    /// about half the error per sample where diffuse interreflection lights the scene, for
    /// 1.3-1.8x the time. auto: on in scenes lit by emissive triangles whose materials are all
    /// Lambertian (there it won: 0.75x the relMSE x seconds), off with mirrors, glass or glossy
    /// materials (there it lost: 1.2-1.6x).
    #[arg(hide = true, long, value_enum, value_name = "MODE")]
    pub connections: Option<path::connections::Connections>,
    /// Path tracer: pixels that draw the same sample numbers (coherent path tracing)
    /// [default: 8]. 8 makes lavapipe's SIMD lanes trace alike: about
    /// 0.55x the time (with the default block and sampler) at the same expected error per
    /// pixel. 1: every pixel its own numbers.
    #[arg(hide = true, long, value_parser = at_least_one, allow_negative_numbers = true, value_name = "N")]
    pub coherence: Option<u32>,
    /// Path tracer: the side of the square over which each --coherence group's pixels are
    /// spread [default: 16] (in Z order with --sampler zsobol, at random with the others), so
    /// that their correlated errors lie apart and the noise shows no structure; a power of two
    /// from 8 to 256. 0: the group is N pixels in a row (less time, but the noise shows as
    /// short horizontal streaks).
    #[arg(hide = true, long, value_name = "B")]
    pub coherence_block: Option<u32>,
    /// Path tracer: adaptive sampling. After a uniform pilot of 8 spp, each block of pixels (a
    /// --coherence-block square, or with groups in a row 8 pixels or whole groups) takes
    /// samples in proportion to the noise the pilot showed around it (not in it, which keeps
    /// the image unbiased); --spp is then the mean over the pixels. Lower relMSE at equal time
    /// where the noise is uneven (0.73x on a mirror box, 0.95x on others), FLIP 1.5-4.5 % higher.
    #[arg(hide = true, long)]
    pub adaptive: bool,
    /// Path tracer: rewrite the output image (atomically) every SECONDS while rendering, so an
    /// image viewer that reloads shows it converge.
    #[arg(help_heading = "Progressive runs", long, value_parser = positive, allow_negative_numbers = true, value_name = "SECONDS")]
    pub preview_every: Option<f64>,
    #[command(flatten)]
    pub shard: ShardArgs,
}

impl PathArgs {
    /// The path-tracer flags given on the command line, by name.
    pub fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        let mut add = |on: bool, name| {
            if on {
                v.push(name)
            }
        };
        add(self.sampler.is_some(), "--sampler");
        add(self.sample_rate.is_some(), "--sample-rate");
        add(self.time.is_some(), "--time");
        add(self.target_relmse.is_some(), "--target-relmse");
        add(self.checkpoint.is_some(), "--checkpoint");
        add(self.checkpoint_interval.is_some(), "--checkpoint-interval");
        add(self.resume.is_some(), "--resume");
        add(self.samples_per_batch.is_some(), "--samples-per-batch");
        add(self.no_nee, "--no-nee");
        add(self.connections.is_some(), "--connections");
        add(self.coherence.is_some(), "--coherence");
        add(self.coherence_block.is_some(), "--coherence-block");
        add(self.adaptive, "--adaptive");
        add(self.preview_every.is_some(), "--preview-every");
        v.extend(self.shard.given());
        v
    }
}

/// A path-traced render, resolved: the command line's values, or a resumed checkpoint's.
pub struct PathRun<'a> {
    /// The scene as loaded: its input files make the run's identity.
    pub scene: &'a SceneSummary,
    /// Those files' content hashes where they were just checked (a prepared-scene cache hit
    /// re-hashes every input): the identity reuses them instead of reading every file again.
    pub input_hashes: Option<Vec<(PathBuf, u64)>>,
    /// The scene file's absolute path (what a checkpoint records).
    pub scene_path: String,
    /// The `--sky` override, as given ("" for the scene's own sky).
    pub sky: String,
    /// The camera used: eye, target, up, vertical field of view.
    pub camera: [f32; crate::integrator::path::checkpoint::CAMERA_NUMBERS],
    pub settings: PathSettings,
    pub seed: u32,
    /// The output image's absolute path, and the builder and layout names (for a checkpoint).
    pub output: String,
    pub builder: String,
    pub layout: String,
    /// Where to save checkpoints, and how often.
    pub checkpoint: Option<PathBuf>,
    pub checkpoint_interval: f64,
    /// The checkpoint to continue.
    pub resume: Option<Checkpoint>,
    pub resume_path: Option<PathBuf>,
    /// The part of a sharded run this is (its sums go to `checkpoint`), if it is one.
    pub shard: Option<Shard>,
    pub preview_every: Option<f64>,
}

/// The settings a path-traced run uses: each flag, or when resuming the checkpoint's value,
/// or the default. Differences from the checkpoint are caught by its identity check.
pub fn path_settings(args: &PathArgs, image: RenderSettings, max_depth: Option<u32>, resumed: Option<&RunSettings>, stop: Stop) -> PathSettings {
    let sampler = args.sampler.or_else(|| resumed.and_then(|r| SamplerKind::from_gpu_value(r.sampler))).unwrap_or(SamplerKind::Zsobol);
    let stored_depth = resumed.map(|r| if r.max_depth == PATH_DEPTH_UNBOUNDED { None } else { Some(r.max_depth) });
    let (coherence, coherence_block) = coherence(args, resumed);
    PathSettings {
        image,
        max_depth: max_depth.or(stored_depth.flatten()),
        sampler,
        sample_rate: args.sample_rate.or(resumed.map(|r| r.sample_rate)).unwrap_or(DEFAULT_SAMPLE_RATE),
        // A resumed run keeps its sets, whatever its new sample count: the same numbers as one run.
        zsobol_log2: resumed.map_or_else(|| path::zsobol_log2(stop.spp), |r| r.zsobol_log2),
        nee: if args.no_nee { false } else { resumed.map_or(true, |r| r.nee != NEE_OFF) },
        // A resumed run keeps the checkpoint's estimator: connections on if it recorded them.
        connections: args
            .connections
            .or_else(|| resumed.map(|r| if r.nee == NEE_WITH_CONNECTIONS { Connections::On } else { Connections::Off }))
            .unwrap_or_default(),
        coherence,
        coherence_block,
        adaptive: args.adaptive,
        grow_batches: args.samples_per_batch.is_none(),
        mirror_sampling: true,
        caster_guiding: true,
        stop,
        first_sample: 0,
    }
}

/// `(coherence, coherence_block)`: the flags, else a resumed run's, else the defaults.
fn coherence(args: &PathArgs, resumed: Option<&RunSettings>) -> (u32, u32) {
    let c = args.coherence.or(resumed.map(|r| r.coherence)).unwrap_or(DEFAULT_COHERENCE);
    let block = args.coherence_block.or(resumed.map(|r| r.coherence_block)).unwrap_or(DEFAULT_COHERENCE_BLOCK);
    (c, block)
}

/// Fails, before any work, on a --coherence / --coherence-block pair the path tracer refuses
/// (the render's own check, `path::coherence::check`, run early).
pub fn check_coherence(args: &PathArgs, resumed: Option<&RunSettings>) -> Result<()> {
    let (c, block) = coherence(args, resumed);
    path::coherence::check(c, block)
}

/// The stop rules: those given, else a resumed run's, else `DEFAULT_PATH_SPP`.
pub fn stop_rules(spp: Option<u32>, args: &PathArgs, resumed: Option<&ResumeDefaults>) -> Stop {
    let given = Stop { spp: spp.map(u64::from), seconds: args.time, target_relmse: args.target_relmse };
    if given != Stop::default() {
        return given;
    }
    if let Some(r) = resumed {
        let stored = Stop { spp: r.spp, seconds: r.seconds, target_relmse: r.target_relmse };
        if stored != Stop::default() {
            return stored;
        }
    }
    Stop { spp: Some(DEFAULT_PATH_SPP), ..Stop::default() }
}

/// This run's settings as a checkpoint records them; `connects`: whether its light-vertex
/// connections are on (`Connections::resolve` for its scene).
pub fn run_settings(run: &PathRun, identity: Identity, connects: bool) -> RunSettings {
    let s = &run.settings;
    RunSettings {
        scene_path: run.scene_path.clone(),
        identity,
        width: s.image.width,
        height: s.image.height,
        seeds: vec![run.seed],
        integrator: "path".into(),
        sampler: s.sampler.gpu_value(),
        sample_rate: s.sample_rate,
        zsobol_log2: s.zsobol_log2,
        max_depth: s.max_depth.unwrap_or(PATH_DEPTH_UNBOUNDED),
        nee: match (s.nee, connects) {
            (false, _) => NEE_OFF,
            (true, false) => NEE_ON,
            (true, true) => NEE_WITH_CONNECTIONS,
        },
        coherence: s.coherence,
        coherence_block: s.coherence_block,
        shards: run.shard.map(ShardSet::of),
        resume: ResumeDefaults {
            output: run.output.clone(),
            builder: run.builder.clone(),
            layout: run.layout.clone(),
            spp: s.stop.spp,
            seconds: s.stop.seconds,
            target_relmse: s.stop.target_relmse,
        },
    }
}

/// The sums of the resumed checkpoint, if they are this run's (same render, same seed).
pub fn resumed_sums(c: &Checkpoint, path: &Path, run: &PathRun, ours: &RunSettings, say: &dyn Fn(&str)) -> Result<Accumulation> {
    let ours = match c.settings.identity {
        // An older vkrt hashed only the scene file: check that much, and say so.
        Identity::SceneFile { .. } => {
            say(&format!(
                "warning: {} was written by an older vkrt, which recorded only the scene file's hash: its meshes, \
                 textures, sky and camera cannot be checked",
                path.display()
            ));
            let fnv = crate::output::checkpoint::fnv1a_file(Path::new(&run.scene_path))?;
            RunSettings { identity: Identity::SceneFile { fnv }, ..ours.clone() }
        }
        Identity::Inputs { .. } => ours.clone(),
    };
    c.settings.check_same_render(&ours, ("the checkpoint", "this run")).with_context(|| {
        format!(
            "cannot resume {}: a resumed run renders the checkpoint's image, so leave out the flags that change it \
             (or start a new run)",
            path.display()
        )
    })?;
    if c.settings.seeds != ours.seeds {
        bail!("cannot resume {}: it holds seeds {:?}, this run uses seed {}", path.display(), c.settings.seeds, run.seed);
    }
    if c.settings.shards != ours.shards {
        let show =
            |s: &Option<ShardSet>| s.as_ref().map_or("a whole run".to_string(), |s| format!("shards {:?} of {} ({} spp)", s.indices, s.count, s.total_spp));
        bail!("cannot resume {}: it holds {}, this run is {}", path.display(), show(&c.settings.shards), show(&ours.shards));
    }
    let to = run.settings.stop.spp.map_or(String::new(), |n| format!(", going on to {n}"));
    say(&format!("resuming {}: {} spp done{to}", path.display(), c.accum.samples));
    Ok(c.accum.clone())
}

/// What a path-traced render returns to the render command, which writes the image.
pub struct PathOutcome {
    pub image: Image,
    pub stats: RenderStats,
    /// Samples per pixel taken (the mean over the pixels for an adaptive run).
    pub samples: u64,
    /// The last error estimate.
    pub relmse: Option<f64>,
}

/// Renders with the path tracer: checkpoints as asked, `write_preview` every
/// `--preview-every` seconds, progress on `progress`.
pub fn render(
    ctx: &Context,
    gpu: &GpuScene,
    run: &PathRun,
    progress: &mut Progress,
    write_preview: &mut dyn FnMut(&Image) -> Result<()>,
    say: &dyn Fn(&str),
) -> Result<PathOutcome> {
    // Hashing every input costs a read of each file: only runs that save or resume need it.
    let ours = if run.checkpoint.is_some() || run.resume.is_some() {
        let inputs = match &run.input_hashes {
            Some(known) => known.iter().map(|(p, hash)| InputHash { path: p.display().to_string(), hash: *hash }).collect(),
            None => hash_inputs(&run.scene.stats.inputs)?,
        };
        let identity = Identity::Inputs { inputs, sky: run.sky.clone(), camera: run.camera };
        Some(run_settings(run, identity, path::connections::connects(&run.settings, gpu)))
    } else {
        None
    };
    let resume = match (&run.resume, &run.resume_path, &ours) {
        (Some(c), Some(p), Some(ours)) => Some(resumed_sums(c, p, run, ours, say)?),
        _ => None,
    };
    let mut on_progress = |p: &PathProgress| {
        progress.update(&Status {
            fraction: p.fraction,
            start_fraction: p.start_fraction,
            count: Some((p.samples, p.target_spp, "spp")),
            rays_per_second: p.rays_per_second,
            relmse: p.relmse,
        });
    };
    let mut save = |acc: &Accumulation| -> Result<()> {
        match (&run.checkpoint, &ours) {
            (Some(p), Some(ours)) => Checkpoint { settings: ours.clone(), accum: acc.clone() }.write(p),
            _ => Ok(()),
        }
    };
    let mut snapshot = |acc: &Accumulation| write_preview(&acc.image());
    let mut hooks = Hooks {
        progress: Some(&mut on_progress),
        checkpoint: if run.checkpoint.is_some() { Some(&mut save) } else { None },
        checkpoint_interval_s: run.checkpoint_interval,
        snapshot: if run.preview_every.is_some() { Some(&mut snapshot) } else { None },
        snapshot_interval_s: run.preview_every.unwrap_or(f64::INFINITY),
        interrupt: interrupt_flag(),
    };
    let (acc, stats) = path::render(ctx, gpu, &run.settings, resume, &mut hooks)?;
    progress.finish();
    let relmse = acc.estimate_relmse();
    Ok(PathOutcome { image: acc.image(), stats, samples: acc.samples, relmse })
}
