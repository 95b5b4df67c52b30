//! When a progressive render stops: the first of its stop rules that holds, and how far along
//! it is. Pure functions of what the run has done, so they are tested without a clock.

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

/// The fewest samples before the error estimate is trusted for stopping.
pub const MIN_SAMPLES_FOR_ESTIMATE: u64 = 4;

/// Where a run stands between batches.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunState {
    /// Samples per pixel so far, resumed ones included.
    pub samples: u64,
    /// Samples the run started from (a resumed checkpoint's count).
    pub first_sample: u64,
    /// Seconds since this run started.
    pub seconds: f64,
    /// Seconds the next batch is expected to take (the last one's per sample, times the next
    /// one's samples): no batch starts that would end past `Stop::seconds`.
    pub next_batch_s: f64,
    /// The last estimate of the image's relMSE, if any.
    pub relmse: Option<f64>,
    /// Samples per pixel when `relmse` was estimated.
    pub relmse_samples: u64,
}

impl Stop {
    /// True if any rule holds. A time limit holds only after this run took a sample, so every
    /// run makes progress.
    pub fn holds(&self, run: &RunState) -> bool {
        let spp = self.spp.is_some_and(|n| run.samples >= n);
        let time = self.seconds.is_some_and(|t| run.samples > run.first_sample && run.seconds + run.next_batch_s > t);
        let error = self.target_relmse.is_some_and(|t| run.samples >= MIN_SAMPLES_FOR_ESTIMATE && run.relmse.is_some_and(|e| e <= t));
        spp || time || error
    }

    /// Samples per pixel where the last estimate puts the target error: the error falls as
    /// 1/spp, so an estimate e at n samples puts target t at n e / t. None without a target,
    /// an estimate, or with the target met.
    pub fn target_samples(&self, run: &RunState) -> Option<u64> {
        let (t, e) = (self.target_relmse?, run.relmse?);
        if !(t > 0.0 && e.is_finite() && e > t) {
            return None;
        }
        let n = run.relmse_samples.max(1) as f64 * e / t;
        // At least one sample more; the cast saturates for absurd ratios.
        Some((n.ceil() as u64).max(run.relmse_samples + 1))
    }

    /// Samples per pixel at which the target error wants its next estimate: where the last one
    /// puts the target ([`Self::target_samples`]), but at least 1/8 more samples than it was
    /// taken at and at most twice as many. Early estimates are noisy, and one that is too high
    /// (the 256² Cornell box read 4 spp as needing 44 for relMSE 1e-2, which 22 met) must not
    /// carry the run past the target; an estimate just over the target must not make a
    /// read-back of every next sample. So a run makes about log2 of its samples such
    /// read-backs, and overshoots a met target by at most 1/8 of its samples.
    pub fn next_estimate_samples(&self, run: &RunState) -> Option<u64> {
        let at = run.relmse_samples.max(1);
        self.target_samples(run).map(|n| n.max(at + at.div_ceil(8)).min(at * 2))
    }

    /// Whether the target error wants a fresh estimate: the first as soon as it can be trusted
    /// (MIN_SAMPLES_FOR_ESTIMATE), then once the samples reach [`Self::next_estimate_samples`].
    /// Without this a fast device rendered on until the next estimate a second or more later:
    /// an H200 took 3132 spp for a 512² target the image met near 200.
    pub fn estimate_due(&self, run: &RunState) -> bool {
        if self.target_relmse.is_none() || run.samples < MIN_SAMPLES_FOR_ESTIMATE {
            return false;
        }
        match run.relmse {
            None => true,
            Some(_) => self.next_estimate_samples(run).is_some_and(|n| run.samples >= n),
        }
    }

