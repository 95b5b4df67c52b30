//! What the caller of a progressive render hears between batches: progress, checkpoints, and
//! the interrupt it may raise.

use super::accumulation::Accumulation;
use anyhow::Result;

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

