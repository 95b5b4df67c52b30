//! Image error metrics, as `../shared/refs/README.md` defines them.

use crate::integrator::Image;
use anyhow::{bail, Result};

/// How far an image is from a reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    pub rmse: f64,
    /// mean((a - b)^2 / (b^2 + 0.01)) over pixels and channels, b the reference.
    pub relmse: f64,
    /// 10 log10(1 / MSE), for images whose peak is 1.
    pub psnr: f64,
    /// Per-channel mean of a minus mean of b.
    pub mean_diff: [f64; 3],
    /// Largest absolute difference of any channel.
    pub max_abs: f64,
}

/// Compares `a` against the reference `b`.
pub fn compare(a: &Image, b: &Image) -> Result<Comparison> {
    if a.width != b.width || a.height != b.height {
        bail!("image sizes differ: {}x{} vs {}x{}", a.width, a.height, b.width, b.height);
    }
    let mut se = 0.0f64;
    let mut rel = 0.0f64;
    let mut max_abs = 0.0f64;
    for (pa, pb) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let (x, y) = (pa[c] as f64, pb[c] as f64);
            let d = x - y;
            se += d * d;
            rel += d * d / (y * y + 0.01);
            max_abs = max_abs.max(d.abs());
        }
    }
    let n = (a.pixels.len() * 3).max(1) as f64;
    let mse = se / n;
    let (ma, mb) = (a.mean(), b.mean());
    Ok(Comparison {
        rmse: mse.sqrt(),
        relmse: rel / n,
        psnr: if mse > 0.0 { 10.0 * (1.0 / mse).log10() } else { f64::INFINITY },
        mean_diff: [ma[0] - mb[0], ma[1] - mb[1], ma[2] - mb[2]],
        max_abs,
    })
}
