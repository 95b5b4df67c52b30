//! Adaptive sampling for the path tracer: after a uniform pilot, each block (a run of pixels in
//! a row: whole coherence blocks, `super::PathSettings::coherence`, at least a workgroup row wide)
//! takes samples in proportion to the relative noise the pilot showed around it, so that the
//! mean relMSE, which is what `vkrt compare` and the time-to-error benchmark measure, falls
//! faster for the same number of samples (docs/experiments/adaptive-sampling.md).
//!
//! Unbiased by construction: a block's rate is computed from the pilot samples of the pixels
//! around it, never from its own, and every pixel's pilot takes the same count. Blocks draw
//! independent sample numbers (a block is made of whole coherence blocks, so no sampler key
//! is in two), so a block's count is independent of its own sample values and the mean of its
//! samples stays an unbiased estimate. (Deciding from a pixel's own samples, as most adaptive
//! samplers do, biases the mean: a bright outlier raises the noise estimate and buys samples
//! that dilute it.) The allocation is fixed after the pilot, so it is a function of (pixel,
//! seed) like every sample, and resumed runs go on with the same rates.
//!
//! The optimal share for the mean relMSE (minimise sum_b v_b / n_b for sum_b n_b fixed) is
//! n_b proportional to sqrt(v_b), v_b the block's relative variance per sample: that is
//! Neyman allocation in stratified sampling (Neyman 1934). Every count is even, so that each
//! pixel's even-indexed half is exactly half of it (`Accumulation::counts`).

use super::accumulation::Accumulation;

/// Uniform samples per pixel before the allocation (even).
pub const PILOT_SPP: u32 = 8;
/// Mean of the per-round rates before doubling: one round is ~2 x this many samples per pixel.
pub const RATE_MEAN: f64 = 4.0;
/// The largest per-round rate before doubling: at most RATE_MAX x the least-sampled block.
pub const RATE_MAX: u32 = 16;
/// Pixel rows and columns around a block that its noise estimate looks at.
const WINDOW_ROWS_ABOVE: u32 = 3;
const WINDOW_ROWS_BELOW: u32 = 4;
const WINDOW_COLUMNS: u32 = 4;

/// The allocation blocks of an image: runs of `block` pixels in a row, keyed as
/// shaders/include/sampler.glsl's `sample_key` with `block` for the coherence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockGrid {
    pub width: u32,
    pub height: u32,
    pub block: u32,
}

/// The fewest pixels in a block: a workgroup row, which lavapipe runs as one SIMD subgroup
/// whose lanes would otherwise wait for the lane with the most samples (measured: 7 % more
/// time per sample with 1-pixel blocks). Fixed, not the device's subgroup size: the blocks
/// decide which samples each pixel takes, so they must not change from device to device.
pub const MIN_BLOCK: u32 = 8;

impl BlockGrid {
    /// Blocks of whole coherence blocks, at least `MIN_BLOCK` pixels wide.
    pub fn new(width: u32, height: u32, coherence: u32) -> Self {
        let c = coherence.max(1);
        Self { width, height, block: c * MIN_BLOCK.div_ceil(c) }
    }
    pub fn blocks_per_row(&self) -> u32 {
        self.width.div_ceil(self.block.max(1))
    }
    pub fn count(&self) -> usize {
        self.blocks_per_row() as usize * self.height as usize
    }
    /// Samples over all pixels when block k takes `per_block[k]` samples in each of its pixels.
    pub fn pixel_samples(&self, per_block: &[u32]) -> u64 {
        per_block.iter().enumerate().map(|(k, &n)| n as u64 * self.pixels(k).1.len() as u64).sum()
    }
    /// Block `key`'s row and pixel columns.
    pub fn pixels(&self, key: usize) -> (u32, std::ops::Range<u32>) {
        let per_row = self.blocks_per_row() as usize;
        let c = self.block.max(1);
        let (y, bx) = ((key / per_row) as u32, (key % per_row) as u32);
        (y, bx * c..((bx + 1) * c).min(self.width))
    }
}

