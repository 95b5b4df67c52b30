//! Which samples the next batch takes: a uniform run's next `samples_per_batch` of every pixel,
//! or an adaptive run's per-block counts ([`AdaptiveState`], `super::adaptive`).

use super::accumulation::Accumulation;
use super::adaptive::{final_counts, round_counts, BlockGrid, PILOT_SPP};
use super::Stop;
use anyhow::{bail, Result};

/// A uniform run's next batch: `batch` samples per pixel, or what is left of `stop.spp`, or up
/// to where the target error wants its next estimate (`target_at`,
/// [`Stop::next_estimate_samples`], so that the estimate there decides), from sample index
/// `next` on, `taken` samples into the run.
pub fn uniform_batch(next: u64, batch: u64, stop: &Stop, taken: u64, target_at: Option<u64>) -> Result<u64> {
    let count = stop.spp.map_or(batch, |n| batch.min(n.saturating_sub(taken)));
    let count = match target_at {
        Some(n) if n > taken => count.min(n - taken),
        _ => count,
    };
    if next + count > u32::MAX as u64 {
        bail!("sample index past 2^32");
    }
    Ok(count)
}

/// An adaptive run's per-block progress: samples taken so far by each block (every
/// pixel of a block has the same count).
pub struct AdaptiveState {
    pub grid: BlockGrid,
    pub done: Vec<u32>,
    /// The budget the counts at the end were computed for, and those counts (they depend on
    /// the rates, fixed once set, and the budget alone).
    end: Option<(u64, Vec<u32>)>,
}

impl AdaptiveState {
    pub fn new(acc: &Accumulation, grid: BlockGrid) -> Self {
        let done: Vec<u32> = (0..grid.count())
            .map(|key| {
                let b = grid.pixels(key);
                acc.counts((b.ys.start * grid.width + b.xs.start) as usize).0 as u32
            })
            .collect();
        Self { grid, done, end: None }
    }

    /// Samples taken over all pixels.
    pub fn total(&self) -> u64 {
        self.grid.pixel_samples(&self.done)
    }

    /// Each block's (first sample, count) for the next batch: the pilot in batches of `batch`
    /// (rounded up to even), then one round of `rates`, cut where a block reaches its count at
    /// the end of `budget` (total samples over all pixels; `super::adaptive::final_counts`).
    pub fn next_batch(&mut self, rates: &[u32], batch: u64, budget: Option<u64>) -> Vec<[u32; 2]> {
        let pilot_left = PILOT_SPP.saturating_sub(self.done.iter().copied().min().unwrap_or(PILOT_SPP));
        let counts: Vec<u32> = if pilot_left > 0 {
            let step = (batch.div_ceil(2) * 2).min(pilot_left as u64) as u32;
            self.done.iter().map(|&d| step.min(PILOT_SPP.saturating_sub(d))).collect()
        } else {
            let end = budget.map(|b| {
                if !matches!(&self.end, Some((cached, counts)) if *cached == b && counts.len() == rates.len()) {
                    self.end = Some((b, final_counts(rates, self.grid, b)));
                }
                self.end.as_ref().map_or(&[][..], |(_, counts)| counts.as_slice())
            });
            round_counts(rates, &self.done, end)
        };
        self.done.iter().zip(counts).map(|(&d, c)| [d, c]).collect()
    }

    pub fn advance(&mut self, batch: &[[u32; 2]]) {
        for (d, b) in self.done.iter_mut().zip(batch) {
            *d += b[1];
        }
    }

    /// True once every block has its pilot: the allocation can be made.
    pub fn pilot_done(&self) -> bool {
        self.done.iter().all(|&d| d >= PILOT_SPP)
    }
}

/// Fails if a batch would take a sample index past 2^32 (the shaders' sample numbers are u32).
pub fn check_block_batch(next: &[[u32; 2]]) -> Result<()> {
    if next.iter().any(|b| b[0] as u64 + b[1] as u64 > u32::MAX as u64) {
        bail!("sample index past 2^32");
    }
    Ok(())
}
