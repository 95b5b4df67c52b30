//! Checkpoints of a progressive render: the running sums, the sample count and every setting
//! that decides which samples a run draws, so that a run can resume and runs with different
//! seeds can be merged into one exact image.
//!
//! Identity: a run is the same render as another if every file its scene was loaded from has
//! the same content (xxh3 of each: the scene file, its meshes, material libraries, textures
//! and sky faces, `scene::LoadStats::inputs`), the `--sky` override is the same, and so are
//! the size and sampling settings. Only the seeds may differ (they are what a merge adds).
//!
//! The file (its format, and its write: to a temporary file beside the target, renamed into
//! place, so a crash never leaves a half-written checkpoint under the real name) is
//! `output::checkpoint`'s.

use super::accumulation::Accumulation;
use super::shard::ShardSet;
use anyhow::{bail, Context as _, Result};
use std::path::PathBuf;

/// Numbers a checkpoint stores for the camera: eye, target, up, vertical field of view in
/// degrees, aperture radius, focus distance.
pub const CAMERA_NUMBERS: usize = 12;

/// The last checkpoint format whose identity was the scene file's FNV-1a hash alone
/// ([`Identity::SceneFile`]); `output::checkpoint` reads and writes the formats.
pub const VERSION_BEFORE_INPUTS: u32 = 3;

/// One file a scene was loaded from, and the xxh3 hash of its content.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputHash {
    /// The path as the loader read it (for messages).
    pub path: String,
    pub hash: u64,
}

/// What makes two runs render the same scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Identity {
    /// Every input file's content, the `--sky` override ("" for the scene's own sky) and the
    /// camera the run used (eye, target, up, vertical field of view in degrees, aperture
    /// radius and focus distance: after any `--camera`, `--eye`... choice).
    Inputs { inputs: Vec<InputHash>, sky: String, camera: [f32; CAMERA_NUMBERS] },
    /// A checkpoint from before format 4: only the FNV-1a hash of the scene file itself.
    SceneFile { fnv: u64 },
}

/// Hashes the content of every file in `paths` (the scene's `LoadStats::inputs`).
pub fn hash_inputs(paths: &[PathBuf]) -> Result<Vec<InputHash>> {
    paths.iter().map(|p| Ok(InputHash { path: p.display().to_string(), hash: crate::prepare::content_hash(p)? })).collect()
}

/// How a resumed run goes on when its command line says nothing more: what the first run was
/// asked for. Not part of the render's identity. Empty in checkpoints before format 4.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ResumeDefaults {
    /// The output image (absolute path).
    pub output: String,
    /// The BVH builder and layout names (`--builder`, `--layout` values).
    pub builder: String,
    pub layout: String,
    /// The stop rules (`--spp`, `--time`, `--target-relmse`).
    pub spp: Option<u64>,
    pub seconds: Option<f64>,
    pub target_relmse: Option<f64>,
}

/// The settings a checkpoint must agree on to be resumed or merged.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSettings {
    /// The scene file (absolute path; as given by checkpoints before format 4).
    pub scene_path: String,
    /// The content of the scene's files and the sky: a changed scene is a different render.
    pub identity: Identity,
    pub width: u32,
    pub height: u32,
    /// The seeds whose samples the sums hold: one for a plain run, several after a merge.
    pub seeds: Vec<u32>,
    /// "path".
    pub integrator: String,
    /// `SAMPLER_*`, and the strata per side for the stratified sampler.
    pub sampler: u32,
    pub sample_rate: u32,
    /// The Z-ordered sampler's set size (`PathSettings::zsobol_log2`).
    pub zsobol_log2: u32,
    /// `PATH_DEPTH_UNBOUNDED` or the depth.
    pub max_depth: u32,
    /// 1: next-event estimation with MIS; 0: BSDF sampling only.
    pub nee: u32,
    /// Pixels sharing sample numbers (`PathSettings::coherence`).
    pub coherence: u32,
    /// The square their pixels are scattered over (`PathSettings::coherence_block`; 0: a row).
    pub coherence_block: u32,
    /// For a sharded run, the parts the sums hold (`super::shard`); None for a whole run.
    pub shards: Option<ShardSet>,
    /// What the run was asked for, to go on with when resumed.
    pub resume: ResumeDefaults,
}

