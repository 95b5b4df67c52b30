//! The progressive render loop: short batches of samples, each dispatched tile by tile, until a
//! stop rule holds ([`super::stop`]); between batches the error estimate, checkpoints, progress
//! and the interrupt flag ([`super::progress`]). Which samples a batch takes is
//! [`super::schedule`]'s; the GPU buffers and pipeline are [`PathGpu`]'s.

use super::accumulation::{even_indices, Accumulation};
use super::adaptive::{block_rates, BlockGrid, PILOT_SPP};
use super::batch::BatchSizer;
use super::params::{path_params, PATH_BINDINGS};
use super::progress::{Hooks, PathProgress};
use super::schedule::{check_block_batch, uniform_batch, AdaptiveState};
use super::stop::RunState;
use super::PathSettings;
use crate::gpu::{Buffer, Context, MemoryLocation};
use crate::gpu_abi::constants::*;
use crate::gpu_abi::GpuPush;
use crate::integrator::frame::{frame_for, INTEGRATOR_BINDINGS};
use crate::integrator::tiles::{bind_all, dispatch_samples};
use crate::integrator::RenderStats;
use crate::pipeline::shaders::{PathShader, Tracing};
use crate::pipeline::{BindingKind, ComputePipeline};
use crate::prepare::GpuScene;
use anyhow::{bail, Context as _, Result};
use ash::vk;
use std::time::Instant;

/// The least seconds between read-backs that refresh the error estimate.
const ESTIMATE_INTERVAL_S: f64 = 1.0;
/// A read-back takes at most this share of the run: big images refresh the estimate less often.
const ESTIMATE_TIME_SHARE: f64 = 0.05;

/// The sum planes' bindings: even-indexed samples' r, g, b, then odd-indexed ones'.
const SUM_PLANES: [u32; 6] = [BINDING_SUM_EVEN_R, BINDING_SUM_EVEN_G, BINDING_SUM_EVEN_B, BINDING_SUM_ODD_R, BINDING_SUM_ODD_G, BINDING_SUM_ODD_B];

/// A path-traced render's GPU side: its uniforms, sum planes and pipeline.
struct PathGpu<'a> {
    /// One fixed-point u64 per pixel each, in `SUM_PLANES` order.
    planes: Vec<Buffer<'a>>,
    /// (samples taken, dropped) per pixel.
    counts: Buffer<'a>,
    /// Each block's (first sample, count) for the next batch of an adaptive run.
    blocks: Buffer<'a>,
    /// Rays traced per pixel, for rays/s.
    rays: Buffer<'a>,
    /// The mirror probe's value per pixel (BINDING_MIRROR_PROBE; 0 until the probe pass runs).
    _mirror_probe: Buffer<'a>,
    /// The pipeline is the mirror-probe variant: run its probe pass before sampling.
    probes_mirrors: bool,
    /// Light-vertex connections on (`super::connections`).
    connects: bool,
    pipeline: ComputePipeline<'a>,
    shader: Tracing,
    // Bound to the pipeline; kept alive with it.
    _frame: Buffer<'a>,
    _params: Buffer<'a>,
}

