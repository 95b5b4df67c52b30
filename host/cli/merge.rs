//! `vkrt merge`: adds checkpoints of runs with different seeds, or the shards of one sharded
//! run (`vkrt render --shard`), into one image or checkpoint; one checkpoint alone becomes its
//! image. Merged shards are the same bytes as the run rendered whole.

use super::render::DisplayArgs;
use crate::integrator::path::checkpoint::Checkpoint;
use crate::output;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Checkpoints written by `vkrt render --integrator path --checkpoint`, of runs with
    /// different seeds, or every shard of one `--shard` run (one alone is turned into its image).
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// The result: an image (.png after --exposure and --tonemap, .exr or .pfm linear) or a
    /// checkpoint (.ckpt) that can be merged or resumed again.
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    #[command(flatten)]
    pub display: DisplayArgs,
}

/// Whether `path` names a checkpoint output (.ckpt).
pub fn is_checkpoint(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("ckpt"))
}

/// The checkpoints in `inputs`, read and added into the first (`Checkpoint::merge`'s rules:
/// the same render, other seeds or other shards). Shared with the Python package's `merge`.
pub fn read_and_merge(inputs: &[PathBuf]) -> Result<Checkpoint> {
    let mut iter = inputs.iter();
    let Some(first) = iter.next() else { bail!("nothing to merge") };
    let mut merged = Checkpoint::read(first)?;
    for p in iter {
        let c = Checkpoint::read(p)?;
        let names = (first.display().to_string(), p.display().to_string());
        merged.merge(&c, (&names.0, &names.1)).with_context(|| format!("merging {} into {}", p.display(), first.display()))?;
    }
    Ok(merged)
}

pub fn run(args: &MergeArgs) -> Result<()> {
    if !is_checkpoint(&args.output) {
        output::ImageFormat::from_path(&args.output).context("-o names neither an image nor a checkpoint (.ckpt)")?;
    }
    let merged = read_and_merge(&args.inputs)?;
    if let Some(missing) = merged.settings.shards.as_ref().and_then(|s| s.missing_message()) {
        if !is_checkpoint(&args.output) {
            bail!("{missing}: the shards given are not the whole run (merge them into a .ckpt to add the rest later)");
        }
        eprintln!("note: {missing}; {} holds the shards given, to merge with the rest later", args.output.display());
    }
    if is_checkpoint(&args.output) {
        merged.write(&args.output)?;
    } else {
        output::write_render(&args.output, &merged.accum.image(), &args.display.display())?;
    }
    eprintln!("merged {} checkpoint(s) (seeds {:?}): {} spp into {}", args.inputs.len(), merged.settings.seeds, merged.accum.samples, args.output.display());
    Ok(())
}
