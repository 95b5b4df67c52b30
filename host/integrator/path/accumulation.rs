//! A progressive render's running sums: what the GPU accumulates, what checkpoints store and
//! what `vkrt merge` adds. The image is the sum over the sample count (a box filter: every
//! sample of a pixel lands inside it, weight 1). Sums are fixed-point integers (units of
//! 2^-ACCUM_FRACTION_BITS, `gpu_abi::constants`): adding them is exact and independent of
//! order, so a run in any number of batches, a resumed run and merged shards of a run are the
//! same bytes. Uniform runs take the same count in every pixel; adaptive runs
//! (`super::adaptive`) an even count of its own per pixel, half of it even-indexed.

use crate::gpu_abi::constants::ACCUM_FRACTION_BITS;
use crate::integrator::Image;
use anyhow::{bail, Context as _, Result};

/// Radiance of one fixed-point unit.
pub const FIXED_UNIT: f64 = 1.0 / (1u64 << ACCUM_FRACTION_BITS) as f64;

/// Pixels per chunk of the error estimate's pass (`Accumulation::estimate_relmse`): a chunk's
/// sum is one unit of work and of the fixed summation order.
const ESTIMATE_CHUNK: usize = 16384;

/// A pixel's mean: its fixed-point `sum` over `count` samples, 0 without samples.
fn mean(sum: [u64; 3], count: u64) -> [f32; 3] {
    let scale = if count > 0 { FIXED_UNIT / count as f64 } else { 0.0 };
    sum.map(|c| (c as f64 * scale) as f32)
}

/// Radiance sums per pixel, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Accumulation {
    pub width: u32,
    pub height: u32,
    /// Samples taken per pixel (from the run's first sample index on); for adaptive runs the
    /// mean over the pixels, rounded down (each pixel's own count is in `counts`).
    pub samples: u64,
    /// How many of those have an even index: the size of the first half-image (uniform runs).
    pub even_samples: u64,
    /// Fixed-point radiance sums (r, g, b) of the even-indexed samples, per pixel.
    pub even: Vec<[u64; 3]>,
    /// The same for the odd-indexed samples.
    pub odd: Vec<[u64; 3]>,
    /// Per pixel: samples taken, and how many of them were dropped (NaN, Inf or beyond the
    /// fixed-point range; they count as zero radiance).
    pub counts: Vec<[u32; 2]>,
    /// Adaptive run: each pixel has its own (even) sample count, `counts[p][0]`.
    pub per_pixel: bool,
    /// Adaptive run past its pilot: samples per round of each coherence block
    /// (`super::adaptive::block_rates`); empty otherwise.
    pub rates: Vec<u32>,
}

/// Even sample indices in `first .. first + n`.
pub fn even_indices(first: u64, n: u64) -> u64 {
    (first + n).div_ceil(2) - first.div_ceil(2)
}

