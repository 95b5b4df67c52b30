//! Interruption of a progressive render: SIGTERM (as Ctrl-C) writes a final checkpoint and the
//! image so far, then exits non-zero; SIGKILL leaves the last checkpoint intact and resumable;
//! resuming keeps every sample the checkpoint held.

mod common;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};
use vkrt::integrator::path::checkpoint::Checkpoint;

const SCENE: &str = "scenes/cornell-measured/cornell.yaml";

/// A long path-traced render that checkpoints every 0.2 s.
fn start_long_render(dir: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_vkrt"))
        .args(["render", common::repo_path(SCENE).to_str().unwrap(), "--integrator", "path", "--width", "64", "--height", "64", "--spp", "1000000"])
        .arg("--checkpoint")
        .arg(dir.join("run.ckpt"))
        .args(["--checkpoint-interval", "0.2", "-o"])
        .arg(dir.join("run.exr"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start vkrt")
}

/// Waits until the checkpoint holds at least `samples` samples.
fn wait_for_checkpoint(path: &Path, samples: u64) -> Checkpoint {
    let start = Instant::now();
    loop {
        if let Ok(c) = Checkpoint::read(path) {
            if c.accum.samples >= samples {
                return c;
            }
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no checkpoint with {samples} samples after 2 minutes");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn signal(child: &Child, sig: &str) {
    let status = Command::new("kill").args([sig, &child.id().to_string()]).status().expect("run kill");
    assert!(status.success());
}

fn resume(dir: &Path, spp: u64) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_vkrt"))
        .args(["render", common::repo_path(SCENE).to_str().unwrap(), "--integrator", "path", "--width", "64", "--height", "64"])
        .args(["--spp", &spp.to_string(), "--resume"])
        .arg(dir.join("run.ckpt"))
        .arg("--checkpoint")
        .arg(dir.join("run.ckpt"))
        .arg("-o")
        .arg(dir.join("resumed.exr"))
        .output()
        .expect("run vkrt")
}

#[test]
fn sigterm_writes_the_checkpoint_and_image_then_exits() {
    let dir = common::scratch_dir("interrupt-term");
    let _ = std::fs::remove_file(dir.join("run.ckpt"));
    let _ = std::fs::remove_file(dir.join("run.exr"));
    let child = start_long_render(&dir);
    let before = wait_for_checkpoint(&dir.join("run.ckpt"), 8);
    signal(&child, "-TERM");
    let output = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "an interrupted render must exit non-zero");
    assert!(err.contains("interrupted"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // The final checkpoint holds at least what the last periodic one did, and the image exists.
    let last = Checkpoint::read(&dir.join("run.ckpt")).unwrap();
    assert!(last.accum.samples >= before.accum.samples, "final checkpoint lost samples");
    let image = vkrt::output::read_image(&dir.join("run.exr")).unwrap();
    assert_eq!((image.width, image.height), (64, 64));
    assert!(image.mean().iter().all(|&m| m > 0.0), "the image so far is empty");
    // Resuming adds to exactly those samples.
    let more = last.accum.samples + 4;
    let out = resume(&dir, more);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(Checkpoint::read(&dir.join("run.ckpt")).unwrap().accum.samples, more);
}

#[test]
fn sigkill_leaves_the_last_checkpoint_intact_and_resumable() {
    let dir = common::scratch_dir("interrupt-kill");
    let _ = std::fs::remove_file(dir.join("run.ckpt"));
    let mut child = start_long_render(&dir);
    // Kill while checkpoints are being rewritten, several times over.
    wait_for_checkpoint(&dir.join("run.ckpt"), 24);
    signal(&child, "-KILL");
    let _ = child.wait();
    let last = Checkpoint::read(&dir.join("run.ckpt")).expect("the checkpoint survives kill -9");
    assert!(last.accum.samples >= 24);
    // No temporary file is taken for the checkpoint, and the run continues from it.
    let more = last.accum.samples + 4;
    let out = resume(&dir, more);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(Checkpoint::read(&dir.join("run.ckpt")).unwrap().accum.samples, more);
}