/// Each block's samples per round (even, 2 to 2 x RATE_MAX) from the `pilot`: the relative
/// noise of each pixel, (A - B)^2 / (F^2 + 0.01) over the channels with A and B the pilot's
/// half-images and F their mean, averaged over the block's neighbourhood without the block.
pub fn block_rates(pilot: &Accumulation, grid: BlockGrid) -> Vec<u32> {
    let (w, h) = (grid.width as usize, grid.height as usize);
    let spreads = pilot.half_spreads();
    // Summed-area table of the per-pixel noise, (h + 1) x (w + 1).
    let mut table = vec![0.0f64; (w + 1) * (h + 1)];
    for y in 0..h {
        let mut row = 0.0f64;
        for x in 0..w {
            let e = spreads[y * w + x];
            row += if e.is_finite() { e } else { 0.0 };
            table[(y + 1) * (w + 1) + x + 1] = table[y * (w + 1) + x + 1] + row;
        }
    }
    let rect = |x0: usize, x1: usize, y0: usize, y1: usize| {
        table[y1 * (w + 1) + x1] - table[y0 * (w + 1) + x1] - table[y1 * (w + 1) + x0] + table[y0 * (w + 1) + x0]
    };
    let noise: Vec<f64> = (0..grid.count())
        .map(|key| {
            let (y, cols) = grid.pixels(key);
            let (y, x0, x1) = (y as usize, cols.start as usize, cols.end as usize);
            let wy0 = y.saturating_sub(WINDOW_ROWS_ABOVE as usize);
            let wy1 = (y + 1 + WINDOW_ROWS_BELOW as usize).min(h);
            let wx0 = x0.saturating_sub(WINDOW_COLUMNS as usize);
            let wx1 = (x1 + WINDOW_COLUMNS as usize).min(w);
            let around = rect(wx0, wx1, wy0, wy1) - rect(x0, x1, y, y + 1);
            let n = (wx1 - wx0) * (wy1 - wy0) - (x1 - x0);
            if n > 0 { (around / n as f64).max(0.0).sqrt() } else { 0.0 }
        })
        .collect();
    // The scale: the mean noise over the blocks other than this one whose windows do not hold
    // its pixels (a global mean would let the block's own samples in through its neighbours).
    let total: f64 = noise.iter().sum();
    let per_row = grid.blocks_per_row() as usize;
    let c = grid.block.max(1) as usize;
    (0..noise.len())
        .map(|key| {
            let (y, cols) = grid.pixels(key);
            let (y, x0, x1) = (y as usize, cols.start as usize, cols.end as usize);
            let (mut near, mut near_n) = (0.0f64, 0usize);
            // Block (y2, j) sees this block if its rows reach row y and its columns overlap.
            let rows = y.saturating_sub(WINDOW_ROWS_BELOW as usize)..(y + 1 + WINDOW_ROWS_ABOVE as usize).min(h);
            let j0 = x0.saturating_sub(WINDOW_COLUMNS as usize + c - 1) / c;
            let j1 = ((x1 + WINDOW_COLUMNS as usize).div_ceil(c)).min(per_row);
            for y2 in rows {
                for j in j0..j1 {
                    let (bx0, bx1) = (j * c, ((j + 1) * c).min(w));
                    if bx0 < x1 + WINDOW_COLUMNS as usize && bx1 + WINDOW_COLUMNS as usize > x0 {
                        near += noise[y2 * per_row + j];
                        near_n += 1;
                    }
                }
            }
            let far_n = noise.len() - near_n;
            let mean = if far_n > 0 { (total - near) / far_n as f64 } else { 0.0 };
            let r = if mean > 0.0 { (RATE_MEAN * noise[key] / mean).round() } else { RATE_MEAN };
            2 * (r.min(RATE_MAX as f64) as u32).max(1)
        })
        .collect()
}

