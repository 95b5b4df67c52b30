//! `vkrt render --shard I/N` and `--shard-from-env`: which part of a sharded run this process
//! renders (`integrator::path::shard`), from the command line or from the batch system's
//! array-job environment.

use crate::integrator::path::shard::Shard;
use anyhow::{bail, Context as _, Result};
use clap::Args;
use std::path::{Path, PathBuf};

/// The array-job variables `--shard-from-env` reads, in this order: the index, and the count
/// where the system exports one (Slurm), else from `--shard-count`.
const SLURM_ID: &str = "SLURM_ARRAY_TASK_ID";
const SLURM_MIN: &str = "SLURM_ARRAY_TASK_MIN";
const SLURM_COUNT: &str = "SLURM_ARRAY_TASK_COUNT";
const KUBERNETES_INDEX: &str = "JOB_COMPLETION_INDEX";
const AWS_BATCH_INDEX: &str = "AWS_BATCH_JOB_ARRAY_INDEX";

/// `--shard env`: the shard from the array job's environment.
const SHARD_FROM_ENV: &str = "env";

/// What `{shard}` in `-o` becomes: the shard's index.
pub const INDEX_PLACEHOLDER: &str = "{shard}";

#[derive(Debug, Args, Default)]
pub struct ShardArgs {
    /// Path tracer: render part I of N (numbered from 0) of the --spp run's sample indices and
    /// write its sums to -o, a .ckpt (`{shard}` in the name becomes I); `vkrt merge` of all N
    /// gives the same bytes as the whole run. Needs --spp; not with --adaptive, --time or
    /// --target-relmse. `env`: I and N from the array job's environment (Slurm's
    /// SLURM_ARRAY_TASK_ID less SLURM_ARRAY_TASK_MIN, and SLURM_ARRAY_TASK_COUNT; Kubernetes
    /// Indexed Jobs' JOB_COMPLETION_INDEX or AWS Batch's AWS_BATCH_JOB_ARRAY_INDEX, N from
    /// --shard-count).
    #[arg(help_heading = "Clusters", long, value_name = "I/N|env", conflicts_with = "shard_from_env")]
    pub shard: Option<String>,
    /// Path tracer: as `--shard env`, with I (and N) from the array job's environment: Slurm's
    /// SLURM_ARRAY_TASK_ID (less SLURM_ARRAY_TASK_MIN) and SLURM_ARRAY_TASK_COUNT, Kubernetes
    /// Indexed Jobs' JOB_COMPLETION_INDEX or AWS Batch's AWS_BATCH_JOB_ARRAY_INDEX (N from
    /// --shard-count).
    #[arg(hide = true, long)]
    pub shard_from_env: bool,
    /// Path tracer, --shard-from-env: the number of shards, where the environment has no count
    /// (Kubernetes, AWS Batch), or to check Slurm's.
    #[arg(hide = true, long, value_name = "N")]
    pub shard_count: Option<u32>,
}

impl ShardArgs {
    pub fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        if self.shard.is_some() {
            v.push("--shard");
        }
        if self.shard_from_env {
            v.push("--shard-from-env");
        }
        if self.shard_count.is_some() {
            v.push("--shard-count");
        }
        v
    }

    /// The (index, count) asked for, if any, reading `env` for `--shard-from-env`.
    pub fn requested(&self, env: &dyn Fn(&str) -> Option<String>) -> Result<Option<(u32, u32)>> {
        let from_env = self.shard_from_env || self.shard.as_deref() == Some(SHARD_FROM_ENV);
        if self.shard_count.is_some() && !from_env {
            bail!("--shard-count goes with --shard env (--shard I/N names the count itself)");
        }
        if let Some(text) = self.shard.as_ref().filter(|_| !from_env) {
            let (i, n) = text.split_once('/').with_context(|| format!("--shard {text}: expected I/N, e.g. 3/8"))?;
            let number = |s: &str| s.trim().parse::<u32>().with_context(|| format!("--shard {text}: '{s}' is not a whole number"));
            return Ok(Some((number(i)?, number(n)?)));
        }
        if !from_env {
            return Ok(None);
        }
        let read = |name: &str| -> Result<Option<u32>> {
            env(name).map(|v| v.trim().parse::<u32>().with_context(|| format!("{name}={v} is not a whole number"))).transpose()
        };
        if let Some(id) = read(SLURM_ID)? {
            let min = read(SLURM_MIN)?.unwrap_or(0);
            let count = match (read(SLURM_COUNT)?, self.shard_count) {
                (Some(c), Some(n)) if c != n => bail!("{SLURM_COUNT}={c} but --shard-count {n}"),
                (Some(c), _) | (None, Some(c)) => c,
                (None, None) => bail!("{SLURM_ID} is set but not {SLURM_COUNT}: give --shard-count"),
            };
            let index = id.checked_sub(min).with_context(|| format!("{SLURM_ID}={id} is below {SLURM_MIN}={min}"))?;
            return Ok(Some((index, count)));
        }
        for name in [KUBERNETES_INDEX, AWS_BATCH_INDEX] {
            if let Some(index) = read(name)? {
                let count = self.shard_count.with_context(|| format!("{name} gives the shard's index but not the count: add --shard-count N"))?;
                return Ok(Some((index, count)));
            }
        }
        bail!("--shard env: none of {SLURM_ID}, {KUBERNETES_INDEX}, {AWS_BATCH_INDEX} is set (not in an array job?)")
    }
}

