//! Sharded runs (`vkrt render --shard I/N`, `--shard env` and its older spelling `--shard-from-env`): the shards of a run, merged,
//! are the same bytes as the run rendered whole, for any shard count and any split of a --spp
//! the count does not divide; a merge of the wrong or an incomplete set of shards is a clear
//! error naming what is wrong or missing.

mod common;

use std::process::{Command, Output};

fn vkrt(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(common::vkrt_bin());
    cmd.args(args);
    // The array-job variables of the machine running the tests must not leak in.
    for var in ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_COUNT", "JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"] {
        cmd.env_remove(var);
    }
    cmd.envs(env.iter().copied());
    cmd.output().expect("run vkrt")
}

fn ok(out: Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{what}: {err}");
    err
}

fn fails(out: Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{what} succeeded: {err}");
    assert!(!err.contains("panicked"), "{what} panicked: {err}");
    err
}

#[test]
fn merged_shards_are_the_whole_run_bit_for_bit() {
    let dir = common::scratch_dir("shards");
    let scene = common::repo_path("scenes/cornell-measured/cornell.yaml").display().to_string();
    let p = |name: &str| dir.join(name).display().to_string();
    let base = ["render", &scene, "--integrator", "path", "--width", "40", "--height", "32", "--spp", "10", "--quiet"];
    // The whole run, in batches of 3 samples (batching must not matter either).
    let whole = p("whole.exr");
    ok(vkrt(&[&base[..], &["--samples-per-batch", "3", "-o", &whole]].concat(), &[]), "whole run");
    for count in [3u32, 4] {
        let mut parts = Vec::new();
        for i in 0..count {
            let out = p(&format!("n{count}-part-{{shard}}.ckpt"));
            let label = format!("{i}/{count}");
            if i == 1 {
                // One shard as a Slurm array task numbered from 1 would see it.
                let (id, n) = ((i + 1).to_string(), count.to_string());
                let env = [("SLURM_ARRAY_TASK_ID", id.as_str()), ("SLURM_ARRAY_TASK_MIN", "1"), ("SLURM_ARRAY_TASK_COUNT", n.as_str())];
                ok(vkrt(&[&base[..], &["--shard", "env", "-o", &out]].concat(), &env), "shard from Slurm's environment");
            } else {
                ok(vkrt(&[&base[..], &["--shard", &label, "-o", &out]].concat(), &[]), &format!("shard {label}"));
            }
            parts.push(p(&format!("n{count}-part-{i}.ckpt")));
        }
        // Merged in reverse order: addition of the fixed-point sums is order-free.
        parts.reverse();
        let merged = p(&format!("merged-{count}.exr"));
        let mut args: Vec<&str> = vec!["merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["-o", &merged]);
        ok(vkrt(&args, &[]), "merge");
        let (a, b) = (std::fs::read(&whole).unwrap(), std::fs::read(&merged).unwrap());
        assert!(a == b, "{count} merged shards differ from the whole run");
    }
    // A shard resumed goes on where it stopped: here it is complete, so the sums stay.
    let part = p("n3-part-0.ckpt");
    let before = std::fs::read(&part).unwrap();
    ok(vkrt(&["render", "--resume", &part, "--quiet"], &[]), "resume a finished shard");
    let after = vkrt::integrator::path::checkpoint::Checkpoint::read(std::path::Path::new(&part)).unwrap();
    let was = vkrt::integrator::path::checkpoint::Checkpoint::from_bytes(&before).unwrap();
    assert_eq!(after.accum, was.accum);

    // Missing shards are named; shards of different runs are refused.
    let err = fails(vkrt(&["merge", &p("n4-part-0.ckpt"), &p("n4-part-2.ckpt"), "-o", &p("partial.exr")], &[]), "an incomplete merge");
    assert!(err.contains("shards 1, 3 of 4 are missing"), "{err}");
    let err = fails(vkrt(&["merge", &p("n4-part-0.ckpt"), &p("n3-part-1.ckpt"), "-o", &p("mixed.exr")], &[]), "shards of two cuttings");
    assert!(err.contains("shards of different runs"), "{err}");
    let err = fails(vkrt(&["merge", &p("n4-part-0.ckpt"), &p("n4-part-0.ckpt"), "-o", &p("twice.exr")], &[]), "a shard twice");
    assert!(err.contains("there twice"), "{err}");
    // A partial merge into a checkpoint is allowed, and completes later.
    ok(vkrt(&["merge", &p("n4-part-0.ckpt"), &p("n4-part-2.ckpt"), "-o", &p("half.ckpt")], &[]), "partial merge to a .ckpt");
    let done = p("done.exr");
    ok(vkrt(&["merge", &p("half.ckpt"), &p("n4-part-1.ckpt"), &p("n4-part-3.ckpt"), "-o", &done], &[]), "the rest");
    assert!(std::fs::read(&whole).unwrap() == std::fs::read(&done).unwrap(), "a merge in two steps differs");

    // Settings that cannot shard are one-line errors before any work.
    for (extra, want) in [
        (vec!["--shard", "0/2", "--adaptive"], "--adaptive"),
        (vec!["--shard", "0/2", "--time", "5"], "--spp only"),
        (vec!["--shard", "2/2"], "does not exist"),
        (vec!["--shard", "0/20"], "cannot be cut into 20"),
        (vec!["--shard", "0/2", "-o", "x.exr"], "a .ckpt"),
        (vec!["--shard-from-env"], "not in an array job"),
    ] {
        let mut args: Vec<&str> = base.to_vec();
        args.extend(extra.iter().copied());
        if !extra.contains(&"-o") {
            args.extend(["-o", "never-{shard}.ckpt"]);
        }
        let err = fails(vkrt(&args, &[]), &format!("{extra:?}"));
        assert!(err.contains(want) && err.lines().count() == 1, "{extra:?}: {err}");
    }
}