impl Accumulation {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            samples: 0,
            even_samples: 0,
            even: vec![[0; 3]; n],
            odd: vec![[0; 3]; n],
            counts: vec![[0; 2]; n],
            per_pixel: false,
            rates: Vec::new(),
        }
    }

    /// Pixel p's sample count, and the even-indexed part of it.
    pub fn counts(&self, p: usize) -> (u64, u64) {
        if self.per_pixel {
            let n = u64::from(self.counts[p][0]);
            (n, n / 2)
        } else {
            (self.samples, self.even_samples)
        }
    }

    /// Each pixel's sum (of `sums`, fixed point) over its count (`count(p)`).
    fn mean_of(&self, sums: impl Iterator<Item = [u64; 3]>, count: impl Fn(usize) -> u64) -> Image {
        Image { width: self.width, height: self.height, pixels: sums.enumerate().map(|(p, s)| mean(s, count(p))).collect() }
    }

    /// Pixel p's sum over all its samples (even + odd; cannot overflow: `add` checks).
    fn total(&self, p: usize) -> [u64; 3] {
        let (e, o) = (self.even[p], self.odd[p]);
        [e[0].wrapping_add(o[0]), e[1].wrapping_add(o[1]), e[2].wrapping_add(o[2])]
    }

    /// The image: each pixel's mean sample.
    pub fn image(&self) -> Image {
        self.mean_of((0..self.even.len()).map(|p| self.total(p)), |p| self.counts(p).0)
    }

    /// The two independent half-images: even-indexed samples and odd-indexed ones.
    pub fn halves(&self) -> (Image, Image) {
        let odd = self.mean_of(self.odd.iter().copied(), |p| {
            let (n, e) = self.counts(p);
            n - e
        });
        (self.mean_of(self.even.iter().copied(), |p| self.counts(p).1), odd)
    }

    /// Estimated relMSE of `image()` against the converged image, from the spread of the two
    /// half-images A and B (independent, unbiased): E[(A - B)^2] = var(A) + var(B), and var(A)
    /// = s^2 / n_a, so var(image) = s^2 / n = E[(A - B)^2] / (n (1/n_a + 1/n_b)). The
    /// denominator uses the full image for the unknown truth, as `../shared/refs` does.
    /// Adaptive runs: the same per pixel, with each pixel's own counts. `None` until each half
    /// of every pixel has a sample.
    pub fn estimate_relmse(&self) -> Option<f64> {
        let pixels = self.even.len();
        // One pass over the sums, in chunks of ESTIMATE_CHUNK pixels on every core, each chunk's
        // sum added in chunk order: the same value whatever the thread count. It was three
        // images and a spread per pixel made one after the other, on one core: on a GPU that
        // renders 1024² at ~500 spp/s it was most of a run to a target error.
        let chunks = pixels.div_ceil(ESTIMATE_CHUNK);
        let partial = |c: usize| -> Option<f64> {
            let mut total = 0.0f64;
            for p in c * ESTIMATE_CHUNK..((c + 1) * ESTIMATE_CHUNK).min(pixels) {
                total += self.scaled_spread(p)?;
            }
            Some(total)
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(chunks);
        let sums: Vec<Option<f64>> = if threads <= 1 {
            (0..chunks).map(partial).collect()
        } else {
            let mut sums = vec![Some(0.0); chunks];
            std::thread::scope(|scope| {
                let per = chunks.div_ceil(threads);
                for (t, out) in sums.chunks_mut(per).enumerate() {
                    let partial = &partial;
                    scope.spawn(move || {
                        for (i, o) in out.iter_mut().enumerate() {
                            *o = partial(t * per + i);
                        }
                    });
                }
            });
            sums
        };
        let mut total = 0.0f64;
        for s in sums {
            total += s?;
        }
        Some(total / (pixels * 3).max(1) as f64)
    }

    /// Pixel p's term of [`Self::estimate_relmse`]: its [`Self::spread`] over
    /// n (1/n_a + 1/n_b). None while a half has no sample.
    fn scaled_spread(&self, p: usize) -> Option<f64> {
        let (n, na) = self.counts(p);
        let nb = n - na;
        if na == 0 || nb == 0 {
            return None;
        }
        Some(self.spread(p) / (n as f64 * (1.0 / na as f64 + 1.0 / nb as f64)))
    }

    /// Pixel p's half-images' spread relative to the image: the sum over the channels of
    /// (A - B)^2 / (F^2 + 0.01), F the full image (the relMSE's denominator, as
    /// `../shared/refs` defines it), from the pixel's sums alone.
    fn spread(&self, p: usize) -> f64 {
        let (n, na) = self.counts(p);
        let (a, b, f) = (mean(self.even[p], na), mean(self.odd[p], n - na), mean(self.total(p), n));
        (0..3)
            .map(|c| {
                let d = (a[c] - b[c]) as f64;
                let f = f[c] as f64;
                d * d / (f * f + 0.01)
            })
            .sum()
    }

    /// Per pixel, the two half-images' spread relative to the image ([`Self::spread`]): what
    /// `estimate_relmse` averages and adaptive sampling maps.
    pub fn half_spreads(&self) -> Vec<f64> {
        (0..self.even.len()).map(|p| self.spread(p)).collect()
    }

    /// Samples dropped as NaN, infinite or out of range, over all pixels.
    pub fn nonfinite_samples(&self) -> u64 {
        self.counts.iter().map(|c| u64::from(c[1])).sum()
    }

    /// Fails if a pixel's even and odd sums together would not fit the fixed-point range.
    pub fn check_range(&self) -> Result<()> {
        for (p, (e, o)) in self.even.iter().zip(&self.odd).enumerate() {
            if (0..3).any(|c| e[c].checked_add(o[c]).is_none()) {
                bail!("pixel {p}: its radiance sum overflows the fixed-point sums (2^40)");
            }
        }
        Ok(())
    }

    /// Adds another run's sums (another seed, or other sample indices of the same seed: a
    /// shard): exactly the run that took both sets of samples, bit for bit.
    pub fn add(&mut self, other: &Accumulation) -> Result<()> {
        if (self.width, self.height) != (other.width, other.height) {
            bail!("image sizes differ: {}x{} and {}x{}", self.width, self.height, other.width, other.height);
        }
        if self.per_pixel != other.per_pixel {
            bail!("one run is adaptive and the other is not");
        }
        let overflow = || anyhow::anyhow!("the merged sums overflow the fixed-point range");
        for (a, b) in self.even.iter_mut().zip(&other.even).chain(self.odd.iter_mut().zip(&other.odd)) {
            for c in 0..3 {
                a[c] = a[c].checked_add(b[c]).ok_or_else(overflow)?;
            }
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            for c in 0..2 {
                a[c] = a[c].checked_add(b[c]).context("a pixel's sample count passes 2^32")?;
            }
        }
        self.check_range()?;
        self.samples += other.samples;
        self.even_samples += other.even_samples;
        // Each run's allocation was its own: the merged sums cannot go on with either.
        self.rates.clear();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_split_the_sum_and_the_estimate_sees_noise() {
        let mut acc = Accumulation::new(2, 1);
        let fixed = |x: f64| (x / FIXED_UNIT) as u64;
        // Pixel 0: samples 1 (even) and 3 (odd); pixel 1: 2 and 2.
        acc.samples = 2;
        acc.even_samples = 1;
        acc.even = vec![[fixed(1.0); 3], [fixed(2.0); 3]];
        acc.odd = vec![[fixed(3.0); 3], [fixed(2.0); 3]];
        assert_eq!(acc.image().pixels, vec![[2.0; 3], [2.0; 3]]);
        let (a, b) = acc.halves();
        assert_eq!(a.pixels, vec![[1.0; 3], [2.0; 3]]);
        assert_eq!(b.pixels, vec![[3.0; 3], [2.0; 3]]);
        // Pixel 0: (1 - 3)^2 / (4 + 0.01); pixel 1: 0; mean over 6 channel values, over n (1 + 1).
        let want = (3.0 * 4.0 / 4.01) / 6.0 / 4.0;
        let got = acc.estimate_relmse().unwrap_or(f64::NAN);
        assert!((got - want).abs() < 1e-9, "estimate {got}, want {want}");
    }

    /// The chunked pass gives the mean of `half_spreads` over n (1/n_a + 1/n_b), on an image of
    /// several chunks with per-pixel counts (an adaptive run), and None while a half is empty.
    #[test]
    fn the_chunked_estimate_is_the_mean_of_the_spreads() {
        let (w, h) = (300u32, 200u32);
        let n = (w * h) as usize;
        assert!(n > 3 * ESTIMATE_CHUNK);
        let mut rng = crate::rng::Pcg32::new(5);
        let mut acc = Accumulation::new(w, h);
        acc.per_pixel = true;
        for p in 0..n {
            let count = 2 * (1 + rng.next_u32() % 8);
            acc.counts[p] = [count, 0];
            for c in 0..3 {
                acc.even[p][c] = u64::from(rng.next_u32() % 1_000_000) * u64::from(count);
                acc.odd[p][c] = u64::from(rng.next_u32() % 1_000_000) * u64::from(count);
            }
        }
        let spreads = acc.half_spreads();
        let want: f64 = spreads
            .iter()
            .enumerate()
            .map(|(p, s)| {
                let (n, na) = acc.counts(p);
                s / (n as f64 * (1.0 / na as f64 + 1.0 / (n - na) as f64))
            })
            .sum::<f64>()
            / (3 * n) as f64;
        let got = acc.estimate_relmse().unwrap_or(f64::NAN);
        assert!((got - want).abs() <= 1e-12 * want, "estimate {got}, want {want}");
        acc.counts[n - 1] = [0, 0];
        assert_eq!(acc.estimate_relmse(), None, "a pixel without samples has no estimate yet");
    }

    #[test]
    fn merging_is_exact_in_any_order() {
        let part = |k: u64| {
            let mut a = Accumulation::new(1, 1);
            a.even = vec![[k * 1_000_003, k, u64::from(k == 2)]];
            a.odd = vec![[k * 7, 3 * k, 0]];
            a.counts = vec![[k as u32, 0]];
            a.samples = k;
            a
        };
        let (mut left, mut right) = (part(1), part(3));
        left.add(&part(2)).unwrap();
        left.add(&part(3)).unwrap();
        right.add(&part(2)).unwrap();
        right.add(&part(1)).unwrap();
        assert_eq!(left, right);
        let mut full = part(1);
        full.even[0][0] = u64::MAX;
        assert!(full.add(&part(1)).is_err(), "an overflowing merge must fail");
    }

    #[test]
    fn even_indices_count_from_any_first_sample() {
        assert_eq!(even_indices(0, 5), 3);
        assert_eq!(even_indices(1, 5), 2);
        assert_eq!(even_indices(4, 0), 0);
        assert_eq!(even_indices(3, 4), 2);
    }
}
