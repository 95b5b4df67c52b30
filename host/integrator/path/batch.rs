//! How many samples per pixel the next batch takes. A batch is one submission per tile, and each
//! costs something whatever its sample count: the shader's per-pixel prologue and the write-back
//! of the sums (storage-buffer traffic, one lane at a time on lavapipe), the submission and the
//! wake-up of lavapipe's threads. On small images of cheap scenes that is several per cent of
//! the run (`CornellBox-Mirror` 256², 64 spp: 16 spp per batch took 0.91-0.95x the time of 4,
//! images bit-identical; docs/experiments/per-step-cost.md). So batches grow from the first
//! size while a submission stays short, which is the rule that keeps a device without a
//! watchdog (lavapipe) responsive and a GPU's watchdog away, and while a whole batch stays
//! short, which bounds how long an interrupt, a time limit or a progress line waits.
//!
//! Which samples a pixel takes never depends on the batch size: images are the same bytes
//! whatever the batches (fixed-point sums, `tests/progressive.rs`).

/// Samples per pixel of the first batch (and of every batch when growth is off): what the
/// path tracer always took before batches grew.
pub const FIRST_BATCH_SPP: u32 = 4;
/// The most samples per pixel a grown batch takes: past 16 the per-batch cost is already
/// under the timing noise (per-step-cost.md), and a bound keeps one mismeasured batch harmless.
pub const MAX_GROWN_BATCH_SPP: u32 = 64;
/// A grown batch's tile submissions should each take at most this long: an order of magnitude
/// under a desktop GPU driver's watchdog (about 2 s).
pub const SUBMISSION_TARGET_S: f64 = 0.25;
/// A grown batch should take at most this long as a whole: an interrupt, a time limit and the
/// progress line are seen between batches.
pub const BATCH_TARGET_S: f64 = 1.0;

/// The batch size of a run: fixed, or grown from measured batch times.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatchSizer {
    spp: u32,
    first: u32,
    grow: bool,
}

impl BatchSizer {
    /// Every batch takes `spp` samples per pixel (at least 1).
    pub fn fixed(spp: u32) -> Self {
        let spp = spp.max(1);
        Self { spp, first: spp, grow: false }
    }

    /// Batches start at `first` samples per pixel and grow ([`grown_batch`]), never below it.
    pub fn growing(first: u32) -> Self {
        let first = first.max(1);
        Self { spp: first, first, grow: true }
    }

    /// Samples per pixel the next batch takes (before the stop rule's cap).
    pub fn spp(&self) -> u64 {
        u64::from(self.spp)
    }

    /// Takes the measurement of a batch of `spp` samples per pixel that made `submissions`
    /// submissions in `seconds`; `seconds_left`: what remains of a time limit, if any.
    pub fn observe(&mut self, spp: u64, submissions: u64, seconds: f64, seconds_left: Option<f64>) {
        if self.grow {
            self.spp = grown_batch(self.spp, self.first, spp, submissions, seconds, seconds_left);
        }
    }
}

/// The next batch size after a batch of `spp` samples per pixel in `submissions` submissions
/// took `seconds`, given the current size `current` and the least size `first`: as many samples
/// as keep one submission under [`SUBMISSION_TARGET_S`], the batch under [`BATCH_TARGET_S`] and
/// within `seconds_left` of a time limit, at most double the current size (one batch's time is
/// one measurement, and the first can include start-up work) and at most
/// [`MAX_GROWN_BATCH_SPP`]; never below `first`. `seconds` must be the batch's own time, its
/// submissions waited for (`render` drains before timing). Sample costs are taken as constant over a
/// run, which they are in expectation: every batch draws the same kind of paths.
pub fn grown_batch(current: u32, first: u32, spp: u64, submissions: u64, seconds: f64, seconds_left: Option<f64>) -> u32 {
    let ceiling = current.saturating_mul(2).min(MAX_GROWN_BATCH_SPP).max(first);
    if spp == 0 || seconds.is_nan() || seconds <= 0.0 {
        // Nothing measured (an empty scene renders nothing): no reason to hold back.
        return ceiling;
    }
    let per_sample = seconds / spp as f64;
    let per_submission_sample = per_sample / submissions.max(1) as f64;
    let mut fits = (SUBMISSION_TARGET_S / per_submission_sample).min(BATCH_TARGET_S / per_sample);
    if let Some(left) = seconds_left {
        fits = fits.min(left.max(0.0) / per_sample);
    }
    // `fits` is finite and non-negative here; the cast saturates.
    (fits.floor() as u32).clamp(first, ceiling)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cheap_batches_grow_by_doubling_up_to_the_bound() {
        // 4 spp in 4 submissions took 10 ms: room for far more, but growth is at most 2x.
        let mut s = BatchSizer::growing(4);
        let mut sizes = vec![];
        for _ in 0..6 {
            let spp = s.spp();
            s.observe(spp, 4, 0.0025 * spp as f64, None);
            sizes.push(s.spp());
        }
        assert_eq!(sizes, [8, 16, 32, 64, 64, 64]);
    }

    #[test]
    fn growth_stops_where_a_submission_or_the_batch_would_be_long() {
        // 4 submissions of 37.5 ms at 4 spp (the Mirror box on lavapipe): 0.25 s per submission
        // and 1 s per batch both allow 26.7 spp.
        assert_eq!(grown_batch(16, 4, 4, 4, 0.15, None), 26);
        // 16 submissions of 47 ms: the batch (0.75 s at 4 spp) allows 5.3 spp.
        assert_eq!(grown_batch(4, 4, 4, 16, 0.75, None), 5);
        // 1 submission of 0.75 s at 4 spp: the submission allows 1.3, so the first size.
        assert_eq!(grown_batch(4, 4, 4, 1, 0.75, None), 4);
        // A batch already too long shrinks back, never below the first size.
        assert_eq!(grown_batch(32, 4, 32, 4, 4.0, None), 8);
        assert_eq!(grown_batch(32, 4, 32, 4, 400.0, None), 4);
    }

    #[test]
    fn a_time_limit_caps_the_next_batch() {
        // 0.1 s per spp and 0.55 s left: 5 spp, not the 10 the targets allow.
        assert_eq!(grown_batch(16, 4, 4, 4, 0.4, Some(0.55)), 5);
        // Past the limit: the first size (the stop rule decides whether it runs).
        assert_eq!(grown_batch(16, 4, 4, 4, 0.4, Some(-1.0)), 4);
    }

    #[test]
    fn fixed_batches_do_not_change_and_nothing_measured_grows() {
        let mut s = BatchSizer::fixed(3);
        s.observe(3, 1, 1e-6, None);
        assert_eq!(s.spp(), 3);
        assert_eq!(BatchSizer::fixed(0).spp(), 1);
        assert_eq!(grown_batch(4, 4, 4, 4, 0.0, None), 8);
        assert_eq!(grown_batch(4, 4, 0, 0, 1.0, None), 8);
        assert_eq!(grown_batch(64, 4, 4, 4, 0.0, None), 64);
    }
}
