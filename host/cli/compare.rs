//! `vkrt compare`: error metrics of an image against a reference.

use crate::output;
use crate::output::compare::compare;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The image to judge (.exr, .pfm or .png).
    pub image: PathBuf,
    /// The reference.
    pub reference: PathBuf,
    /// Exit with an error if relMSE exceeds this.
    #[arg(long)]
    pub max_relmse: Option<f64>,
}

pub fn run(args: &CompareArgs) -> Result<()> {
    let a = output::read_image(&args.image)?;
    let b = output::read_image(&args.reference)?;
    let c = compare(&a, &b).with_context(|| format!("comparing {} with {}", args.image.display(), args.reference.display()))?;
    let (ma, mb) = (a.mean(), b.mean());
    println!("rmse      {:.6e}", c.rmse);
    println!("relmse    {:.6e}   (mean((a-b)^2 / (b^2 + 0.01)))", c.relmse);
    println!("psnr      {:.3} dB", c.psnr);
    for (k, name) in ["r", "g", "b"].iter().enumerate() {
        let rel = if mb[k] != 0.0 { format!(" ({:+.3} %)", 100.0 * c.mean_diff[k] / mb[k]) } else { String::new() };
        println!("mean {name}    {:.6} vs {:.6}: {:+.6e}{rel}", ma[k], mb[k], c.mean_diff[k]);
    }
    if let Some(max) = args.max_relmse {
        if !(c.relmse <= max) {
            bail!("relMSE {:.6e} exceeds --max-relmse {max:e}", c.relmse);
        }
    }
    Ok(())
}
