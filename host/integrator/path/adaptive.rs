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
/// Row blocks: pixel rows and columns around a block that its noise estimate looks at.
const ROW_WINDOW_ABOVE: u32 = 3;
const ROW_WINDOW_BELOW: u32 = 4;
const ROW_WINDOW_COLUMNS: u32 = 4;

/// The allocation blocks of an image, keyed as shaders/path.comp's `adaptive_block_key`: runs
/// of `block_w` pixels in a row (`block_h` 1; `sample_key` with `block_w` for the coherence), or
/// with scattered coherence the `block_w` x `block_h` squares its groups are dealt over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BlockGrid {
    pub width: u32,
    pub height: u32,
    pub block_w: u32,
    pub block_h: u32,
}

/// The fewest pixels in a block: a workgroup row, which lavapipe runs as one SIMD subgroup
/// whose lanes would otherwise wait for the lane with the most samples (measured: 7 % more
/// time per sample with 1-pixel blocks). Fixed, not the device's subgroup size: the blocks
/// decide which samples each pixel takes, so they must not change from device to device.
pub const MIN_BLOCK: u32 = 8;

/// A block's pixels: columns `xs` of rows `ys`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockPixels {
    pub xs: std::ops::Range<u32>,
    pub ys: std::ops::Range<u32>,
}

