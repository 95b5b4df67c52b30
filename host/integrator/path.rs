//! The progressive path tracer's host side (shaders/path.comp): light table, accumulation
//! buffers, and the loop of short sample batches that runs until a stop condition holds.

use super::accumulation::Accumulation;
use super::adaptive::{block_rates, round_counts, BlockGrid, PILOT_SPP};
use super::frame::{frame_for, scene_scale, INTEGRATOR_BINDINGS};
use super::gpu_scene::GpuScene;
use super::light_table::LightTable;
use super::tiles::{bind_all, dispatch_samples};
use super::{RenderSettings, RenderStats};
use crate::gpu::{Buffer, Context, MemoryLocation, TexelArray, TexelFormat};
use crate::layout::constants::*;
use crate::layout::scene_buffers::SceneBuffers;
use crate::layout::{GpuFrame, GpuPathParams, GpuPush};
use crate::pipeline::{shaders, BindingKind, ComputePipeline};
use crate::scene::Scene;
use anyhow::{bail, Context as _, Result};
use ash::vk;
use std::time::Instant;

/// How the path tracer draws its random numbers (see shaders/include/sampler.glsl).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol (Burley 2020): low discrepancy, the lowest error per sample.
    Sobol,
    /// Independent uniform numbers from a hash of (pixel, sample, seed).
    Independent,
    /// `--sample-rate`^2 strata per pixel for the pixel position, independent numbers elsewhere.
    Stratified,
}

impl SamplerKind {
    pub fn gpu_value(self) -> u32 {
        match self {
            Self::Sobol => SAMPLER_SOBOL,
            Self::Independent => SAMPLER_INDEPENDENT,
            Self::Stratified => SAMPLER_STRATIFIED,
        }
    }
}

/// When a progressive render stops: the first condition that holds (at least one must be set).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stop {
    /// Samples per pixel in total (counting resumed ones).
    pub spp: Option<u64>,
    /// Wall-clock seconds for this run; no batch starts that would end past it.
    pub seconds: Option<f64>,
    /// Estimated relMSE (from the two half-images) to reach.
    pub target_relmse: Option<f64>,
}

/// Path tracer settings. `image.spp` and `image.max_depth` are not used: see `stop` and `max_depth`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSettings {
    /// Size, seed, tile size and samples per batch.
    pub image: RenderSettings,
    /// Path segments (rays) per path; `None` for unbounded (Russian roulette ends paths).
    pub max_depth: Option<u32>,
    pub sampler: SamplerKind,
    /// Strata per pixel side for the stratified sampler (default 4: 16 strata).
    pub sample_rate: u32,
    /// Next-event estimation with MIS (default); false: BSDF sampling only, for tests.
    pub nee: bool,
    /// Pixels in a row that draw the same sample numbers (default 1: each pixel its own).
    /// Coherent path tracing (Sadeghi, Chen & Jensen 2009, "Coherent path tracing", JGT
    /// 14(2)): with 8, lavapipe's eight lanes (one row of a workgroup) take the same bounce,
    /// light and roulette decisions at neighbouring points, so their rays stay coherent and
    /// their paths end together. Each pixel's estimate is distributed as before, so the
    /// expected error per pixel is the same; the errors of a block's pixels are correlated,
    /// which shows as short horizontal streaks in the noise (BENCHMARKS.md, "Coherent
    /// sampling").
    pub coherence: u32,
    /// Adaptive sampling (`integrator::adaptive`): after a uniform pilot of `PILOT_SPP`, each
    /// block (a workgroup row, or whole coherence blocks) takes samples in proportion to the
    /// noise the pilot showed around it. Unbiased; `stop.spp` is then the mean over the pixels.
    pub adaptive: bool,
    pub stop: Stop,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            image: RenderSettings::default(),
            max_depth: None,
            sampler: SamplerKind::Sobol,
            sample_rate: 4,
            nee: true,
            coherence: 1,
            adaptive: false,
            stop: Stop { spp: Some(16), ..Stop::default() },
        }
    }
}

/// The fewest samples before the error estimate is trusted for stopping.
const MIN_SAMPLES_FOR_ESTIMATE: u64 = 4;
/// Seconds between read-backs that refresh the error estimate.
const ESTIMATE_INTERVAL_S: f64 = 1.0;

