//! `tools/slurm/submit` on a real single-node Slurm that the test starts itself: Debian's
//! `slurm-wlm` and `munge` daemons run directly (no systemd) from a throw-away folder with a
//! `slurm.conf` generated for this host, and are stopped by their PIDs when the test ends, also
//! when it fails. Checks the two promises of the Slurm scripts: the merged image of an array
//! render is byte-identical to one process rendering the whole run, and a failing shard cancels
//! the merge, which the wrapper reports naming the shard.
//!
//! Needs root (slurmd runs jobs as their user) and the packages (`tools/ensure-deps.sh
//! --with-slurm`, which `tools/test` runs); without them the test says why and skips.

mod common;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// How long the daemons may take to bring the node to `idle`.
const NODE_IDLE_TIMEOUT: Duration = Duration::from_secs(60);

fn skip(test: &str, why: &str) {
    // The stderr handle, not eprintln!, which the harness captures: the reason shows in the log.
    let _ = writeln!(std::io::stderr(), "SKIPPED {test}: {why}");
}

fn on_path(tool: &str) -> bool {
    Command::new("sh").args(["-c", &format!("command -v {tool}")]).stdout(Stdio::null()).status().is_ok_and(|s| s.success())
}

/// A port nobody listens on now (the OS's pick; the tiny race with another process is
/// acceptable in a test).
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").and_then(|l| l.local_addr()).expect("a free port").port()
}

/// munged, slurmctld and slurmd, running from `dir`.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
    daemons: Vec<(&'static str, Child)>,
}

impl Cluster {
    /// Starts the daemons and waits until the node is idle; None (with the reason printed) when
    /// this machine cannot run them.
    fn start(test: &str) -> Option<Cluster> {
        // SAFETY: geteuid has no preconditions.
        if unsafe { geteuid() } != 0 {
            skip(test, "needs root to run slurmd (CI runs as root)");
            return None;
        }
        let missing: Vec<_> = ["munged", "mungekey", "slurmctld", "slurmd", "sbatch", "scontrol", "sinfo"].into_iter().filter(|t| !on_path(t)).collect();
        if !missing.is_empty() {
            skip(test, &format!("{} not installed (tools/ensure-deps.sh --with-slurm installs slurm-wlm and munge)", missing.join(", ")));
            return None;
        }
        let dir = std::env::temp_dir().join(format!("vkrt-slurm-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        for sub in ["state", "spool"] {
            std::fs::create_dir_all(dir.join(sub)).unwrap();
        }
        // munged refuses a socket folder that others may write to.
        use std::os::unix::fs::PermissionsExt as _;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o711)).unwrap();
        let mut cluster = Cluster { conf: dir.join("slurm.conf"), dir, daemons: Vec::new() };
        let d = cluster.dir.clone();
        let p = |name: &str| d.join(name).display().to_string();

        let key = Command::new("mungekey").args(["--create", "--keyfile", &p("munge.key")]).output().unwrap();
        assert!(key.status.success(), "mungekey: {}", String::from_utf8_lossy(&key.stderr));
        cluster.spawn(
            "munged",
            Command::new("munged").args(["--foreground", "--force"]).args([
                format!("--socket={}", p("munge.socket")),
                format!("--key-file={}", p("munge.key")),
                format!("--pid-file={}", p("munged.pid")),
                format!("--log-file={}", p("munged.log")),
                format!("--seed-file={}", p("munged.seed")),
            ]),
        );