/// The name of a `SAMPLER_*` value, as `--sampler` spells it.
fn sampler_name(v: u32) -> String {
    super::SamplerKind::from_gpu_value(v).map_or(format!("unknown sampler {v}"), |k| k.name().to_string())
}

/// An estimator word (`NEE_*`) as the flags that choose it read.
fn nee_name(v: u32) -> String {
    use crate::gpu_abi::constants::{NEE_OFF, NEE_ON, NEE_WITH_CONNECTIONS};
    match v {
        NEE_OFF => "off (--no-nee)".into(),
        NEE_ON => "on, without light-vertex connections (--connections off)".into(),
        NEE_WITH_CONNECTIONS => "on, with light-vertex connections (--connections on)".into(),
        _ => format!("unknown estimator {v}"),
    }
}

/// A max depth as `--max-depth` reads.
fn depth_name(v: u32) -> String {
    if v == crate::gpu_abi::constants::PATH_DEPTH_UNBOUNDED {
        "unbounded".into()
    } else {
        v.to_string()
    }
}

impl RunSettings {
    /// Fails, naming the first difference, unless `self` and `other` render the same image
    /// (seeds aside); `names` say what each is in the message ("the checkpoint", "this run").
    pub fn check_same_render(&self, other: &RunSettings, names: (&str, &str)) -> Result<()> {
        let (a_name, b_name) = names;
        check_same_scene(&self.identity, &other.identity, a_name, b_name)?;
        // Not compared: `zsobol_log2`. A resumed run keeps the checkpoint's, and runs with other
        // seeds draw independent numbers whatever their set sizes, so merging runs of different
        // --spp (a sobol pair as much as a zsobol one) stays an unbiased estimate.
        let checks: [(&str, String, String); 8] = [
            ("size", format!("{}x{}", self.width, self.height), format!("{}x{}", other.width, other.height)),
            ("integrator", self.integrator.clone(), other.integrator.clone()),
            ("sampler", sampler_name(self.sampler), sampler_name(other.sampler)),
            ("sample rate", self.sample_rate.to_string(), other.sample_rate.to_string()),
            ("max depth", depth_name(self.max_depth), depth_name(other.max_depth)),
            ("light sampling", nee_name(self.nee), nee_name(other.nee)),
            ("coherence", self.coherence.to_string(), other.coherence.to_string()),
            ("coherence block", self.coherence_block.to_string(), other.coherence_block.to_string()),
        ];
        for (what, a, b) in checks {
            if a != b {
                bail!("{what} differs: {a} ({a_name}) vs {b} ({b_name})");
            }
        }
        Ok(())
    }
}

/// Fails, naming the file or setting, unless two identities are the same scene. A format-3
/// identity (the scene file's hash alone) can only be compared with another one.
fn check_same_scene(a: &Identity, b: &Identity, a_name: &str, b_name: &str) -> Result<()> {
    match (a, b) {
        (Identity::Inputs { inputs: ia, sky: sa, camera: ca }, Identity::Inputs { inputs: ib, sky: sb, camera: cb }) => {
            if ia.len() != ib.len() {
                let list = |v: &[InputHash]| v.iter().map(|i| i.path.as_str()).collect::<Vec<_>>().join(", ");
                bail!("the scenes are made of different files: {a_name} read {} ({}), {b_name} read {} ({})", ia.len(), list(ia), ib.len(), list(ib));
            }
            for (x, y) in ia.iter().zip(ib) {
                if x.hash != y.hash {
                    let same_name = x.path == y.path;
                    bail!("scene file content differs: {}{}", x.path, if same_name { " changed".to_string() } else { format!(" vs {}", y.path) });
                }
            }
            if sa != sb {
                let show = |s: &str| if s.is_empty() { "the scene's own".to_string() } else { format!("--sky {s}") };
                bail!("sky differs: {} ({a_name}) vs {} ({b_name})", show(sa), show(sb));
            }
            if ca.map(f32::to_bits) != cb.map(f32::to_bits) {
                bail!("camera differs: {} ({a_name}) vs {} ({b_name})", camera_flags(ca), camera_flags(cb));
            }
            Ok(())
        }
        (Identity::SceneFile { fnv: fa }, Identity::SceneFile { fnv: fb }) => {
            if fa != fb {
                bail!("scene file content differs: {fa:016x} ({a_name}) vs {fb:016x} ({b_name})");
            }
            Ok(())
        }
        _ => bail!(
            "one of the runs was saved by an older vkrt (checkpoint format {VERSION_BEFORE_INPUTS} or before), which \
             recorded only the scene file's hash, not its meshes, textures or sky; such a checkpoint can be merged only \
             with another of its format"
        ),
    }
}

