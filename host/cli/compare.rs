//! `vkrt compare`: error metrics of an image against a reference, as text or JSON, and a
//! false-colour picture of where they differ.

use crate::integrator::Image;
use crate::output;
use crate::output::compare::{compare, Comparison};
use crate::output::heatmap;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The image to judge (.exr, .pfm or .png).
    pub image: PathBuf,
    /// The reference.
    pub reference: PathBuf,
    /// Exit with an error if relMSE exceeds this; the output ends with a verdict line (`pass`
    /// or `FAIL`, and `"pass"` in --json).
    #[arg(long, value_name = "RELMSE")]
    pub max_relmse: Option<f64>,
    /// Write where the images differ as a false-colour PNG: each pixel's relative squared error
    /// (the relMSE's terms, summed over the channels) on a viridis scale, with a legend in
    /// units of 1e-4 (it says so), capped at the 99th percentile.
    #[arg(long, value_name = "OUT.png")]
    pub diff: Option<PathBuf>,
    /// Print the metrics as one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Box-filter IMAGE down to the reference's size first: IMAGE must be a whole multiple of
    /// it (e.g. a 1024² render against a 512² reference). Under a box pixel filter the mean of
    /// k x k pixels is the k-times-larger pixel, so the comparison is fair; its relMSE is about
    /// 1/k² of the full-size image's, since k² pixels' independent noise averages out.
    #[arg(long)]
    pub downsample: bool,
}

/// The `--diff` picture's unit: its legend counts relative squared error in 1e-4.
const DIFF_UNITS: f64 = 1e4;

/// Each pixel's sum over the channels of (a - b)^2 / (b^2 + 0.01): what the relMSE averages.
pub fn relative_errors(a: &Image, b: &Image) -> Vec<f64> {
    a.pixels.iter().zip(&b.pixels).map(|(p, q)| (0..3).map(|c| (p[c] as f64 - q[c] as f64).powi(2) / ((q[c] as f64).powi(2) + 0.01)).sum()).collect()
}

/// Whether an image file holds display-referred values (an 8-bit picture, tone-mapped and
/// encoded for a screen) rather than linear radiance (.exr, .pfm).
fn is_display_referred(path: &std::path::Path) -> bool {
    output::ImageFormat::from_path(path).ok() == Some(output::ImageFormat::Png)
}

fn json(c: &Comparison, a: &Image, b: &Image, pass: Option<bool>) -> String {
    let (ma, mb) = (a.mean(), b.mean());
    let num = |x: f64| if x.is_finite() { format!("{x:e}") } else { "null".to_string() };
    let triple = |v: [f64; 3]| format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]));
    format!(
        "{{\"width\": {}, \"height\": {}, \"rmse\": {}, \"relmse\": {}, \"psnr\": {}, \"max_abs\": {}, \"mean\": {}, \"reference_mean\": {}, \"mean_diff\": {}{}}}",
        a.width,
        a.height,
        num(c.rmse),
        num(c.relmse),
        num(c.psnr),
        num(c.max_abs),
        triple(ma),
        triple(mb),
        triple(c.mean_diff),
        pass.map_or(String::new(), |p| format!(", \"pass\": {p}"))
    )
}

pub fn run(args: &CompareArgs) -> Result<()> {
    let mut a = output::read_image(&args.image)?;
    let b = output::read_image(&args.reference)?;
    if is_display_referred(&args.image) != is_display_referred(&args.reference) {
        let (png, linear) = if is_display_referred(&args.image) { (&args.image, &args.reference) } else { (&args.reference, &args.image) };
        eprintln!(
            "warning: {} is an 8-bit picture (tone-mapped and encoded for display) and {} holds linear radiance: \
             their numbers differ even for the same render; compare the .exr or .pfm outputs",
            png.display(),
            linear.display()
        );
    }
    if !args.downsample && (a.width, a.height) != (b.width, b.height) {
        let k = a.width / b.width.max(1);
        let hint = if k > 1 && a.width == k * b.width && a.height == k * b.height {
            format!("; it is {k}x the reference's size: --downsample averages it down to it")
        } else {
            String::new()
        };
        bail!(
            "{} is {}x{} and the reference {} is {}x{}: images compare pixel by pixel{hint}",
            args.image.display(),
            a.width,
            a.height,
            args.reference.display(),
            b.width,
            b.height
        );
    }
    if args.downsample {
        let k = a.width / b.width.max(1);
        if k == 0 || a.width != k * b.width || a.height != k * b.height {
            bail!("--downsample: {} is {}x{}, not a whole multiple of the reference's {}x{}", args.image.display(), a.width, a.height, b.width, b.height);
        }
        a = a.box_downsample(k);
    }
    let c = compare(&a, &b).with_context(|| format!("comparing {} with {}", args.image.display(), args.reference.display()))?;
    if let Some(path) = &args.diff {
        if output::ImageFormat::from_path(path).ok() != Some(output::ImageFormat::Png) {
            bail!("--diff {}: the difference picture is a .png", path.display());
        }
        // In units of 1e-4 (the legend's numbers), capped at the 99th percentile so that a few
        // fireflies do not wash the picture out.
        let units: Vec<f64> = relative_errors(&a, &b).iter().map(|e| if e.is_finite() { e * DIFF_UNITS } else { 0.0 }).collect();
        let mut sorted = units.clone();
        sorted.sort_by(f64::total_cmp);
        let cap = sorted.get(sorted.len().saturating_sub(1) * 99 / 100).copied().unwrap_or(0.0).max(1.0);
        let counts: Vec<u32> = units.iter().map(|u| u.min(cap).round() as u32).collect();
        heatmap::write(path, &counts, a.width, a.height, "relative squared error in 1e-4").with_context(|| format!("--diff {}", path.display()))?;
    }
    let pass = args.max_relmse.map(|max| c.relmse <= max);
    if args.json {
        println!("{}", json(&c, &a, &b, pass));
    } else {
        let (ma, mb) = (a.mean(), b.mean());
        println!("rmse      {:.6e}", c.rmse);
        println!("relmse    {:.6e}   (mean((a-b)^2 / (b^2 + 0.01)))", c.relmse);
        println!("psnr      {:.3} dB", c.psnr);
        for (k, name) in ["r", "g", "b"].iter().enumerate() {
            let rel = if mb[k] != 0.0 { format!(" ({:+.3} %)", 100.0 * c.mean_diff[k] / mb[k]) } else { String::new() };
            println!("mean {name}    {:.6} vs {:.6}: {:+.6e}{rel}", ma[k], mb[k], c.mean_diff[k]);
        }
        if let (Some(max), Some(pass)) = (args.max_relmse, pass) {
            let (word, rel) = if pass { ("pass", "<=") } else { ("FAIL", ">") };
            println!("verdict   {word}: relMSE {:.6e} {rel} --max-relmse {max:e}", c.relmse);
        }
    }
    if let Some(max) = args.max_relmse {
        if !(c.relmse <= max) {
            bail!("relMSE {:.6e} exceeds --max-relmse {max:e}", c.relmse);
        }
    }
    Ok(())
}