impl<'a> PathGpu<'a> {
    /// Uploads the settings and the sums of `acc` and builds the pipeline for the scene's layout
    /// and features.
    fn new(ctx: &'a Context, scene: &GpuScene, settings: &PathSettings, acc: &Accumulation, block_count: usize) -> Result<Self> {
        let img = &settings.image;
        let params = path_params(scene, settings)?;
        let frame = frame_for(scene, img)?;
        let uniform = vk::BufferUsageFlags::UNIFORM_BUFFER;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let frame_buf = Buffer::with_data(ctx, "frame", std::slice::from_ref(&frame), uniform)?;
        let params_buf = Buffer::with_data(ctx, "path params", std::slice::from_ref(&params), uniform)?;
        let pixels = img.width as u64 * img.height as u64;
        let names = ["sums (even, r)", "sums (even, g)", "sums (even, b)", "sums (odd, r)", "sums (odd, g)", "sums (odd, b)"];
        let mut planes = Vec::with_capacity(SUM_PLANES.len());
        for (k, name) in names.iter().enumerate() {
            let plane = Buffer::new(ctx, name, pixels * 8, storage, MemoryLocation::Device)?;
            let half = if k < 3 { &acc.even } else { &acc.odd };
            plane.write_with(pixels as usize, |dst: &mut [u64]| {
                for (d, s) in dst.iter_mut().zip(half) {
                    *d = s[k % 3];
                }
            })?;
            planes.push(plane);
        }
        let counts = Buffer::new(ctx, "sample counts", pixels * 8, storage, MemoryLocation::Device)?;
        counts.write(bytemuck::cast_slice(&acc.counts))?;
        let blocks = Buffer::new(ctx, "block samples", block_count as u64 * 8, storage, MemoryLocation::Device)?;
        let rays = Buffer::new(ctx, "ray counts", pixels * 4, storage, MemoryLocation::Device)?;
        rays.clear()?;
        let bindings: Vec<(u32, BindingKind)> = INTEGRATOR_BINDINGS.iter().chain(PATH_BINDINGS).chain(scene.bvh.instance_bindings()).copied().collect();
        let features = img.features(&scene.info);
        let probes_mirrors = settings.mirror_sampling && features.has(crate::prepare::features::MIRROR);
        // A value per pixel for the mirror variant; the plain shader never reads it, but the
        // binding must hold a buffer.
        let probe_bytes = if probes_mirrors { pixels * 4 } else { 4 };
        let mirror_probe = Buffer::new(ctx, "mirror probe", probe_bytes, storage, MemoryLocation::Device)?;
        mirror_probe.clear()?;
        // Scenes with caustic casters (prepare::casters) run the variant that aims at them.
        let casters = settings.aims_at_casters(scene);
        let connects = super::connections::connects(settings, scene);
        // A lean build without the connections' code gives way to the full one where the scene
        // connects (a mirror scene with `--connections on`); casters builds never connect.
        let mut path = PathShader { mirrors: probes_mirrors, casters, lean: features.lean() };
        if connects && !path.can_connect() {
            path.lean = false;
        }
        debug_assert!(!connects || path.can_connect(), "{path:?} cannot connect");
        let shader = Tracing::Path(path);
        let pipeline = ComputePipeline::specialized(
            ctx,
            shader.name(),
            scene.bvh.spirv(shader)?,
            &bindings,
            std::mem::size_of::<GpuPush>() as u32,
            &[features.spec_constants(), scene.trace_spec_constants(), vec![(SPEC_LIGHT_CONNECTIONS, connects as u32)]].concat(),
        )?;
        scene.bind(&pipeline)?;
        scene.bind_path_arrays(&pipeline)?;
        bind_all(
            &pipeline,
            &[
                (BINDING_FRAME, &frame_buf),
                (BINDING_PATH_PARAMS, &params_buf),
                (BINDING_SAMPLE_COUNTS, &counts),
                (BINDING_BLOCK_SAMPLES, &blocks),
                (BINDING_RAY_COUNTS, &rays),
                (BINDING_MIRROR_PROBE, &mirror_probe),
            ],
        )?;
        for (binding, plane) in SUM_PLANES.iter().zip(&planes) {
            pipeline.bind(*binding, plane)?;
        }
        Ok(Self {
            planes,
            counts,
            blocks,
            rays,
            _mirror_probe: mirror_probe,
            probes_mirrors,
            connects,
            pipeline,
            shader,
            _frame: frame_buf,
            _params: params_buf,
        })
    }

    /// The sums as they stand, read into `acc` (its kind, uniform or per-pixel counts, and its
    /// adaptive rates kept), in its own arrays: a fresh Accumulation per read was 56 MB of new
    /// arrays at 1024², page faults and all, for every estimate. `samples`: per pixel, or the
    /// mean for per-pixel counts.
    fn read_into(&self, acc: &mut Accumulation, samples: u64, first_sample: u64) -> Result<()> {
        let pixels = acc.width as usize * acc.height as usize;
        for (k, plane) in self.planes.iter().enumerate() {
            let half = if k < 3 { &mut acc.even } else { &mut acc.odd };
            plane
                .read_with(pixels, |src: &[u64]| {
                    for (d, s) in half.iter_mut().zip(src) {
                        d[k % 3] = *s;
                    }
                })
                .context("reading the sums")?;
        }
        let counts = &mut acc.counts;
        self.counts.read_with(pixels, |src: &[[u32; 2]]| counts.copy_from_slice(src)).context("reading the sample counts")?;
        acc.samples = samples;
        acc.even_samples = if acc.per_pixel { samples / 2 } else { even_indices(first_sample, samples) };
        acc.check_range()
    }

    /// Rays traced so far in this run, over all pixels.
    fn rays_traced(&self, pixels: usize) -> Result<u64> {
        let mut total = 0u64;
        self.rays.read_with(pixels, |counts: &[u32]| total = counts.iter().map(|&c| u64::from(c)).sum())?;
        Ok(total)
    }
}

