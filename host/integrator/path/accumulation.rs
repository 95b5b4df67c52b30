//! A progressive render's running sums: what the GPU accumulates, what checkpoints store and
//! what `vkrt merge` adds. The image is the sum over the sample count (a box filter: every
//! sample of a pixel lands inside it, weight 1). Uniform runs take the same count in every
//! pixel; adaptive runs (`super::adaptive`) an even count of its own per pixel, kept in
//! `even[p][3]`, half of it even-indexed.

use crate::integrator::Image;
use anyhow::{bail, Result};

/// Radiance sums per pixel, row 0 at the top.
#[derive(Debug, Clone, PartialEq)]
pub struct Accumulation {
    pub width: u32,
    pub height: u32,
    /// Samples taken per pixel (sample indices 0 .. samples of each seed); for adaptive runs
    /// the mean over the pixels, rounded down (the counts are in `even[p][3]`).
    pub samples: u64,
    /// Samples whose index is even, per pixel: the size of the first half-image (uniform runs).
    pub even_samples: u64,
    /// rgb: radiance sum of all samples; w: samples dropped as NaN or infinite.
    pub sum: Vec<[f32; 4]>,
    /// rgb: radiance sum of the even-indexed samples; w: the pixel's sample count.
    pub even: Vec<[f32; 4]>,
    /// Adaptive run: each pixel has its own (even) sample count, `even[p][3]`.
    pub per_pixel: bool,
    /// Adaptive run past its pilot: samples per round of each coherence block
    /// (`super::adaptive::block_rates`); empty otherwise.
    pub rates: Vec<u32>,
}

impl Accumulation {
    pub fn new(width: u32, height: u32) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            samples: 0,
            even_samples: 0,
            sum: vec![[0.0; 4]; n],
            even: vec![[0.0; 4]; n],
            per_pixel: false,
            rates: Vec::new(),
        }
    }

    /// Pixel p's sample count, and the even-indexed part of it.
    pub fn counts(&self, p: usize) -> (u64, u64) {
        if self.per_pixel {
            let n = self.even[p][3] as u64;
            (n, n / 2)
        } else {
            (self.samples, self.even_samples)
        }
    }

    /// Each pixel's sum (of `sums`) over its count (`count(p)`).
    fn mean_of(&self, sums: impl Iterator<Item = [f32; 3]>, count: impl Fn(usize) -> u64) -> Image {
        Image {
            width: self.width,
            height: self.height,
            pixels: sums
                .enumerate()
                .map(|(p, s)| {
                    let n = count(p);
                    let inv = if n > 0 { 1.0 / n as f64 } else { 0.0 };
                    s.map(|c| (c as f64 * inv) as f32)
                })
                .collect(),
        }
    }

    /// The image: each pixel's mean sample.
    pub fn image(&self) -> Image {
        self.mean_of(self.sum.iter().map(|s| [s[0], s[1], s[2]]), |p| self.counts(p).0)
    }

    /// The two independent half-images: even-indexed samples and odd-indexed ones.
    pub fn halves(&self) -> (Image, Image) {
        let odd = self.sum.iter().zip(&self.even).map(|(s, e)| [s[0] - e[0], s[1] - e[1], s[2] - e[2]]);
        let odd = self.mean_of(odd, |p| {
            let (n, e) = self.counts(p);
            n - e
        });
        (self.mean_of(self.even.iter().map(|e| [e[0], e[1], e[2]]), |p| self.counts(p).1), odd)
    }

    /// Estimated relMSE of `image()` against the converged image, from the spread of the two
    /// half-images A and B (independent, unbiased): E[(A - B)^2] = var(A) + var(B), and var(A)
    /// = s^2 / n_a, so var(image) = s^2 / n = E[(A - B)^2] / (n (1/n_a + 1/n_b)). The
    /// denominator uses the full image for the unknown truth, as `../shared/refs` does.
    /// Adaptive runs: the same per pixel, with each pixel's own counts. `None` until each half
    /// of every pixel has a sample.
    pub fn estimate_relmse(&self) -> Option<f64> {
        let spreads = self.half_spreads();
        let mut total = 0.0f64;
        for (p, spread) in spreads.iter().enumerate() {
            let (n, na) = self.counts(p);
            let nb = n - na;
            if na == 0 || nb == 0 {
                return None;
            }
            total += spread / (n as f64 * (1.0 / na as f64 + 1.0 / nb as f64));
        }
        Some(total / (spreads.len() * 3).max(1) as f64)
    }

    /// Per pixel, the two half-images' spread relative to the image: the sum over the channels
    /// of (A - B)^2 / (F^2 + 0.01), F the full image (the relMSE's denominator, as
    /// `../shared/refs` defines it). What `estimate_relmse` averages and adaptive sampling maps.
    pub fn half_spreads(&self) -> Vec<f64> {
        let (a, b) = self.halves();
        let full = self.image();
        a.pixels
            .iter()
            .zip(&b.pixels)
            .zip(&full.pixels)
            .map(|((pa, pb), pf)| {
                (0..3)
                    .map(|c| {
                        let d = (pa[c] - pb[c]) as f64;
                        let f = pf[c] as f64;
                        d * d / (f * f + 0.01)
                    })
                    .sum()
            })
            .collect()
    }

    /// Samples dropped as NaN or infinite, over all pixels.
    pub fn nonfinite_samples(&self) -> u64 {
        self.sum.iter().map(|s| s[3] as u64).sum()
    }

    /// Adds another run's sums (made with another seed) to this one: the result is exactly the
    /// run that took both sets of samples.
    pub fn add(&mut self, other: &Accumulation) -> Result<()> {
        if (self.width, self.height) != (other.width, other.height) {
            bail!("image sizes differ: {}x{} and {}x{}", self.width, self.height, other.width, other.height);
        }
        if self.per_pixel != other.per_pixel {
            bail!("one run is adaptive and the other is not");
        }
        for (a, b) in self.sum.iter_mut().zip(&other.sum).chain(self.even.iter_mut().zip(&other.even)) {
            for c in 0..4 {
                a[c] = (a[c] as f64 + b[c] as f64) as f32;
            }
        }
        self.samples += other.samples;
        self.even_samples += other.even_samples;
        // Each seed's allocation was its own: the merged sums cannot go on with either.
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
        // Pixel 0: samples 1 (even) and 3 (odd); pixel 1: 2 and 2.
        acc.samples = 2;
        acc.even_samples = 1;
        acc.sum = vec![[4.0, 4.0, 4.0, 0.0], [4.0, 4.0, 4.0, 0.0]];
        acc.even = vec![[1.0, 1.0, 1.0, 0.0], [2.0, 2.0, 2.0, 0.0]];
        assert_eq!(acc.image().pixels, vec![[2.0; 3], [2.0; 3]]);
        let (a, b) = acc.halves();
        assert_eq!(a.pixels, vec![[1.0; 3], [2.0; 3]]);
        assert_eq!(b.pixels, vec![[3.0; 3], [2.0; 3]]);
        // Pixel 0: (1 - 3)^2 / (4 + 0.01); pixel 1: 0; mean over 6 channel values, over n (1 + 1).
        let want = (3.0 * 4.0 / 4.01) / 6.0 / 4.0;
        let got = acc.estimate_relmse().unwrap_or(f64::NAN);
        assert!((got - want).abs() < 1e-9, "estimate {got}, want {want}");
    }
}