        // This host as slurmd sees it (`slurmd -C`: name, cores, memory), so the node is
        // neither drained for missing resources nor given fewer than it has.
        let probe = Command::new("slurmd").arg("-C").output().unwrap();
        let node = String::from_utf8_lossy(&probe.stdout).lines().next().unwrap_or_default().to_string();
        assert!(node.starts_with("NodeName="), "slurmd -C: {node}");
        let host = node.split_whitespace().next().unwrap().trim_start_matches("NodeName=").to_string();
        let conf = format!(
            "ClusterName=vkrt-test\n\
             SlurmctldHost={host}(127.0.0.1)\n\
             SlurmUser=root\nSlurmdUser=root\n\
             SlurmctldPort={ctld}\nSlurmdPort={slurmd}\n\
             AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket={socket}\n\
             StateSaveLocation={state}\nSlurmdSpoolDir={spool}\n\
             SlurmctldPidFile={ctld_pid}\nSlurmdPidFile={slurmd_pid}\n\
             SlurmctldLogFile={ctld_log}\nSlurmdLogFile={slurmd_log}\n\
             ProctrackType=proctrack/linuxproc\nTaskPlugin=task/affinity\n\
             SelectType=select/cons_tres\nSelectTypeParameters=CR_Core\n\
             AccountingStorageType=accounting_storage/none\nJobAcctGatherType=jobacct_gather/none\nJobCompType=jobcomp/none\n\
             MpiDefault=none\nReturnToService=2\n\
             # Finished jobs stay visible to `scontrol show job`, which the wrapper polls.\n\
             MinJobAge=600\n\
             # Look at pending jobs (the merge, once its dependency is met) every second.\n\
             SchedulerType=sched/builtin\nSchedulerParameters=sched_interval=1\n\
             {node} NodeAddr=127.0.0.1 State=UNKNOWN\n\
             PartitionName=main Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            ctld = free_port(),
            slurmd = free_port(),
            socket = p("munge.socket"),
            state = p("state"),
            spool = p("spool"),
            ctld_pid = p("slurmctld.pid"),
            slurmd_pid = p("slurmd.pid"),
            ctld_log = p("slurmctld.log"),
            slurmd_log = p("slurmd.log"),
        );
        std::fs::write(&cluster.conf, conf).unwrap();
        wait_for(Duration::from_secs(10), "munged's socket", || d.join("munge.socket").exists());
        let conf = cluster.conf.clone();
        // -i: ignore state from an earlier cluster; -D: stay in the foreground, our child.
        cluster.spawn("slurmctld", Command::new("slurmctld").args(["-D", "-i"]).env("SLURM_CONF", &conf));
        cluster.spawn("slurmd", Command::new("slurmd").arg("-D").env("SLURM_CONF", &conf));
        let started = Instant::now();
        wait_for(NODE_IDLE_TIMEOUT, "the node to be idle (see the logs in the cluster folder)", || {
            cluster.command("sinfo").args(["-h", "-o", "%t"]).output().is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        let _ =
            writeln!(std::io::stderr(), "slurm: cluster in {} idle {:.1} s after the daemons started", cluster.dir.display(), started.elapsed().as_secs_f64());
        Some(cluster)
    }

    fn spawn(&mut self, name: &'static str, cmd: &mut Command) {
        let log = std::fs::File::create(self.dir.join(format!("{name}.out"))).unwrap();
        let child = cmd.stdout(log.try_clone().unwrap()).stderr(log).spawn().unwrap_or_else(|e| panic!("starting {name}: {e}"));
        self.daemons.push((name, child));
    }

    /// A Slurm client command talking to this cluster.
    fn command(&self, program: &str) -> Command {
        let mut cmd = Command::new(program);
        cmd.env("SLURM_CONF", &self.conf);
        cmd
    }
}

impl Drop for Cluster {
    /// Stops the daemons by their PIDs, newest first: SIGTERM, then SIGKILL for one that has
    /// not exited within five seconds.
    fn drop(&mut self) {
        let _ = self.command("scancel").args(["--user", "root"]).status();
        for (name, child) in self.daemons.iter_mut().rev() {
            let _ = Command::new("kill").args(["-TERM", &child.id().to_string()]).status();
            let deadline = Instant::now() + Duration::from_secs(5);
            while Instant::now() < deadline && matches!(child.try_wait(), Ok(None)) {
                std::thread::sleep(Duration::from_millis(50));
            }
            if matches!(child.try_wait(), Ok(None)) {
                let _ = writeln!(std::io::stderr(), "slurm: {name} ignored SIGTERM; killing it");
                let _ = child.kill();
                let _ = child.wait();
            }
        }
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

extern "C" {
    fn geteuid() -> u32;
}

fn wait_for(timeout: Duration, what: &str, mut ready: impl FnMut() -> bool) {
    let deadline = Instant::now() + timeout;
    while !ready() {
        assert!(Instant::now() < deadline, "timed out after {timeout:?} waiting for {what}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

fn submit(cluster: &Cluster, dir: &Path, image: &Path, shards: u32, render: &[&str]) -> Output {
    let mut cmd = cluster.command("bash");
    cmd.arg(common::repo_path("tools/slurm/submit"));
    cmd.args(["--shards", &shards.to_string(), "--dir", &dir.display().to_string(), "-o", &image.display().to_string()]);
    cmd.args(["--vkrt", &common::vkrt_bin().display().to_string(), "--wait", "--"]);
    cmd.args(render);
    cmd.output().expect("run tools/slurm/submit")
}

#[test]
fn slurm_array_render_merges_bit_for_bit_and_a_failed_shard_cancels_the_merge() {
    let test = "slurm_array_render_merges_bit_for_bit_and_a_failed_shard_cancels_the_merge";
    let Some(cluster) = Cluster::start(test) else { return };
    let work = common::scratch_dir("slurm");
    let scene = common::repo_path("scenes/cornell-measured/cornell.yaml").display().to_string();
    // 7 spp over 3 shards: a split the count does not divide.
    let render = [scene.as_str(), "--integrator", "path", "--width", "48", "--height", "40", "--spp", "7", "--quiet"];

    let whole = work.join("whole.exr");
    let out = Command::new(common::vkrt_bin()).arg("render").args(render).arg("-o").arg(&whole).output().unwrap();
    assert!(out.status.success(), "one-process render: {}", String::from_utf8_lossy(&out.stderr));

    let run = work.join("run");
    let merged = work.join("merged.exr");
    let out = submit(&cluster, &run, &merged, 3, &render);
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "submit failed:\n{stdout}{stderr}");
    let _ = writeln!(std::io::stderr(), "slurm: {}", stdout.trim().replace('\n', "\nslurm: "));
    assert!(stdout.contains("merged 3 shards into"), "{stdout}");
    assert_eq!(std::fs::read(&merged).unwrap(), std::fs::read(&whole).unwrap(), "the merged array render differs from the one-process render");
    for i in 0..3 {
        assert!(run.join(format!("part-{i}.ckpt")).is_file(), "shard {i}'s checkpoint is missing");
    }

    // Shard 1 cannot write its checkpoint (a folder is in the way): the merge must not run.
    let broken = work.join("broken");
    std::fs::create_dir_all(broken.join("part-1.ckpt")).unwrap();
    let image = work.join("never.exr");
    let out = submit(&cluster, &broken, &image, 3, &render);
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "submit with a failing shard:\n{stdout}{stderr}");
    assert!(stderr.contains("shard 1 failed"), "the wrapper must name the failed shard:\n{stderr}");
    assert!(stderr.contains("Is a directory"), "the wrapper must show the shard's log:\n{stderr}");
    assert!(!image.exists(), "the merge ran although a shard failed");
    let merge_id = stdout.split("merge: ").nth(1).map(str::trim).expect("submit prints the merge job's id");
    let state = cluster.command("scontrol").args(["show", "job", merge_id, "-o"]).output().unwrap();
    let state = String::from_utf8_lossy(&state.stdout);
    assert!(state.contains("JobState=CANCELLED"), "the merge job is not cancelled: {state}");
}
