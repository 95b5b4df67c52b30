//! `vkrt merge`: adds checkpoints of runs with different seeds into one image or checkpoint.

use crate::integrator::path::checkpoint::Checkpoint;
use crate::output;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Checkpoints written by `vkrt render --integrator path --checkpoint`.
    #[arg(required = true, num_args = 2..)]
    pub inputs: Vec<PathBuf>,
    /// The merged result: an image (.png, .exr, .pfm; float images get a PNG preview) or, with
    /// any other extension, a checkpoint that can be merged or resumed again.
    #[arg(short, long)]
    pub output: PathBuf,
}

pub fn run(args: &MergeArgs) -> Result<()> {
    let mut iter = args.inputs.iter();
    let Some(first) = iter.next() else { bail!("nothing to merge") };
    let mut merged = Checkpoint::read(first)?;
    for p in iter {
        let c = Checkpoint::read(p)?;
        merged.merge(&c).with_context(|| format!("merging {} into {}", p.display(), first.display()))?;
    }
    if output::ImageFormat::from_path(&args.output).is_ok() {
        output::write_render(&args.output, &merged.accum.image(), true)?;
    } else {
        merged.write(&args.output)?;
    }
    eprintln!(
        "merged {} runs (seeds {:?}): {} spp into {}",
        args.inputs.len(),
        merged.settings.seeds,
        merged.accum.samples,
        args.output.display()
    );
    Ok(())
}