    /// 0 to 1: how far the rule closest to holding is. The error falls as 1/spp, so for a
    /// target error the fraction of the samples needed so far is target / estimate.
    pub fn fraction(&self, run: &RunState) -> f64 {
        let mut fraction = 0.0f64;
        if let Some(n) = self.spp {
            fraction = fraction.max(run.samples as f64 / n.max(1) as f64);
        }
        if let Some(t) = self.seconds {
            fraction = fraction.max(run.seconds / t.max(1e-9));
        }
        if let (Some(t), Some(e)) = (self.target_relmse, run.relmse) {
            fraction = fraction.max((t / e).min(1.0));
        }
        fraction.min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(samples: u64, seconds: f64, next_batch_s: f64, relmse: Option<f64>) -> RunState {
        RunState { samples, first_sample: 0, seconds, next_batch_s, relmse, relmse_samples: samples }
    }

    #[test]
    fn the_target_rule_asks_for_estimates_where_the_target_is_expected() {
        let stop = Stop { target_relmse: Some(0.01), ..Stop::default() };
        // Nothing to trust before 4 samples; then the first estimate at once.
        assert!(!stop.estimate_due(&RunState { samples: 2, ..RunState::default() }));
        assert!(stop.estimate_due(&RunState { samples: 4, ..RunState::default() }));
        // 0.015 at 8 spp: the target is expected at 12; not due before, due there (8 + 1/8 is 9).
        let est = RunState { samples: 8, relmse: Some(0.015), relmse_samples: 8, ..RunState::default() };
        assert_eq!(stop.target_samples(&est), Some(12));
        assert!(!stop.estimate_due(&RunState { samples: 11, ..est }));
        assert!(stop.estimate_due(&RunState { samples: 12, ..est }));
        // 0.04 at 8 spp puts it at 32, but the next estimate comes at 16 (twice the samples).
        let far = RunState { relmse: Some(0.04), ..est };
        assert_eq!((stop.target_samples(&far), stop.next_estimate_samples(&far)), (Some(32), Some(16)));
        assert!(!stop.estimate_due(&RunState { samples: 15, ..far }) && stop.estimate_due(&RunState { samples: 16, ..far }));
        // Just over the target: one more sample at least, and the next estimate 1/8 further.
        let close = RunState { samples: 100, relmse: Some(0.010001), relmse_samples: 100, ..RunState::default() };
        assert_eq!((stop.target_samples(&close), stop.next_estimate_samples(&close)), (Some(101), Some(113)));
        // Met, no target, or no estimate: nothing expected.
        assert_eq!(stop.target_samples(&RunState { relmse: Some(0.005), ..est }), None);
        assert_eq!(Stop { spp: Some(8), ..Stop::default() }.target_samples(&est), None);
        assert!(!Stop { spp: Some(8), ..Stop::default() }.estimate_due(&est));
    }

    #[test]
    fn each_rule_holds_when_it_should() {
        let spp = Stop { spp: Some(16), ..Stop::default() };
        assert!(!spp.holds(&at(12, 100.0, 1.0, None)) && spp.holds(&at(16, 0.0, 0.0, None)));
        // A batch that would end past the limit does not start; none starts before a sample.
        let time = Stop { seconds: Some(10.0), ..Stop::default() };
        assert!(!time.holds(&at(4, 8.0, 1.5, None)));
        assert!(time.holds(&at(4, 8.0, 2.5, None)));
        assert!(!time.holds(&RunState { samples: 4, first_sample: 4, seconds: 20.0, next_batch_s: 0.0, relmse: None, relmse_samples: 0 }));
        let error = Stop { target_relmse: Some(0.01), ..Stop::default() };
        assert!(!error.holds(&at(2, 0.0, 0.0, Some(0.001))), "trusted an estimate from too few samples");
        assert!(!error.holds(&at(8, 0.0, 0.0, Some(0.02))) && error.holds(&at(8, 0.0, 0.0, Some(0.01))));
        assert!(!error.holds(&at(8, 0.0, 0.0, None)));
    }

    #[test]
    fn the_fraction_follows_the_closest_rule() {
        let s = Stop { spp: Some(100), seconds: Some(10.0), target_relmse: Some(0.01) };
        assert_eq!(s.fraction(&at(25, 1.0, 0.0, None)), 0.25);
        assert_eq!(s.fraction(&at(25, 5.0, 0.0, None)), 0.5);
        assert!((s.fraction(&at(25, 1.0, 0.0, Some(0.0125))) - 0.8).abs() < 1e-12);
        assert_eq!(s.fraction(&at(500, 1.0, 0.0, None)), 1.0);
    }
}