impl BlockPixels {
    pub fn len(&self) -> usize {
        self.xs.len() * self.ys.len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl BlockGrid {
    /// Blocks of whole coherence blocks: with scattered coherence
    /// (`super::coherence::block_bits` > 0) the `coherence_block` squares, else runs of whole
    /// groups in a row, at least `MIN_BLOCK` pixels wide.
    pub fn new(width: u32, height: u32, coherence: u32, coherence_block: u32) -> Self {
        if super::coherence::block_bits(coherence, coherence_block) > 0 {
            return Self { width, height, block_w: coherence_block, block_h: coherence_block };
        }
        let c = coherence.max(1);
        Self { width, height, block_w: c * MIN_BLOCK.div_ceil(c), block_h: 1 }
    }
    pub fn blocks_per_row(&self) -> u32 {
        self.width.div_ceil(self.block_w.max(1))
    }
    pub fn block_rows(&self) -> u32 {
        self.height.div_ceil(self.block_h.max(1))
    }
    pub fn count(&self) -> usize {
        self.blocks_per_row() as usize * self.block_rows() as usize
    }
    /// Samples over all pixels when block k takes `per_block[k]` samples in each of its pixels.
    pub fn pixel_samples(&self, per_block: &[u32]) -> u64 {
        per_block.iter().enumerate().map(|(k, &n)| n as u64 * self.pixels(k).len() as u64).sum()
    }
    /// Block `key`'s pixels.
    pub fn pixels(&self, key: usize) -> BlockPixels {
        let per_row = self.blocks_per_row() as usize;
        let (bw, bh) = (self.block_w.max(1), self.block_h.max(1));
        let (by, bx) = ((key / per_row) as u32, (key % per_row) as u32);
        BlockPixels { xs: bx * bw..((bx + 1) * bw).min(self.width), ys: by * bh..((by + 1) * bh).min(self.height) }
    }
    /// How far a block's noise window reaches past it: (left, right, up, down) in pixels.
    /// Rows look a few rows up and down; squares half a square all round.
    fn window_reach(&self) -> (u32, u32, u32, u32) {
        if self.block_h <= 1 {
            (ROW_WINDOW_COLUMNS, ROW_WINDOW_COLUMNS, ROW_WINDOW_ABOVE, ROW_WINDOW_BELOW)
        } else {
            let r = (self.block_w / 2).max(1);
            (r, r, r, r)
        }
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
    let rect =
        |x0: usize, x1: usize, y0: usize, y1: usize| table[y1 * (w + 1) + x1] - table[y0 * (w + 1) + x1] - table[y1 * (w + 1) + x0] + table[y0 * (w + 1) + x0];
    let (left, right, up, down) = grid.window_reach();
    let (left, right, up, down) = (left as usize, right as usize, up as usize, down as usize);
    let noise: Vec<f64> = (0..grid.count())
        .map(|key| {
            let b = grid.pixels(key);
            let (x0, x1, y0, y1) = (b.xs.start as usize, b.xs.end as usize, b.ys.start as usize, b.ys.end as usize);
            let (wx0, wx1) = (x0.saturating_sub(left), (x1 + right).min(w));
            let (wy0, wy1) = (y0.saturating_sub(up), (y1 + down).min(h));
            let around = rect(wx0, wx1, wy0, wy1) - rect(x0, x1, y0, y1);
            let n = (wx1 - wx0) * (wy1 - wy0) - (x1 - x0) * (y1 - y0);
            if n > 0 {
                (around / n as f64).max(0.0).sqrt()
            } else {
                0.0
            }
        })
        .collect();
    // The scale: the mean over the blocks other than this one whose windows do not hold its
    // pixels (a global mean would let the block's own samples in through its neighbours).
    let total: f64 = noise.iter().sum();
    let (per_row, rows) = (grid.blocks_per_row() as usize, grid.block_rows() as usize);
    let (bw, bh) = (grid.block_w.max(1) as usize, grid.block_h.max(1) as usize);
    (0..noise.len())
        .map(|key| {
            let b = grid.pixels(key);
            let (x0, x1, y0, y1) = (b.xs.start as usize, b.xs.end as usize, b.ys.start as usize, b.ys.end as usize);
            // Block (i, j) sees this one if its window, its pixels widened by the reach,
            // overlaps this block's pixels.
            let (mut near, mut near_n) = (0.0f64, 0usize);
            let (j0, j1) = (x0.saturating_sub(right) / bw, ((x1 + left).div_ceil(bw)).min(per_row));
            let (i0, i1) = (y0.saturating_sub(down) / bh, ((y1 + up).div_ceil(bh)).min(rows));
            for i in i0..i1 {
                for j in j0..j1 {
                    let (bx0, bx1) = (j * bw, ((j + 1) * bw).min(w));
                    let (by0, by1) = (i * bh, ((i + 1) * bh).min(h));
                    if bx0 < x1 + left && bx1 + right > x0 && by0 < y1 + up && by1 + down > y0 {
                        near += noise[i * per_row + j];
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

/// Each block's count at the end of a run of `budget` samples in total (over all pixels):
/// `PILOT_SPP` plus its rate times a common number of rounds t, rounded down to even after a
/// shift by the block's own phase (the golden-ratio sequence over the keys, so that blocks of
/// equal rate do not all step at the same t), with the least t whose counts reach the budget:
/// they overshoot it by about one block's step. The counts rise with the budget and do not
/// depend on how the run was cut into batches or resumed, so a run stopped at one budget and
/// resumed to a larger one ends with the very samples of a run straight to it.
pub fn final_counts(rates: &[u32], grid: BlockGrid, budget: u64) -> Vec<u32> {
    const GOLDEN: f64 = 0.618_033_988_749_894_9;
    let count_at = |t: f64, k: usize, r: u32| PILOT_SPP + 2 * (f64::from(r) * t / 2.0 + (k as f64 * GOLDEN).fract()).floor() as u32;
    let sizes: Vec<u64> = (0..rates.len()).map(|k| grid.pixels(k).len() as u64).collect();
    let total_at = |t: f64| -> u64 { rates.iter().zip(&sizes).enumerate().map(|(k, (&r, &n))| count_at(t, k, r) as u64 * n).sum() };
    let per_round = grid.pixel_samples(rates).max(1);
    // Bisection on t: below `lo` the counts fall short of the budget, at `hi` they reach it.
    let (mut lo, mut hi) = (0.0f64, budget as f64 / per_round as f64 + 1.0);
    if total_at(lo) >= budget {
        hi = 0.0;
    }
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if total_at(mid) >= budget {
            hi = mid
        } else {
            lo = mid
        }
    }
    rates.iter().enumerate().map(|(k, &r)| count_at(hi, k, r)).collect()
}

/// The samples each block takes in the next round, having taken `done`: its rate, but at most
/// what brings it to its count `end` at the end of the run ([`final_counts`]; none for a run
/// stopped by time or error). Even, since rates and counts are.
pub fn round_counts(rates: &[u32], done: &[u32], end: Option<&[u32]>) -> Vec<u32> {
    match end {
        None => rates.to_vec(),
        Some(end) => end.iter().zip(rates).zip(done).map(|((&e, &r), &d)| r.min(e.saturating_sub(d))).collect(),
    }
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
        assert_eq!(BlockGrid::new(20, 3, 1, 0).block_w, 8);
        assert_eq!(BlockGrid::new(20, 3, 3, 0).block_w, 9, "a block must hold whole coherence blocks");
        assert_eq!(BlockGrid::new(20, 3, 16, 0).block_w, 16);
        let g = BlockGrid::new(20, 3, 8, 0);
        assert_eq!(g.blocks_per_row(), 3);
        assert_eq!(g.count(), 9);
        assert_eq!(g.pixels(0), BlockPixels { xs: 0..8, ys: 0..1 });
        assert_eq!(g.pixels(2), BlockPixels { xs: 16..20, ys: 0..1 });
        assert_eq!(g.pixels(4), BlockPixels { xs: 8..16, ys: 1..2 });
        // Scattered coherence: the squares its groups are dealt over, cut at the image's edge.
        let s = BlockGrid::new(40, 20, 8, 16);
        assert_eq!((s.block_w, s.block_h, s.blocks_per_row(), s.block_rows(), s.count()), (16, 16, 3, 2, 6));
        assert_eq!(s.pixels(4), BlockPixels { xs: 16..32, ys: 16..20 });
        assert_eq!(s.pixel_samples(&[1; 6]), 800);
        // --coherence 1 ignores the block: rows of 8.
        assert_eq!(BlockGrid::new(40, 20, 1, 16).block_h, 1);
    }

    #[test]
    fn noisier_regions_get_more_samples_and_rates_are_even() {
        let g = BlockGrid::new(64, 32, 8, 0);
        let rates = block_rates(&pilot(64, 32, |x, _| if x < 32 { 0.05 } else { 0.4 }), g);
        assert!(rates.iter().all(|&r| r % 2 == 0 && (2..=2 * RATE_MAX).contains(&r)), "{rates:?}");
        let (calm, noisy) = (rates[0], rates[7]);
        assert!(noisy >= 4 * calm, "noisy block {noisy} vs calm {calm}");
    }

    /// The unbiasedness argument: a block's rate must not depend on its own pilot samples.
    #[test]
    fn a_block_rate_ignores_the_block_own_samples() {
        let g = BlockGrid::new(64, 32, 8, 0);
        let base = |x: u32, y: u32| 0.05 + 0.01 * ((x * 7 + y * 3) % 11) as f32;
        let before = block_rates(&pilot(64, 32, base), g);
        // Block key 4 * 8 + 3 (row 4, pixels 24..32) turns very noisy.
        let key = 4 * 8 + 3;
        let after = block_rates(&pilot(64, 32, |x, y| if y == 4 && (24..32).contains(&x) { 5.0 } else { base(x, y) }), g);
        assert_eq!(before[key], after[key], "the block's own noise changed its rate");
        assert!(after[key - 8] > before[key - 8], "the block above did not see the noise");
    }

    /// The same for squares: the square's own noise does not move its rate; the noise shows
    /// in the rates of the squares around it.
    #[test]
    fn a_square_block_rate_ignores_the_block_own_samples() {
        let g = BlockGrid::new(64, 64, 8, 16);
        let base = |x: u32, y: u32| 0.05 + 0.01 * ((x * 7 + y * 3) % 11) as f32;
        let before = block_rates(&pilot(64, 64, base), g);
        // Square (1, 1): pixels 16..32 x 16..32, key 5.
        let inside = |x: u32, y: u32| (16..32).contains(&x) && (16..32).contains(&y);
        let after = block_rates(&pilot(64, 64, |x, y| if inside(x, y) { 5.0 } else { base(x, y) }), g);
        assert_eq!(before[5], after[5], "the square's own noise changed its rate");
        for k in [1, 4, 6, 9] {
            assert!(after[k] > before[k], "square {k} beside the noisy one did not see it: {} -> {}", before[k], after[k]);
        }
    }

    #[test]
    fn the_last_round_shrinks_to_the_budget() {
        let g = BlockGrid::new(16, 1, 8, 0);
        let rates = vec![4, 12];
        let pilot = vec![PILOT_SPP; 2];
        // 8 px per block: 128 samples the pilot, 128 per round.
        assert_eq!(round_counts(&rates, &pilot, None), rates);
        assert_eq!(round_counts(&rates, &pilot, Some(&final_counts(&rates, g, 128 + 1000))), rates);
        // Half a round left: about half of each rate, in even counts that reach the budget.
        let end = final_counts(&rates, g, 128 + 64);
        assert!(g.pixel_samples(&end) >= 128 + 64 && g.pixel_samples(&end) <= 128 + 64 + 16, "{end:?}");
        assert!(end[0] <= PILOT_SPP + 4 && end[1] <= PILOT_SPP + 8 && end.iter().all(|c| c % 2 == 0), "{end:?}");
        let next = round_counts(&rates, &pilot, Some(&end));
        assert_eq!(next, vec![end[0] - PILOT_SPP, end[1] - PILOT_SPP]);
        assert_eq!(round_counts(&rates, &end, Some(&end)), vec![0, 0]);
    }

    /// The end of a run depends on its budget alone: stopping at one budget and going on to a
    /// larger one takes each block to the same count as going there at once, and the counts
    /// reach the budget by less than one step of a block.
    #[test]
    fn final_counts_rise_with_the_budget_and_ignore_how_the_run_was_cut() {
        let g = BlockGrid::new(72, 40, 8, 16);
        let rates: Vec<u32> = (0..g.count()).map(|k| 2 * (1 + (k as u32 * 7) % 16)).collect();
        let pixels = 72 * 40u64;
        let run = |done: &mut Vec<u32>, budget: u64| loop {
            let next = round_counts(&rates, done, Some(&final_counts(&rates, g, budget)));
            if next.iter().all(|&c| c == 0) {
                break;
            }
            for (d, c) in done.iter_mut().zip(next) {
                *d += c;
            }
        };
        let mut previous = vec![PILOT_SPP; g.count()];
        for spp in [9u64, 13, 16, 24, 31, 64] {
            let end = final_counts(&rates, g, spp * pixels);
            assert!(end.iter().zip(&previous).all(|(a, b)| a >= b), "counts fell from a budget to a larger one");
            let total = g.pixel_samples(&end);
            assert!(total >= spp * pixels && total < spp * pixels + 2 * 256, "{total} samples for {spp} spp");
            let mut straight = vec![PILOT_SPP; g.count()];
            run(&mut straight, spp * pixels);
            assert_eq!(straight, end);
            let mut cut = vec![PILOT_SPP; g.count()];
            run(&mut cut, 11 * pixels);
            run(&mut cut, spp.max(11) * pixels);
            assert_eq!(cut, final_counts(&rates, g, spp.max(11) * pixels), "a run resumed at {spp} spp ended elsewhere");
            previous = end;
        }
    }
}
