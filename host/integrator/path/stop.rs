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
}

impl Stop {
    /// True if any rule holds. A time limit holds only after this run took a sample, so every
    /// run makes progress.
    pub fn holds(&self, run: &RunState) -> bool {
        let spp = self.spp.is_some_and(|n| run.samples >= n);
        let time = self.seconds.is_some_and(|t| run.samples > run.first_sample && run.seconds + run.next_batch_s > t);
        let error = self
            .target_relmse
            .is_some_and(|t| run.samples >= MIN_SAMPLES_FOR_ESTIMATE && run.relmse.is_some_and(|e| e <= t));
        spp || time || error
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
        RunState { samples, first_sample: 0, seconds, next_batch_s, relmse }
    }

    #[test]
    fn each_rule_holds_when_it_should() {
        let spp = Stop { spp: Some(16), ..Stop::default() };
        assert!(!spp.holds(&at(12, 100.0, 1.0, None)) && spp.holds(&at(16, 0.0, 0.0, None)));
        // A batch that would end past the limit does not start; none starts before a sample.
        let time = Stop { seconds: Some(10.0), ..Stop::default() };
        assert!(!time.holds(&at(4, 8.0, 1.5, None)));
        assert!(time.holds(&at(4, 8.0, 2.5, None)));
        assert!(!time.holds(&RunState { samples: 4, first_sample: 4, seconds: 20.0, next_batch_s: 0.0, relmse: None }));
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