/// The sums a run starts from: `resume`'s, checked against `settings`, or empty ones.
fn starting_sums(settings: &PathSettings, grid: BlockGrid, resume: Option<Accumulation>) -> Result<Accumulation> {
    let img = &settings.image;
    let acc = resume.unwrap_or_else(|| {
        let mut a = Accumulation::new(img.width, img.height);
        a.per_pixel = settings.adaptive;
        a
    });
    if (acc.width, acc.height) != (img.width, img.height) {
        bail!("resumed sums are {}x{}, the render is {}x{}", acc.width, acc.height, img.width, img.height);
    }
    if acc.per_pixel != settings.adaptive {
        bail!("the resumed run {} adaptive and this one {}", if acc.per_pixel { "is" } else { "is not" }, if settings.adaptive { "is" } else { "is not" });
    }
    if !acc.rates.is_empty() && (acc.rates.len() != grid.count() || acc.rates.iter().any(|&r| r == 0 || r % 2 != 0)) {
        bail!("the resumed run's adaptive rates ({} of them) are not even rates for this render's {} blocks", acc.rates.len(), grid.count());
    }
    Ok(acc)
}

/// Renders `scene` progressively, continuing `resume` if given (its sums and count; samples go
/// on from its count), until `settings.stop` holds.
pub fn render(
    ctx: &Context,
    scene: &GpuScene,
    settings: &PathSettings,
    resume: Option<Accumulation>,
    hooks: &mut Hooks,
) -> Result<(Accumulation, RenderStats)> {
    let img = &settings.image;
    if img.width == 0 || img.height == 0 {
        bail!("image size {}x{} is empty", img.width, img.height);
    }
    let stop = settings.stop;
    if stop.spp.is_none() && stop.seconds.is_none() && stop.target_relmse.is_none() {
        bail!("no stop condition: give a sample count, a time or a target error");
    }
    if settings.adaptive && stop.spp.is_some_and(|n| n < PILOT_SPP as u64) {
        bail!("adaptive sampling needs at least {PILOT_SPP} spp (its uniform pilot); got {}", stop.spp.unwrap_or(0));
    }
    super::coherence::check(settings.coherence, settings.coherence_block)?;
    let align = super::coherence::dispatch_alignment(settings.coherence, settings.coherence_block);
    let start = Instant::now();
    let grid = BlockGrid::new(img.width, img.height, settings.coherence, settings.coherence_block);
    let mut acc = starting_sums(settings, grid, resume)?;
    let mut adaptive = settings.adaptive.then(|| AdaptiveState::new(&acc, grid));
    // One unused block entry for a uniform run.
    let gpu = PathGpu::new(ctx, scene, settings, &acc, if settings.adaptive { grid.count() } else { 1 })?;
    let mut stats = RenderStats {
        pipeline_seconds: gpu.pipeline.creation_seconds(),
        shader_origin: gpu.pipeline.origin().to_string(),
        light_connections: gpu.connects,
        shader: gpu.shader.name(),
        ..RenderStats::default()
    };
    let pixels = img.width as u64 * img.height as u64;
    // Adaptive runs use the size for their pilot only: then each block's rate decides.
    let mut sizer =
        if settings.grow_batches && !settings.adaptive { BatchSizer::growing(img.samples_per_batch) } else { BatchSizer::fixed(img.samples_per_batch) };
    let empty = scene.bvh.triangle_count == 0;
    if gpu.probes_mirrors && !empty {
        // Before any sample: each run (resumed or a shard too) computes the same values.
        let probe = GpuPush { probe: 1, ..scene.bvh.push };
        dispatch_samples(ctx, &probe, &gpu.pipeline, "mirror probe", img, align, 0, 0, 0, &mut || stats.submissions += 1)?;
    }
    let mut run = RunState { samples: acc.samples, first_sample: acc.samples, ..RunState::default() };
    let start_fraction = stop.fraction(&run);
    let (mut last_estimate, mut last_checkpoint, mut last_snapshot) = (start, start, start);
    // How long a read-back for the estimate took, and the rays counted at the last one.
    let (mut read_s, mut rays_per_second) = (0.0f64, None);
    loop {
        run.seconds = start.elapsed().as_secs_f64();
        if stop.holds(&run) || (empty && run.samples > run.first_sample) {
            break;
        }
        if hooks.interrupt.is_some_and(|i| i.load(std::sync::atomic::Ordering::SeqCst)) {
            stats.interrupted = true;
            break;
        }
        let t_batch = Instant::now();
        let (submissions_before, samples_before) = (stats.submissions, run.samples);
        let batch = sizer.spp();
        let mut dispatch = |base: u32, count: u32| -> Result<()> {
            if empty {
                return Ok(());
            }
            dispatch_samples(ctx, &scene.bvh.push, &gpu.pipeline, "path tile", img, align, base, count, 0, &mut || stats.submissions += 1)
        };
        if let Some(state) = adaptive.as_mut() {
            if state.pilot_done() && acc.rates.is_empty() {
                gpu.read_into(&mut acc, run.samples, settings.first_sample)?;
                acc.rates = block_rates(&acc, grid);
            }
            let next = state.next_batch(&acc.rates, batch, stop.spp.map(|n| n * pixels));
            if next.iter().all(|b| b[1] == 0) {
                break;
            }
            check_block_batch(&next)?;
            gpu.blocks.write(bytemuck::cast_slice(&next))?;
            // Each block's samples come from the block buffer, not the push constants.
            dispatch(0, 0)?;
            state.advance(&next);
            run.samples = state.total() / pixels;
        } else {
            let count = uniform_batch(settings.first_sample + run.samples, batch, &stop, run.samples, stop.next_estimate_samples(&run))?;
            dispatch((settings.first_sample + run.samples) as u32, count as u32)?;
            run.samples += count;
        }
        // The batch's own time, not the time to queue it: with submissions in flight the queueing
        // ends before the last tiles run, and growing batches or a time limit would then
        // be planned from a time that is too short (--time 1 ran 1.36 s). One wait per batch
        // leaves the device idle only while the next batch's first tile is recorded.
        ctx.drain().context("waiting for the batch")?;
        let batch_s = t_batch.elapsed().as_secs_f64();
        let taken = run.samples - samples_before;
        let seconds_left = stop.seconds.map(|t| t - start.elapsed().as_secs_f64());
        sizer.observe(taken, u64::from(stats.submissions - submissions_before), batch_s, seconds_left);
        // The next batch's time, from this one's per sample (the stop rule's time limit).
        run.next_batch_s = if taken > 0 { batch_s * sizer.spp() as f64 / taken as f64 } else { batch_s };
        let now = Instant::now();
        let want_estimate = stop.target_relmse.is_some() || hooks.checkpoint.is_some() || hooks.progress.is_some();
        let since = now.duration_since(last_estimate).as_secs_f64();
        // Every ESTIMATE_INTERVAL_S, those read-backs taking at most ESTIMATE_TIME_SHARE of the
        // run; and where the target error is expected (`estimate_due`), whatever they cost:
        // they are few (`next_estimate_samples`), and one read-back is cheaper than rendering
        // on past the target. With the share rule alone an H200 rendered a 1024² target of
        // 1e-3 for 2.9 s (1720 spp), where 256 spp already gave an estimate of 7.0e-4.
        let by_time = since >= ESTIMATE_INTERVAL_S && since >= read_s / ESTIMATE_TIME_SHARE;
        if want_estimate && (by_time || stop.estimate_due(&run)) {
            gpu.read_into(&mut acc, run.samples, settings.first_sample)?;
            run.relmse = acc.estimate_relmse();
            run.relmse_samples = run.samples;
            if hooks.progress.is_some() {
                let rays = gpu.rays_traced(pixels as usize)?;
                rays_per_second = Some(rays as f64 / start.elapsed().as_secs_f64().max(1e-9));
            }
            last_estimate = now;
            read_s = now.elapsed().as_secs_f64();
            stats.estimates += 1;
            stats.estimate_seconds += read_s;
        }
        if let Some(hook) = hooks.snapshot.as_mut() {
            if now.duration_since(last_snapshot).as_secs_f64() >= hooks.snapshot_interval_s {
                gpu.read_into(&mut acc, run.samples, settings.first_sample)?;
                hook(&acc)?;
                last_snapshot = now;
            }
        }
        if let Some(hook) = hooks.checkpoint.as_mut() {
            if now.duration_since(last_checkpoint).as_secs_f64() >= hooks.checkpoint_interval_s {
                gpu.read_into(&mut acc, run.samples, settings.first_sample)?;
                hook(&acc)?;
                last_checkpoint = now;
            }
        }
        if let Some(progress) = hooks.progress.as_mut() {
            let seconds = start.elapsed().as_secs_f64();
            let at = RunState { seconds, ..run };
            progress(&PathProgress {
                samples: run.samples,
                target_spp: stop.spp,
                seconds,
                samples_per_second: (run.samples - run.first_sample) as f64 * pixels as f64 / seconds.max(1e-9),
                rays_per_second,
                relmse: run.relmse,
                fraction: stop.fraction(&at),
                start_fraction,
            });
        }
    }
    gpu.read_into(&mut acc, run.samples, settings.first_sample)?;
    if let Some(hook) = hooks.checkpoint.as_mut() {
        hook(&acc)?;
    }
    stats.nonfinite_samples = acc.nonfinite_samples();
    stats.seconds = start.elapsed().as_secs_f64();
    stats.rays = gpu.rays_traced(pixels as usize)?;
    Ok((acc, stats))
}