/// FNV-1a (64-bit) of `bytes`: a cheap content fingerprint, not a cryptographic hash.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// A camera `[eye, target, up, fov, aperture, focus]` in `vkrt render`'s own flags (the lens
/// flags only for a thin lens).
pub fn camera_flags(c: &[f32; CAMERA_NUMBERS]) -> String {
    let mut s = format!("--eye {},{},{} --target {},{},{} --up {},{},{} --fov {}", c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9]);
    if c[10] > 0.0 {
        s += &format!(" --aperture {} --focus-distance {}", c[10], c[11]);
    }
    s
}

/// Settings plus sums.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    pub settings: RunSettings,
    pub accum: Accumulation,
}

impl Checkpoint {
    /// Adds `other`'s samples: the same render, and either other seeds (whole runs) or other
    /// shards of the same sharded run (`super::shard`); anything else would count samples
    /// twice or mix runs. `names` say which is which in messages.
    pub fn merge(&mut self, other: &Checkpoint, names: (&str, &str)) -> Result<()> {
        self.settings.check_same_render(&other.settings, names).context("cannot merge different renders")?;
        match (&self.settings.shards, &other.settings.shards) {
            (None, None) => {
                if let Some(seed) = other.settings.seeds.iter().find(|s| self.settings.seeds.contains(s)) {
                    bail!("both runs used seed {seed}: their samples are the same, merging would count them twice");
                }
                self.settings.seeds.extend_from_slice(&other.settings.seeds);
            }
            (Some(a), Some(b)) => {
                if self.settings.seeds != other.settings.seeds {
                    bail!("shards of different runs: seeds {:?} ({}) and {:?} ({})", self.settings.seeds, names.0, other.settings.seeds, names.1);
                }
                let union = a.union(b)?;
                // All parts together are the whole run, as if rendered in one go.
                self.settings.shards = if union.missing().is_empty() { None } else { Some(union) };
            }
            (Some(s), None) | (None, Some(s)) => {
                bail!("one run is a shard of a {}-spp run cut into {} parts and the other a whole run: merge the shards first", s.total_spp, s.count)
            }
        }
        self.accum.add(&other.accum)?;
        Ok(())
    }
}

/// A small run's checkpoint for the tests of the checkpoint's rules and of its file format
/// (`output::checkpoint`).
#[cfg(test)]
pub(crate) fn example(seed: u32) -> Checkpoint {
    let mut accum = Accumulation::new(3, 2);
    accum.samples = 5;
    accum.even_samples = 3;
    for (i, p) in accum.even.iter_mut().enumerate() {
        *p = [i as u64, 1 << 23, u64::from(seed) << 24];
    }
    accum.odd[1] = [7, 0, 1];
    accum.counts = vec![[5, 0]; 6];
    accum.counts[2][1] = 1;
    let settings = RunSettings {
        scene_path: "a.yaml".into(),
        identity: Identity::Inputs {
            inputs: vec![InputHash { path: "a.yaml".into(), hash: 42 }, InputHash { path: "a.obj".into(), hash: 43 }],
            sky: String::new(),
            camera: [0.0, 1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 45.0, 0.0, 0.0],
        },
        width: 3,
        height: 2,
        seeds: vec![seed],
        integrator: "path".into(),
        sampler: crate::gpu_abi::constants::SAMPLER_SOBOL,
        sample_rate: 4,
        zsobol_log2: 6,
        max_depth: u32::MAX,
        nee: 1,
        coherence: 8,
        coherence_block: 32,
        shards: None,
        resume: ResumeDefaults {
            output: "/x/a.exr".into(),
            builder: "sah".into(),
            layout: "threaded".into(),
            spp: Some(64),
            seconds: None,
            target_relmse: Some(1e-3),
        },
    };
    Checkpoint { settings, accum }
}

