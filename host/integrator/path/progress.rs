//! What the caller of a progressive render hears between batches: progress, checkpoints, and
//! the interrupt it may raise.

use super::accumulation::Accumulation;
use anyhow::Result;

/// What the progress callback sees after each batch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathProgress {
    /// Samples per pixel so far (the mean over the pixels for an adaptive run).
    pub samples: u64,
    /// The sample count the run stops at, if it stops on one.
    pub target_spp: Option<u64>,
    pub seconds: f64,
    /// Paths per second in this run.
    pub samples_per_second: f64,
    /// Rays (closest-hit and shadow) per second in this run, as of the last read-back.
    pub rays_per_second: Option<f64>,
    /// The last estimate of the image's relMSE, if any (refreshed about every second while a
    /// progress callback, a target error or checkpoints want it).
    pub relmse: Option<f64>,
    /// 0 to 1: how far the stop condition closest to holding is.
    pub fraction: f64,
    /// The same when this run started: a resumed run starts part of the way, and only what it
    /// has done since says how fast it goes (the ETA).
    pub start_fraction: f64,
}

/// The type of a hook that receives the sums so far.
pub type SumsHook<'h> = &'h mut dyn FnMut(&Accumulation) -> Result<()>;

/// Hooks into the progressive loop.
#[derive(Default)]
pub struct Hooks<'h> {
    pub progress: Option<&'h mut dyn FnMut(&PathProgress)>,
    /// Called with the sums every `checkpoint_interval_s` (default 0: after every batch) and at the end.
    pub checkpoint: Option<SumsHook<'h>>,
    pub checkpoint_interval_s: f64,
    /// Called with the sums every `snapshot_interval_s` during the run (not at the end): a
    /// preview of the image so far (`vkrt render --preview-every`).
    pub snapshot: Option<SumsHook<'h>>,
    pub snapshot_interval_s: f64,
    /// Checked between batches: once raised, the render stops as if a stop condition held, so
    /// the final checkpoint holds every finished sample (Ctrl-C and SIGTERM raise it).
    pub interrupt: Option<&'h std::sync::atomic::AtomicBool>,
}
