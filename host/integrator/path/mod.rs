//! The progressive path tracer (shaders/path.comp): its settings here; the render loop
//! ([`render`]), which batch comes next ([`schedule`], with [`adaptive`] sampling), when to stop
//! ([`stop`]), what the caller hears ([`progress`]), and the running sums ([`accumulation`])
//! that checkpoints store ([`checkpoint`]).

pub mod accumulation;
pub mod adaptive;
pub mod batch;
pub mod checkpoint;
pub mod coherence;
pub mod connections;
pub mod params;
pub mod progress;
pub mod render;
pub mod schedule;
pub mod shard;
pub mod stop;

pub use accumulation::Accumulation;
pub use progress::{Hooks, PathProgress};
pub use render::render;
pub use stop::Stop;

use super::RenderSettings;
use crate::gpu_abi::constants::*;

/// How the path tracer draws its random numbers (see shaders/include/sampler.glsl).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplerKind {
    /// Sobol in Z order (Ahmed & Wonka 2020), the default: each pixel's samples are an
    /// Owen-scrambled Sobol set as with `sobol`, and neighbouring pixels' sets are neighbouring
    /// parts of one sequence, so that the error is blue noise: the same relMSE, lower FLIP.
    Zsobol,
    /// Owen-scrambled Sobol (Burley 2020), each pixel its own shuffled sequence: low
    /// discrepancy per pixel, errors independent between pixels.
    Sobol,
    /// Independent uniform numbers from a hash of (pixel, sample, seed).
    Independent,
    /// `--sample-rate`^2 strata per pixel for the pixel position, independent numbers elsewhere.
    Stratified,
}

impl SamplerKind {
    pub const ALL: [SamplerKind; 4] = [SamplerKind::Zsobol, SamplerKind::Sobol, SamplerKind::Independent, SamplerKind::Stratified];

    pub fn gpu_value(self) -> u32 {
        match self {
            Self::Zsobol => SAMPLER_ZSOBOL,
            Self::Sobol => SAMPLER_SOBOL,
            Self::Independent => SAMPLER_INDEPENDENT,
            Self::Stratified => SAMPLER_STRATIFIED,
        }
    }