/// What the progress callback sees after each batch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathProgress {
    pub samples: u64,
    pub seconds: f64,
    /// Paths per second in this run.
    pub samples_per_second: f64,
    /// The last estimate of the image's relMSE, if any.
    pub relmse: Option<f64>,
    /// 0 to 1: how far the stop condition closest to holding is.
    pub fraction: f64,
}

/// Hooks into the progressive loop.
#[derive(Default)]
pub struct Hooks<'h> {
    pub progress: Option<&'h mut dyn FnMut(&PathProgress)>,
    /// Called with the sums every `checkpoint_interval_s` (default 0: after every batch) and at the end.
    pub checkpoint: Option<&'h mut dyn FnMut(&Accumulation) -> Result<()>>,
    pub checkpoint_interval_s: f64,
    /// Checked between batches: once raised, the render stops as if a stop condition held, so
    /// the final checkpoint holds every finished sample (Ctrl-C and SIGTERM raise it).
    pub interrupt: Option<&'h std::sync::atomic::AtomicBool>,
}

/// The path tracer's bindings besides [`INTEGRATOR_BINDINGS`].
pub const PATH_BINDINGS: &[(u32, BindingKind)] = &[
    (BINDING_LIGHT_PICKS, BindingKind::Texels),
    (BINDING_PATH_PARAMS, BindingKind::Uniform),
    (BINDING_ACCUM_EVEN, BindingKind::Storage),
    (BINDING_BLOCK_SAMPLES, BindingKind::Storage),
];

/// The settings as the shader reads them, and the light table.
pub fn path_params(scene: &Scene, settings: &PathSettings) -> Result<(GpuPathParams, LightTable)> {
    let max_depth = match settings.max_depth {
        Some(0) => bail!("max depth 0 traces no rays; use 1 or more"),
        Some(d) => d,
        None => PATH_DEPTH_UNBOUNDED,
    };
    if settings.sample_rate == 0 {
        bail!("sample rate must be positive");
    }
    if settings.coherence == 0 {
        bail!("coherence must be at least 1 (pixels that share sample numbers)");
    }
    let radius = {
        let b = scene.bounds();
        if b.is_empty() { 0.0 } else { 0.5 * b.extent().length() }
    };
    let table = LightTable::new(&SceneBuffers::new(scene), radius);
    let params = GpuPathParams {
        max_depth,
        rr_depth: PATH_RR_DEPTH,
        sampler_kind: settings.sampler.gpu_value(),
        sample_rate: settings.sample_rate,
        pick_count: table.picks.len() as u32,
        nee: settings.nee as u32,
        inv_total_weight: if table.total_weight > 0.0 { (1.0 / table.total_weight) as f32 } else { 0.0 },
        coherence: settings.coherence,
        adaptive: if settings.adaptive { BlockGrid::new(settings.image.width, settings.image.height, settings.coherence).block } else { 0 },
        _pad0: 0,
        _pad1: 0,
        _pad2: 0,
    };
    Ok((params, table))
}

/// The sums as they stand; `like` gives the run's kind (uniform or per-pixel counts, and the
/// adaptive rates). `samples`: per pixel, or the mean for per-pixel counts.
fn read_accumulation(sum: &Buffer, even: &Buffer, like: &Accumulation, samples: u64) -> Result<Accumulation> {
    let pixels = like.width as usize * like.height as usize;
    let mut acc = Accumulation::new(like.width, like.height);
    acc.sum = sum.read_as(pixels).context("reading the accumulation buffer")?;
    acc.even = even.read_as(pixels).context("reading the even-sample buffer")?;
    acc.samples = samples;
    acc.even_samples = if like.per_pixel { samples / 2 } else { samples.div_ceil(2) };
    acc.per_pixel = like.per_pixel;
    acc.rates = like.rates.clone();
    Ok(acc)
}

/// An adaptive run's per-block progress: samples taken so far by each block (every
/// pixel of a block has the same count).
struct AdaptiveState {
    grid: BlockGrid,
    done: Vec<u32>,
}

impl AdaptiveState {
    fn new(acc: &Accumulation, grid: BlockGrid) -> Self {
        let done: Vec<u32> = (0..grid.count())
            .map(|key| {
                let (y, cols) = grid.pixels(key);
                acc.counts((y * grid.width + cols.start) as usize).0 as u32
            })
            .collect();
        Self { grid, done }
    }

    /// Samples taken over all pixels.
    fn total(&self) -> u64 {
        self.grid.pixel_samples(&self.done)
    }