/// The shard, checked against the run's other settings: `spp` is the whole run's; `timed`
/// names the stop flag other than --spp that was given (--time, --target-relmse), which a
/// shard refuses whether or not --spp is there too.
pub fn resolve(requested: Option<(u32, u32)>, spp: Option<u64>, adaptive: bool, timed: Option<&str>) -> Result<Option<Shard>> {
    let Some((index, count)) = requested else { return Ok(None) };
    if let Some(flag) = timed {
        bail!("--shard stops on --spp only: with {flag} the shards would not add up to one run (give the whole run's --spp)");
    }
    let Some(total) = spp else {
        bail!("--shard needs --spp: the whole run's samples per pixel, which the shards divide");
    };
    if adaptive {
        bail!(
            "--shard does not go with --adaptive: each shard would allocate from its own noise, so the shards \
             would not add up to one run (render the adaptive run in one process, or shard a uniform one)"
        );
    }
    Shard::new(index, count, total).map(Some)
}

/// `-o` with `{shard}` replaced by the index; for a shard it must be a .ckpt.
pub fn output_path(output: &Path, shard: Option<Shard>) -> Result<PathBuf> {
    let Some(shard) = shard else { return Ok(output.to_path_buf()) };
    let text = output.to_string_lossy().replace(INDEX_PLACEHOLDER, &shard.index.to_string());
    let path = PathBuf::from(text);
    if path.extension().and_then(|e| e.to_str()) != Some("ckpt") {
        bail!("-o {}: a shard writes its sums, a .ckpt (merge the shards into an image with `vkrt merge`)", output.display());
    }
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| vars.iter().find(|(k, _)| *k == name).map(|(_, v)| v.to_string())
    }

    #[test]
    fn shard_comes_from_the_flag_or_the_array_job() {
        let flag = ShardArgs { shard: Some("3/8".into()), ..ShardArgs::default() };
        assert_eq!(flag.requested(&env(&[])).unwrap(), Some((3, 8)));
        let from_env = ShardArgs { shard_from_env: true, ..ShardArgs::default() };
        let slurm = [(SLURM_ID, "5"), (SLURM_MIN, "1"), (SLURM_COUNT, "8")];
        assert_eq!(from_env.requested(&env(&slurm)).unwrap(), Some((4, 8)));
        assert!(from_env.requested(&env(&[(KUBERNETES_INDEX, "2")])).is_err(), "no count");
        let counted = ShardArgs { shard_from_env: true, shard_count: Some(4), ..ShardArgs::default() };
        assert_eq!(counted.requested(&env(&[(KUBERNETES_INDEX, "2")])).unwrap(), Some((2, 4)));
        assert_eq!(counted.requested(&env(&[(AWS_BATCH_INDEX, "0")])).unwrap(), Some((0, 4)));
        assert!(counted.requested(&env(&slurm)).is_err(), "count disagrees with Slurm's");
        assert!(from_env.requested(&env(&[])).is_err(), "not in an array job");
        assert!(ShardArgs { shard: Some("3".into()), ..ShardArgs::default() }.requested(&env(&[])).is_err());
    }

    #[test]
    fn shards_need_a_sample_count_and_a_checkpoint() {
        assert!(resolve(Some((0, 2)), None, false, None).is_err());
        assert!(resolve(Some((0, 2)), Some(8), true, None).is_err());
        // The flag given is the one named, with or without --spp (it said "--shard needs --spp").
        for spp in [None, Some(8)] {
            let e = resolve(Some((0, 2)), spp, false, Some("--time")).unwrap_err().to_string();
            assert!(e.contains("with --time"), "{e}");
        }
        let s = resolve(Some((1, 2)), Some(9), false, None).unwrap();
        assert_eq!(s.map(|s| s.range()), Some((4, 5)));
        assert_eq!(output_path(Path::new("part-{shard}.ckpt"), s).unwrap(), PathBuf::from("part-1.ckpt"));
        assert!(output_path(Path::new("part.exr"), s).is_err());
    }
}