    /// The sampler a `SAMPLER_*` value names.
    pub fn from_gpu_value(v: u32) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.gpu_value() == v)
    }

    /// The name `--sampler` takes.
    pub fn name(self) -> &'static str {
        match self {
            Self::Zsobol => "zsobol",
            Self::Sobol => "sobol",
            Self::Independent => "independent",
            Self::Stratified => "stratified",
        }
    }
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
    /// The Z-ordered sampler's set size, log2 of samples per pixel ([`zsobol_log2`] of the
    /// run's total spp): the blue-noise property holds for a set as a whole, so it must be
    /// the run's sample count rounded up to a power of two; samples past it start new sets.
    /// A checkpoint stores it, and a resumed run keeps it.
    pub zsobol_log2: u32,
    /// Next-event estimation with MIS (default); false: BSDF sampling only, for tests.
    pub nee: bool,
    /// Pixels that draw the same sample numbers (default 8, [`coherence::DEFAULT_COHERENCE`];
    /// 1: each pixel its own). Coherent path tracing (Sadeghi, Chen & Jensen 2009, "Coherent
    /// path tracing", JGT 14(2)): lavapipe's eight lanes (one row of a workgroup) take the same
    /// bounce, light and roulette decisions, so their rays stay coherent and their paths end
    /// together: about 0.55x the time per sample on cornell-measured (the default block and
    /// sampler; less on the Mirror and Sphere boxes, docs/experiments/three-box-ladder.md).
    /// Each pixel's estimate is distributed as before, so the expected error per pixel is the
    /// same; the errors of a group's pixels are correlated ([`coherence`] says where that
    /// shows).
    pub coherence: u32,
    /// The side of the square block over which each coherence group's pixels are scattered
    /// (default 16, [`coherence::DEFAULT_COHERENCE_BLOCK`]): correlated errors apart, so
    /// the noise shows no structure. 0: the group is `coherence` pixels in a row, whose
    /// correlated errors show as short horizontal streaks (docs/experiments/
    /// coherent-sampling.md), about 0.75x the time of a 32 block.
    pub coherence_block: u32,
    /// Adaptive sampling ([`adaptive`]): after a uniform pilot of `PILOT_SPP`, each
    /// block (a workgroup row, or whole coherence blocks) takes samples in proportion to the
    /// noise the pilot showed around it. Unbiased; `stop.spp` is then the mean over the pixels.
    /// A block's noise estimate reads its neighbours, which must not share sample numbers with
    /// it: blocks are whole coherence blocks (the scattered coherence's squares, or runs in a
    /// row with `coherence_block` 0).
    pub adaptive: bool,
    /// Batches grow from `image.samples_per_batch` while a tile's submission and the whole
    /// batch stay short ([`batch`]; what `vkrt render` does unless `--samples-per-batch` is
    /// given); false (the default here): every batch takes `image.samples_per_batch`.
    /// Images are the same bytes either way.
    pub grow_batches: bool,
    /// What the path tracer does for mirrors (default true; both unbiased, false only to
    /// compare in tests and experiments), in scenes with mirror materials (the `path_mirrors`
    /// shader variant):
    /// - the mirror probe (shaders/include/mirror_probe.glsl): one pass per run finds the pixels
    ///   where a mirror over a Lambert lobe reflects nothing (the open side of a scene with no
    ///   sky), and there the camera ray's first hit takes the Lambert lobe for most samples
    ///   instead of 1 in 1/p_lambert;
    /// - light through planar mirrors (shaders/include/mirror_light.glsl,
    ///   `crate::prepare::mirrors`): next-event estimation also aims at each light's image in a
    ///   flat mirror, so light a mirror throws onto other surfaces is sampled, not only found.
    pub mirror_sampling: bool,
    /// Aim a share of diffuse bounces at curved glossy, mirror and glass objects
    /// (shaders/include/caster_guide.glsl, `crate::prepare::casters`), so that the light they
    /// throw onto walls (caustics) is found by more than chance; default true (unbiased; false
    /// only to compare in tests and experiments).
    pub caster_guiding: bool,
    /// Light-vertex connections ([`connections`]): auto (the default), on or off.
    pub connections: connections::Connections,
    pub stop: Stop,
    /// The sample index this run starts at (0; a shard's first index, `super::shard`): its
    /// samples are `first_sample ..`, `stop.spp` of them.
    pub first_sample: u64,
}

/// The Z-ordered sampler's set size for a run of `spp` samples per pixel: log2 of `spp` rounded
/// up to a power of two, at most `ZSOBOL_MAX_LOG2`; `DEFAULT_ZSOBOL_LOG2` for a run with no
/// sample count (stopped by time or error).
pub fn zsobol_log2(spp: Option<u64>) -> u32 {
    match spp {
        Some(n) => (64 - n.max(1).saturating_sub(1).leading_zeros()).min(ZSOBOL_MAX_LOG2),
        None => DEFAULT_ZSOBOL_LOG2,
    }
}

/// The set size of a run stopped by time or error: 256 spp, about where such runs end on the
/// test scenes; samples past it start new sets, each its own blue-noise set.
pub const DEFAULT_ZSOBOL_LOG2: u32 = 8;

impl PathSettings {
    /// Whether this run's diffuse bounces aim at caustic casters in `scene` (the `CASTERS`
    /// shader variants): guiding is on and the scene has some.
    pub fn aims_at_casters(&self, scene: &crate::prepare::GpuScene) -> bool {
        self.caster_guiding && scene.caster_count > 0
    }
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            image: RenderSettings::default(),
            max_depth: None,
            sampler: SamplerKind::Zsobol,
            sample_rate: 4,
            zsobol_log2: zsobol_log2(Some(16)),
            nee: true,
            coherence: coherence::DEFAULT_COHERENCE,
            coherence_block: coherence::DEFAULT_COHERENCE_BLOCK,
            adaptive: false,
            grow_batches: false,
            mirror_sampling: true,
            caster_guiding: true,
            connections: connections::Connections::Auto,
            stop: Stop { spp: Some(16), ..Stop::default() },
            first_sample: 0,
        }
    }
}