/// The samples each block takes in the round after `done` rounds-worth of `budget_left`
/// samples in total (over all pixels): its whole rate, or for the last round a share of it,
/// rounded to even, so that the run ends near its budget.
pub fn round_counts(rates: &[u32], grid: BlockGrid, budget_left: u64) -> Vec<u32> {
    let per_round = grid.pixel_samples(rates);
    if per_round == 0 || budget_left >= per_round {
        return rates.to_vec();
    }
    let share = budget_left as f64 / per_round as f64;
    rates.iter().map(|&r| 2 * ((r as f64 * share / 2.0).round() as u32)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pilot with noise `noise(x, y)` in each pixel's halves (A = 1 + n, B = 1 - n).
    fn pilot(w: u32, h: u32, noise: impl Fn(u32, u32) -> f32) -> Accumulation {
        let mut acc = Accumulation::new(w, h);
        acc.per_pixel = true;
        let half = PILOT_SPP as f64 / 2.0;
        let fixed = |x: f64| (x / super::super::accumulation::FIXED_UNIT).round() as u64;
        for y in 0..h {
            for x in 0..w {
                let p = (y * w + x) as usize;
                let n = f64::from(noise(x, y));
                acc.even[p] = [fixed((1.0 + n) * half); 3];
                acc.odd[p] = [fixed((1.0 - n) * half); 3];
                acc.counts[p] = [PILOT_SPP, 0];
            }
        }
        acc
    }

    #[test]
    fn grid_keys_match_the_shader() {
        assert_eq!(BlockGrid::new(20, 3, 1).block, 8);
        assert_eq!(BlockGrid::new(20, 3, 3).block, 9, "a block must hold whole coherence blocks");
        assert_eq!(BlockGrid::new(20, 3, 16).block, 16);
        let g = BlockGrid::new(20, 3, 8);
        assert_eq!(g.blocks_per_row(), 3);
        assert_eq!(g.count(), 9);
        assert_eq!(g.pixels(0), (0, 0..8));
        assert_eq!(g.pixels(2), (0, 16..20));
        assert_eq!(g.pixels(4), (1, 8..16));
    }

    #[test]
    fn noisier_regions_get_more_samples_and_rates_are_even() {
        let g = BlockGrid::new(64, 32, 8);
        let rates = block_rates(&pilot(64, 32, |x, _| if x < 32 { 0.05 } else { 0.4 }), g);
        assert!(rates.iter().all(|&r| r % 2 == 0 && (2..=2 * RATE_MAX).contains(&r)), "{rates:?}");
        let (calm, noisy) = (rates[0], rates[7]);
        assert!(noisy >= 4 * calm, "noisy block {noisy} vs calm {calm}");
    }

    /// The unbiasedness argument: a block's rate must not depend on its own pilot samples.
    #[test]
    fn a_block_rate_ignores_the_block_own_samples() {
        let g = BlockGrid::new(64, 32, 8);
        let base = |x: u32, y: u32| 0.05 + 0.01 * ((x * 7 + y * 3) % 11) as f32;
        let before = block_rates(&pilot(64, 32, base), g);
        // Block key 4 * 8 + 3 (row 4, pixels 24..32) turns very noisy.
        let key = 4 * 8 + 3;
        let after = block_rates(&pilot(64, 32, |x, y| if y == 4 && (24..32).contains(&x) { 5.0 } else { base(x, y) }), g);
        assert_eq!(before[key], after[key], "the block's own noise changed its rate");
        assert!(after[key - 8] > before[key - 8], "the block above did not see the noise");
    }

    #[test]
    fn the_last_round_shrinks_to_the_budget() {
        let g = BlockGrid::new(16, 1, 8);
        let rates = vec![4, 12];
        assert_eq!(round_counts(&rates, g, 1000), rates);
        // 128 per round; 64 left: half of each rate, rounded to even.
        assert_eq!(round_counts(&rates, g, 64), vec![2, 6]);
    }
}