    /// Each block's (first sample, count) for the next batch: the pilot in batches of `batch`
    /// (rounded up to even), then one round of `rates`, cut to what is left of `budget` (total
    /// samples over all pixels) if given.
    fn next_batch(&self, rates: &[u32], batch: u64, budget: Option<u64>) -> Vec<[u32; 2]> {
        let pilot_left = PILOT_SPP.saturating_sub(self.done.iter().copied().min().unwrap_or(PILOT_SPP));
        let counts: Vec<u32> = if pilot_left > 0 {
            let step = (batch.div_ceil(2) * 2).min(pilot_left as u64) as u32;
            self.done.iter().map(|&d| step.min(PILOT_SPP.saturating_sub(d))).collect()
        } else {
            round_counts(rates, self.grid, budget.map_or(u64::MAX, |b| b.saturating_sub(self.total())))
        };
        self.done.iter().zip(counts).map(|(&d, c)| [d, c]).collect()
    }

    fn advance(&mut self, batch: &[[u32; 2]]) {
        for (d, b) in self.done.iter_mut().zip(batch) {
            *d += b[1];
        }
    }
}

/// Renders `scene` progressively, continuing `resume` if given (its sums and count; samples go
/// on from its count), until `settings.stop` holds.
pub fn render(
    ctx: &Context,
    scene: &Scene,
    gpu: &GpuScene,
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
    let start = Instant::now();
    let mut acc = resume.unwrap_or_else(|| {
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
    if settings.adaptive && stop.spp.is_some_and(|n| n < PILOT_SPP as u64) {
        bail!("adaptive sampling needs at least {PILOT_SPP} spp (its uniform pilot); got {}", stop.spp.unwrap_or(0));
    }
    let grid = BlockGrid::new(img.width, img.height, settings.coherence);
    if !acc.rates.is_empty() && (acc.rates.len() != grid.count() || acc.rates.iter().any(|&r| r == 0 || r % 2 != 0)) {
        bail!("the resumed run's adaptive rates ({} of them) are not even rates for this render's {} blocks", acc.rates.len(), grid.count());
    }
    let mut adaptive = settings.adaptive.then(|| AdaptiveState::new(&acc, grid));
    let mut stats = RenderStats::default();
    let (params, table) = path_params(scene, settings)?;
    let frame: GpuFrame = frame_for(scene, img, gpu.light_count, gpu.emitter_count)?;
    debug_assert_eq!(frame.scene_scale, scene_scale(scene));
    let uniform = vk::BufferUsageFlags::UNIFORM_BUFFER;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let frame_buf = Buffer::with_data(ctx, "frame", std::slice::from_ref(&frame), uniform)?;
    let params_buf = Buffer::with_data(ctx, "path params", std::slice::from_ref(&params), uniform)?;
    // Read at a per-lane index, so a texel buffer like the scene's arrays.
    let picks = TexelArray::with_data(ctx, "light picks", &table.picks, TexelFormat::Rgba32Uint)?;
    let pixels = img.width as u64 * img.height as u64;
    let sum_buf = Buffer::new(ctx, "accumulation", pixels * 16, storage, MemoryLocation::Device)?;
    let even_buf = Buffer::new(ctx, "accumulation (even samples)", pixels * 16, storage, MemoryLocation::Device)?;
    sum_buf.write(bytemuck::cast_slice(&acc.sum))?;
    even_buf.write(bytemuck::cast_slice(&acc.even))?;
    // Written before each batch of an adaptive run; one unused entry otherwise.
    let blocks = if settings.adaptive { grid.count() as u64 } else { 1 };
    let block_buf = Buffer::new(ctx, "block samples", blocks * 8, storage, MemoryLocation::Device)?;
    let bindings: Vec<(u32, BindingKind)> = INTEGRATOR_BINDINGS.iter().chain(PATH_BINDINGS).copied().collect();
    let spv = shaders::for_layout("path", gpu.layout)?;
    let features = img.features(scene);
    let pipeline = ComputePipeline::specialized(
        ctx,
        "path",
        spv,
        &bindings,
        std::mem::size_of::<GpuPush>() as u32,
        &features.spec_constants(),
    )?;
    gpu.bind_scene(&pipeline)?;
    pipeline.bind_texels(BINDING_LIGHT_PICKS, &picks.view)?;
    bind_all(
        &pipeline,
        &[
            (BINDING_FRAME, &frame_buf),
            (BINDING_ACCUM, &sum_buf),
            (BINDING_PATH_PARAMS, &params_buf),
            (BINDING_ACCUM_EVEN, &even_buf),
            (BINDING_BLOCK_SAMPLES, &block_buf),
        ],
    )?;

    let first_sample = acc.samples;
    let mut samples = acc.samples;
    let mut relmse = None;
    let mut last_estimate = start;
    let mut last_checkpoint = start;
    let mut last_batch_s = 0.0f64;
    let batch = img.samples_per_batch.max(1) as u64;
    let empty = gpu.triangle_count == 0;
    let scene_push = gpu.push();
    loop {
        let elapsed = start.elapsed().as_secs_f64();
        let spp_done = stop.spp.is_some_and(|n| samples >= n);
        let time_done = stop.seconds.is_some_and(|t| samples > first_sample && elapsed + last_batch_s > t);
        let error_done = stop.target_relmse.is_some_and(|t| samples >= MIN_SAMPLES_FOR_ESTIMATE && relmse.is_some_and(|e| e <= t));
        if spp_done || time_done || error_done || (empty && samples > first_sample) {
            break;
        }
        if hooks.interrupt.is_some_and(|i| i.load(std::sync::atomic::Ordering::SeqCst)) {
            stats.interrupted = true;
            break;
        }
        let t_batch = Instant::now();
        if let Some(state) = adaptive.as_mut() {
            if state.done.iter().all(|&d| d >= PILOT_SPP) && acc.rates.is_empty() {
                acc = read_accumulation(&sum_buf, &even_buf, &acc, samples)?;
                acc.rates = block_rates(&acc, grid);
            }
            let next = state.next_batch(&acc.rates, batch, stop.spp.map(|n| n * pixels));
            if next.iter().all(|b| b[1] == 0) {
                break;
            }
            if next.iter().any(|b| b[0] as u64 + b[1] as u64 > u32::MAX as u64) {
                bail!("sample index past 2^32");
            }
            block_buf.write(bytemuck::cast_slice(&next))?;
            if !empty {
                dispatch_samples(ctx, &scene_push, &pipeline, "path tile", img, 0, 0, 0, &mut || stats.submissions += 1)?;
            }
            state.advance(&next);
            samples = state.total() / pixels;
        } else {
            let count = stop.spp.map_or(batch, |n| batch.min(n - samples));
            if samples + count > u32::MAX as u64 {
                bail!("sample index past 2^32");
            }
            if !empty {
                dispatch_samples(ctx, &scene_push, &pipeline, "path tile", img, samples as u32, count as u32, 0, &mut || stats.submissions += 1)?;
            }
            samples += count;
        }
        last_batch_s = t_batch.elapsed().as_secs_f64();
        let now = Instant::now();
        let want_estimate = stop.target_relmse.is_some() || hooks.checkpoint.is_some();
        if want_estimate && now.duration_since(last_estimate).as_secs_f64() >= ESTIMATE_INTERVAL_S {
            acc = read_accumulation(&sum_buf, &even_buf, &acc, samples)?;
            relmse = acc.estimate_relmse();
            last_estimate = now;
        }
        if let Some(hook) = hooks.checkpoint.as_mut() {
            if now.duration_since(last_checkpoint).as_secs_f64() >= hooks.checkpoint_interval_s {
                acc = read_accumulation(&sum_buf, &even_buf, &acc, samples)?;
                hook(&acc)?;
                last_checkpoint = now;
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        let mut fraction = 0.0f64;
        if let Some(n) = stop.spp {
            fraction = fraction.max(samples as f64 / n.max(1) as f64);
        }
        if let Some(t) = stop.seconds {
            fraction = fraction.max(seconds / t.max(1e-9));
        }
        if let (Some(t), Some(e)) = (stop.target_relmse, relmse) {
            // Error falls as 1/spp: the fraction of the samples needed so far.
            fraction = fraction.max((t / e).min(1.0));
        }
        if let Some(progress) = hooks.progress.as_mut() {
            progress(&PathProgress {
                samples,
                seconds,
                samples_per_second: (samples - first_sample) as f64 * pixels as f64 / seconds.max(1e-9),
                relmse,
                fraction: fraction.min(1.0),
            });
        }
    }
    acc = read_accumulation(&sum_buf, &even_buf, &acc, samples)?;
    if let Some(hook) = hooks.checkpoint.as_mut() {
        hook(&acc)?;
    }
    stats.nonfinite_samples = acc.nonfinite_samples();
    stats.seconds = start.elapsed().as_secs_f64();
    Ok((acc, stats))
}