/// A checkpoint as vkrt wrote it before format 4: identified by the scene file's hash.
#[cfg(test)]
pub(crate) fn example_legacy(seed: u32) -> Checkpoint {
    let mut c = example(seed);
    c.settings.identity = Identity::SceneFile { fnv: 42 };
    c.settings.resume = ResumeDefaults::default();
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    impl Checkpoint {
        fn merge_for_test(&mut self, other: &Checkpoint) -> Result<()> {
            self.merge(other, ("a", "b"))
        }
    }

    #[test]
    fn merge_needs_the_same_render_and_new_seeds() {
        let mut a = example(1);
        assert!(a.merge_for_test(&example(1)).is_err(), "merged a seed with itself");
        // Any input file's content, or the sky, makes it another render, named in the error.
        let mut other = example(2);
        if let Identity::Inputs { inputs, .. } = &mut other.settings.identity {
            inputs[1].hash = 44;
        }
        let e = a.merge_for_test(&other).map(|_| ()).unwrap_err();
        assert!(format!("{e:#}").contains("a.obj changed"), "{e:#}");
        let mut other = example(2);
        if let Identity::Inputs { sky, .. } = &mut other.settings.identity {
            *sky = "1,1,1".into();
        }
        let e = a.merge_for_test(&other).map(|_| ()).unwrap_err();
        assert!(format!("{e:#}").contains("sky differs"), "{e:#}");
        let mut other = example(2);
        if let Identity::Inputs { camera, .. } = &mut other.settings.identity {
            camera[9] = 50.0;
        }
        let e = a.merge_for_test(&other).map(|_| ()).unwrap_err();
        assert!(format!("{e:#}").contains("camera differs") && format!("{e:#}").contains("--fov 50"), "{e:#}");
        let mut other = example(2);
        other.settings.sampler = crate::gpu_abi::constants::SAMPLER_INDEPENDENT;
        let e = a.merge_for_test(&other).map(|_| ()).unwrap_err();
        assert!(format!("{e:#}").contains("sampler differs: sobol") && format!("{e:#}").contains("independent"), "{e:#}");
        assert!(a.merge_for_test(&example_legacy(2)).is_err(), "merged a format-3 checkpoint with a format-4 one");
        let mut old = example_legacy(1);
        let mut changed = example_legacy(2);
        changed.settings.identity = Identity::SceneFile { fnv: 7 };
        assert!(old.merge_for_test(&changed).is_err(), "merged format-3 checkpoints of different scene files");
        assert!(old.merge_for_test(&example_legacy(2)).is_ok());
        a.merge_for_test(&example(2)).ok();
        assert_eq!(a.accum.samples, 10);
        assert_eq!(a.settings.seeds, vec![1, 2]);
        assert_eq!(a.accum.even[1], [2, 1 << 24, 3 << 24]);
        assert_eq!(a.accum.odd[1], [14, 0, 2]);
    }

    /// Runs of other --spp (so other Z-ordered set sizes) with other seeds merge: their numbers
    /// are independent, so the sum is an unbiased estimate; the first run's size stays.
    #[test]
    fn runs_of_other_set_sizes_merge() {
        let mut a = example(1);
        let mut other = example(2);
        other.settings.zsobol_log2 = a.settings.zsobol_log2 + 2;
        a.merge_for_test(&other).unwrap();
        assert_eq!(a.settings.seeds, vec![1, 2]);
        assert_eq!(a.settings.zsobol_log2, example(1).settings.zsobol_log2);
    }
}
