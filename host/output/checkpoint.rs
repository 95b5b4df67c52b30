//! The checkpoint file: what `Checkpoint::to_bytes` writes and `Checkpoint::from_bytes` reads,
//! every version since the first, and the file's atomic write and its read
//! (`integrator::path::checkpoint` holds what a checkpoint is, its identity and merge rules).
//!
//! Format (little-endian): magic `VKRTCKPT`, version u32, then the settings (strings as u32
//! length + UTF-8), (version 5) the shards held (count u32, 0 for a whole run; total spp u64;
//! index count u32 and the indices u32), samples u64, even_samples u64, then the sums: version
//! 5 the fixed-point u64 r, g, b of the even-indexed samples per pixel, as many of the odd ones,
//! and (samples, dropped) u32 per pixel; versions 1 to 4 float sums, width * height * 4 f32 of
//! `sum` (rgb, dropped) and as many of `even` (rgb, count), read into fixed point (such a run
//! resumes and merges, but not bit-identically with one rendered whole in format 5). Then
//! (version 3) per_pixel u32 (1: adaptive run) and the adaptive block rates as a u32 count and
//! that many u32, then (version 4) the sky override string and the inputs as a u32 count and
//! that many (path string, hash u64), the camera and the resume defaults. Versions 1 to 3
//! stored only an FNV-1a hash of the scene file itself, in the slot where version 4 stores 0;
//! they still read, with that weaker identity ([`Identity::SceneFile`]), and such a run written
//! again (resumed or merged) keeps the hash in the slot and writes the identity block empty. Version 8 stores `zsobol_log2` after `coherence_block`
//! (read as 0 from older files, whose samplers did not read it).

use crate::bytes::{ByteReader, ByteWriter};
use crate::integrator::path::accumulation::{Accumulation, FIXED_UNIT};
pub use crate::integrator::path::checkpoint::VERSION_BEFORE_INPUTS;
use crate::integrator::path::checkpoint::{fnv1a, Checkpoint, Identity, InputHash, ResumeDefaults, RunSettings, CAMERA_NUMBERS};
use crate::integrator::path::shard::ShardSet;
use anyhow::{bail, Context as _, Result};
use std::path::Path;

pub const MAGIC: &[u8; 8] = b"VKRTCKPT";
pub const VERSION: u32 = 8;
/// The last format before `zsobol_log2` was stored (read as 0: no Z-ordered sampler then).
pub const VERSION_BEFORE_ZSOBOL: u32 = 7;
/// The last format before `coherence_block` was stored (read as 0: coherence groups in a row).
pub const VERSION_BEFORE_COHERENCE_BLOCK: u32 = 6;
/// The last format whose camera had no lens (ten numbers; read as a pinhole).
pub const VERSION_BEFORE_LENS: u32 = 5;
/// The last format with float sums and no shards (still read).
pub const VERSION_BEFORE_FIXED: u32 = 4;
/// The format before `coherence` was stored (still read, as coherence 1).
pub const VERSION_BEFORE_COHERENCE: u32 = 1;
/// The format before adaptive runs (still read, as a uniform run).
pub const VERSION_BEFORE_ADAPTIVE: u32 = 2;

/// Float sums of checkpoint formats 1 to 4 (`sum`: rgb and dropped; `even`: rgb of the
/// even-indexed samples and, adaptive runs, the pixel's count) in fixed point, rounded.
fn legacy_sums(accum: &mut Accumulation, sum: &[[f32; 4]], even: &[[f32; 4]], samples: u64) {
    let fixed = |x: f32| (f64::from(x.max(0.0)) / FIXED_UNIT).round() as u64;
    for (p, (s, e)) in sum.iter().zip(even).enumerate() {
        accum.even[p] = [fixed(e[0]), fixed(e[1]), fixed(e[2])];
        accum.odd[p] = [fixed(s[0] - e[0]), fixed(s[1] - e[1]), fixed(s[2] - e[2])];
        // Uniform runs kept no per-pixel count; adaptive ones kept it in even's w.
        let taken = if e[3] > 0.0 { e[3] as u32 } else { samples.min(u64::from(u32::MAX)) as u32 };
        accum.counts[p] = [taken, s[3] as u32];
    }
}

/// The fewest bytes a pixel takes in any version: two `[f32; 4]` sums before the fixed-point
/// format, two `[u64; 3]` sums and two `u32` counts since.
const LEAST_BYTES_PER_PIXEL: usize = 32;

/// The fixed-point sums of `count` pixels (version 5 on).
fn fixed(r: &mut ByteReader, count: usize, field: &str) -> Result<Vec<[u64; 3]>> {
    let bytes = r.take(count.checked_mul(24).context("image too large")?, field)?;
    Ok(bytes
        .chunks_exact(24)
        .map(|c| {
            let w = |i: usize| u64::from_le_bytes(c[i..i + 8].try_into().unwrap_or([0; 8]));
            [w(0), w(8), w(16)]
        })
        .collect())
}

/// The (samples, dropped) counts of `count` pixels.
fn counts(r: &mut ByteReader, count: usize) -> Result<Vec<[u32; 2]>> {
    let bytes = r.take(count.checked_mul(8).context("image too large")?, "sample counts")?;
    Ok(bytes.chunks_exact(8).map(|c| [u32::from_le_bytes([c[0], c[1], c[2], c[3]]), u32::from_le_bytes([c[4], c[5], c[6], c[7]])]).collect())
}

/// The shards field: None for a whole run (count 0).
fn shards(r: &mut ByteReader) -> Result<Option<ShardSet>> {
    let count = r.u32("shard count")?;
    let total_spp = r.u64("shard total spp")?;
    let n = r.u32("shard index count")?;
    if n > count {
        bail!("field `shard index count` is {n}, more than the {count} shards");
    }
    let indices = (0..n).map(|_| r.u32("shard index")).collect::<Result<Vec<_>>>()?;
    if indices.iter().any(|&i| i >= count) || indices.windows(2).any(|w| w[0] >= w[1]) {
        bail!("field `shard index` is not an ascending list of shards below {count}");
    }
    Ok((count > 0).then_some(ShardSet { count, total_spp, indices }))
}

/// The float sums of `count` pixels (versions 1 to 4).
fn floats(r: &mut ByteReader, count: usize, field: &str) -> Result<Vec<[f32; 4]>> {
    let bytes = r.take(count.checked_mul(16).context("image too large")?, field)?;
    Ok(bytes
        .chunks_exact(16)
        .map(|c| {
            let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
            [f(0), f(4), f(8), f(12)]
        })
        .collect())
}

impl Checkpoint {
    /// Writes atomically: a temporary file beside `path`, then a rename.
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::files::write_whole(path, |tmp| Ok(std::fs::write(tmp, self.to_bytes())?)).with_context(|| format!("writing checkpoint {}", path.display()))
    }

    pub fn read(path: &Path) -> Result<Self> {
        let data = std::fs::read(path).with_context(|| format!("reading checkpoint {}", path.display()))?;
        Self::from_bytes(&data).with_context(|| format!("checkpoint {}", path.display()))
    }

    pub fn to_bytes(&self) -> Vec<u8> {
        let s = &self.settings;
        let mut out = ByteWriter::with_capacity(256 + self.accum.even.len() * 56);
        out.raw(MAGIC);
        out.raw(&VERSION.to_le_bytes());
        out.str_u32(&s.scene_path);
        // Formats 1-3 stored the scene file's hash here; format 4 keeps the slot, at 0.
        let legacy = match &s.identity {
            Identity::SceneFile { fnv } => *fnv,
            Identity::Inputs { .. } => 0,
        };
        out.raw(&legacy.to_le_bytes());
        for v in [s.width, s.height, s.seeds.len() as u32] {
            out.raw(&v.to_le_bytes());
        }
        for seed in &s.seeds {
            out.raw(&seed.to_le_bytes());
        }
        out.str_u32(&s.integrator);
        for v in [s.sampler, s.sample_rate, s.max_depth, s.nee, s.coherence, s.coherence_block, s.zsobol_log2] {
            out.raw(&v.to_le_bytes());
        }
        let none = ShardSet { count: 0, total_spp: 0, indices: Vec::new() };
        let shards = s.shards.as_ref().unwrap_or(&none);
        out.raw(&shards.count.to_le_bytes());
        out.raw(&shards.total_spp.to_le_bytes());
        out.raw(&(shards.indices.len() as u32).to_le_bytes());
        for i in &shards.indices {
            out.raw(&i.to_le_bytes());
        }
        out.raw(&self.accum.samples.to_le_bytes());
        out.raw(&self.accum.even_samples.to_le_bytes());
        for px in self.accum.even.iter().chain(&self.accum.odd) {
            for c in px {
                out.raw(&c.to_le_bytes());
            }
        }
        for px in &self.accum.counts {
            for c in px {
                out.raw(&c.to_le_bytes());
            }
        }
        out.raw(&(self.accum.per_pixel as u32).to_le_bytes());
        out.raw(&(self.accum.rates.len() as u32).to_le_bytes());
        for r in &self.accum.rates {
            out.raw(&r.to_le_bytes());
        }
        // A run identified by the scene file's hash (read from format 3 or older) writes the
        // block empty: the hash in the slot above says which identity holds.
        let (sky, inputs, camera) = match &s.identity {
            Identity::Inputs { inputs, sky, camera } => (sky.as_str(), inputs.as_slice(), *camera),
            Identity::SceneFile { .. } => ("", &[][..], [0.0; CAMERA_NUMBERS]),
        };
        out.str_u32(sky);
        out.raw(&(inputs.len() as u32).to_le_bytes());
        for i in inputs {
            out.str_u32(&i.path);
            out.raw(&i.hash.to_le_bytes());
        }
        for c in camera {
            out.raw(&c.to_le_bytes());
        }
        let r = &s.resume;
        for text in [&r.output, &r.builder, &r.layout] {
            out.str_u32(text);
        }
        // 0 and NaN: not given.
        out.raw(&r.spp.unwrap_or(0).to_le_bytes());
        for x in [r.seconds, r.target_relmse] {
            out.raw(&x.unwrap_or(f64::NAN).to_le_bytes());
        }
        out.into_inner()
    }

    pub fn from_bytes(data: &[u8]) -> Result<Self> {
        let mut r = ByteReader::new(data);
        if r.take(8, "magic")? != MAGIC {
            bail!("not a vkrt checkpoint (bad magic)");
        }
        let version = r.u32("version")?;
        if !(VERSION_BEFORE_COHERENCE..=VERSION).contains(&version) {
            bail!("checkpoint version {version}; this vkrt reads versions {VERSION_BEFORE_COHERENCE} to {VERSION}");
        }
        let scene_path = r.str_u32("scene_path")?;
        let scene_hash = r.u64("scene_hash")?;
        let width = r.u32("width")?;
        let height = r.u32("height")?;
        let seed_count = r.u32("seed count")? as usize;
        let seeds = (0..seed_count).map(|_| r.u32("seeds")).collect::<Result<Vec<_>>>()?;
        let integrator = r.str_u32("integrator")?;
        let sampler = r.u32("sampler")?;
        let sample_rate = r.u32("sample_rate")?;
        let max_depth = r.u32("max_depth")?;
        let nee = r.u32("nee")?;
        if nee > crate::gpu_abi::constants::NEE_WITH_CONNECTIONS {
            bail!("field `nee` is {nee}: an estimator this vkrt does not know (0 to {})", crate::gpu_abi::constants::NEE_WITH_CONNECTIONS);
        }
        // Version 1 predates the setting: its runs gave every pixel its own numbers.
        let coherence = if version == VERSION_BEFORE_COHERENCE { 1 } else { r.u32("coherence")? };
        // Before format 7 coherence groups were rows.
        let coherence_block = if version > VERSION_BEFORE_COHERENCE_BLOCK { r.u32("coherence_block")? } else { 0 };
        let zsobol_log2 = if version > VERSION_BEFORE_ZSOBOL { r.u32("zsobol_log2")? } else { 0 };
        if zsobol_log2 > crate::gpu_abi::constants::ZSOBOL_MAX_LOG2 {
            bail!("field `zsobol_log2` is {zsobol_log2}, more than {}", crate::gpu_abi::constants::ZSOBOL_MAX_LOG2);
        }
        let shards = if version > VERSION_BEFORE_FIXED { shards(&mut r)? } else { None };
        let samples = r.u64("samples")?;
        let even_samples = r.u64("even_samples")?;
        if even_samples > samples {
            bail!("even_samples {even_samples} exceeds samples {samples}");
        }
        let pixels = width as usize * height as usize;
        // Every pixel's sums are stored (at least 32 bytes of them, in the oldest format):
        // a damaged size fails here rather than allocating for pixels the file does not hold.
        if pixels > r.remaining() / LEAST_BYTES_PER_PIXEL {
            bail!("truncated: {width}x{height} pixels need more than the {} bytes left (byte {})", r.remaining(), r.position());
        }
        let mut accum = Accumulation::new(width, height);
        if version > VERSION_BEFORE_FIXED {
            accum.even = fixed(&mut r, pixels, "even sums")?;
            accum.odd = fixed(&mut r, pixels, "odd sums")?;
            accum.counts = counts(&mut r, pixels)?;
        } else {
            let (sum, even) = (floats(&mut r, pixels, "sum")?, floats(&mut r, pixels, "even")?);
            legacy_sums(&mut accum, &sum, &even, samples);
        }
        let (mut per_pixel, mut rates) = (false, Vec::new());
        if version > VERSION_BEFORE_ADAPTIVE {
            per_pixel = match r.u32("per_pixel")? {
                0 => false,
                1 => true,
                v => bail!("field `per_pixel` is {v}, not 0 or 1"),
            };
            let n = r.u32("rate count")? as usize;
            if n > pixels {
                bail!("field `rate count` is {n}, more than the {pixels} pixels");
            }
            rates = (0..n).map(|_| r.u32("rates")).collect::<Result<Vec<_>>>()?;
        }
        let identity = if version > VERSION_BEFORE_INPUTS {
            let sky = r.str_u32("sky")?;
            let n = r.u32("input count")? as usize;
            let remaining = r.remaining();
            // Each input takes at least 12 bytes: a bad count is an error, not a huge allocation.
            if n > remaining / 12 {
                bail!("field `input count` is {n}, more than the {remaining} bytes left can hold");
            }
            let inputs = (0..n).map(|_| Ok(InputHash { path: r.str_u32("input path")?, hash: r.u64("input hash")? })).collect::<Result<Vec<_>>>()?;
            // Formats before the lens stored ten numbers: a pinhole.
            let stored = if version > VERSION_BEFORE_LENS { CAMERA_NUMBERS } else { 10 };
            let mut camera = [0.0f32; CAMERA_NUMBERS];
            for c in &mut camera[..stored] {
                *c = f32::from_bits(r.u32("camera")?);
            }
            // A hash in the old slot: a run first saved in format 3 or older, written again
            // (resumed or merged) with its weaker identity and this block empty.
            if scene_hash != 0 {
                Identity::SceneFile { fnv: scene_hash }
            } else {
                Identity::Inputs { inputs, sky, camera }
            }
        } else {
            Identity::SceneFile { fnv: scene_hash }
        };
        let resume = if version > VERSION_BEFORE_INPUTS {
            let (output, builder, layout) = (r.str_u32("output")?, r.str_u32("builder")?, r.str_u32("layout")?);
            let spp = Some(r.u64("stop spp")?).filter(|&n| n > 0);
            let mut given = || -> Result<Option<f64>> { Ok(Some(f64::from_bits(r.u64("stop")?)).filter(|x| !x.is_nan())) };
            let (seconds, target_relmse) = (given()?, given()?);
            ResumeDefaults { output, builder, layout, spp, seconds, target_relmse }
        } else {
            ResumeDefaults::default()
        };
        if r.remaining() != 0 {
            bail!("{} unexpected bytes after the data", r.remaining());
        }
        Ok(Self {
            settings: RunSettings {
                scene_path,
                identity,
                width,
                height,
                seeds,
                integrator,
                sampler,
                sample_rate,
                zsobol_log2,
                max_depth,
                nee,
                coherence,
                coherence_block,
                shards,
                resume,
            },
            accum: Accumulation { samples, even_samples, per_pixel, rates, ..accum },
        })
    }
}

/// The FNV-1a hash of a file's content: the identity checkpoints before format 4 stored.
pub fn fnv1a_file(path: &Path) -> Result<u64> {
    Ok(fnv1a(&std::fs::read(path).with_context(|| format!("reading {} to hash it", path.display()))?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::path::checkpoint::{example, example_legacy};

    #[test]
    fn round_trips_and_rejects_damage() {
        let c = example(7);
        let bytes = c.to_bytes();
        assert_eq!(Checkpoint::from_bytes(&bytes).ok().as_ref(), Some(&c));
        assert!(Checkpoint::from_bytes(&bytes[..bytes.len() - 1]).is_err(), "truncated data accepted");
        let mut bad = bytes.clone();
        bad[0] = b'X';
        assert!(Checkpoint::from_bytes(&bad).is_err(), "bad magic accepted");
    }

    #[test]
    fn a_damaged_size_is_an_error_before_any_allocation_for_it() {
        let bytes = example(7).to_bytes();
        // magic, version, the scene path (length and bytes), the scene hash: then width, height.
        let at = 8 + 4 + 4 + "a.yaml".len() + 8;
        assert_eq!(bytes[at..at + 8], [3, 0, 0, 0, 2, 0, 0, 0]);
        let mut bad = bytes.clone();
        bad[at..at + 8].copy_from_slice(&[u32::MAX.to_le_bytes(), u32::MAX.to_le_bytes()].concat());
        // Without the check this would ask for 2^64 x 56 bytes of sums.
        let e = format!("{:#}", Checkpoint::from_bytes(&bad).unwrap_err());
        assert!(e.contains("truncated") && e.contains("4294967295x4294967295"), "{e}");
    }

    /// The bytes vkrt wrote in `version` (1 to 3: no inputs, float sums) for `c`'s settings,
    /// with float sums `sum` and `even` (rgb + dropped, rgb + count) per pixel.
    fn legacy_bytes(c: &Checkpoint, version: u32, sum: &[[f32; 4]], even: &[[f32; 4]]) -> Vec<u8> {
        let s = &c.settings;
        let mut out = ByteWriter::default();
        out.raw(MAGIC);
        out.raw(&version.to_le_bytes());
        out.str_u32(&s.scene_path);
        let Identity::SceneFile { fnv } = s.identity else { panic!("a legacy identity") };
        out.raw(&fnv.to_le_bytes());
        for v in [s.width, s.height, s.seeds.len() as u32].iter().chain(&s.seeds) {
            out.raw(&v.to_le_bytes());
        }
        out.str_u32(&s.integrator);
        let mut words = vec![s.sampler, s.sample_rate, s.max_depth, s.nee];
        if version > VERSION_BEFORE_COHERENCE {
            words.push(s.coherence);
        }
        for v in words {
            out.raw(&v.to_le_bytes());
        }
        out.raw(&c.accum.samples.to_le_bytes());
        out.raw(&c.accum.even_samples.to_le_bytes());
        for x in sum.iter().chain(even).flatten() {
            out.raw(&x.to_le_bytes());
        }
        if version > VERSION_BEFORE_ADAPTIVE {
            out.raw(&[0u8; 8]);
        }
        out.into_inner()
    }

    /// `c`'s bytes as format `version` writes them: the last `drop` of the settings words
    /// (coherence_block, zsobol_log2) left out.
    fn without_last_setting_words(c: &Checkpoint, drop: usize, version: u32) -> Vec<u8> {
        let bytes = c.to_bytes();
        let s = &c.settings;
        let words: Vec<u8> =
            [s.sampler, s.sample_rate, s.max_depth, s.nee, s.coherence, s.coherence_block, s.zsobol_log2].iter().flat_map(|v| v.to_le_bytes()).collect();
        let end = bytes.windows(words.len()).position(|w| w == words.as_slice()).expect("the settings words") + words.len();
        let mut old = [&bytes[..end - 4 * drop], &bytes[end..]].concat();
        old[8..12].copy_from_slice(&version.to_le_bytes());
        old
    }

    /// Format-6 files (before `coherence_block`) read as coherence groups in a row, the only
    /// kind there was.
    #[test]
    fn format_6_reads_as_coherence_in_rows() {
        let c = example(5);
        let read = Checkpoint::from_bytes(&without_last_setting_words(&c, 2, VERSION_BEFORE_COHERENCE_BLOCK)).unwrap();
        assert_eq!(read.settings.coherence, 8);
        assert_eq!(read.settings.coherence_block, 0);
        assert_eq!(read.accum, c.accum);
    }

    /// Format-7 files (before the Z-ordered sampler) read with set size 0, which their samplers
    /// never read; everything else is as written.
    #[test]
    fn format_7_reads_without_zsobol_sets() {
        let c = example(5);
        let read = Checkpoint::from_bytes(&without_last_setting_words(&c, 1, VERSION_BEFORE_ZSOBOL)).unwrap();
        assert_eq!(read.settings.zsobol_log2, 0);
        assert_eq!((read.settings.coherence, read.settings.coherence_block), (8, 32));
        assert_eq!(read.accum, c.accum);
    }

    /// Format-3 files (the scene file's hash alone, float sums) and version-1 files (before
    /// `coherence` was stored: read as coherence 1) still read, their sums in fixed point.
    #[test]
    fn reads_older_formats() {
        let mut c = example_legacy(3);
        c.settings.coherence = 8;
        c.settings.coherence_block = 0;
        c.settings.zsobol_log2 = 0;
        let sum = vec![[3.0f32, 0.5, 0.0, 1.0]; 6];
        let even = vec![[1.0f32, 0.25, 0.0, 0.0]; 6];
        let read = Checkpoint::from_bytes(&legacy_bytes(&c, VERSION_BEFORE_INPUTS, &sum, &even)).unwrap();
        assert_eq!(read.settings, c.settings);
        assert_eq!(read.accum.even[0], [1 << 24, 1 << 22, 0]);
        assert_eq!(read.accum.odd[0], [2 << 24, 1 << 22, 0]);
        // Uniform runs kept no per-pixel count: the run's count; the dropped sample is kept.
        assert_eq!(read.accum.counts[0], [5, 1]);
        let read = Checkpoint::from_bytes(&legacy_bytes(&c, VERSION_BEFORE_COHERENCE, &sum, &even)).unwrap();
        assert_eq!(read.settings.coherence, 1);
        assert_eq!(read.accum.image().pixels[0], [3.0 / 5.0, 0.1, 0.0]);
        let mut future = example(3).to_bytes();
        future[8..12].copy_from_slice(&(VERSION + 1).to_le_bytes());
        assert!(Checkpoint::from_bytes(&future).is_err(), "a newer version was accepted");
    }

    /// A run read from a format-3 file keeps its weaker identity when written again (what
    /// `vkrt merge` of two such runs into a .ckpt does): the file reads back as it was written,
    /// resume defaults included.
    #[test]
    fn a_scene_file_identity_round_trips() {
        let mut c = example_legacy(4);
        c.settings.resume.output = "out.exr".into();
        c.settings.resume.spp = Some(64);
        let read = Checkpoint::from_bytes(&c.to_bytes()).unwrap();
        assert_eq!(read.settings, c.settings);
        assert_eq!(read.accum, c.accum);
    }

    #[test]
    fn shards_round_trip_and_merge_into_the_whole_run() {
        use crate::integrator::path::shard::{Shard, ShardSet};
        let part = |i: u32| {
            let mut c = example(9);
            c.settings.shards = Some(ShardSet::of(Shard::new(i, 3, 16).unwrap()));
            c
        };
        let a = part(0);
        assert_eq!(Checkpoint::from_bytes(&a.to_bytes()).ok().as_ref(), Some(&a));
        let mut m = part(2);
        m.merge(&part(0), ("a", "b")).unwrap();
        assert_eq!(m.settings.shards.as_ref().and_then(|s| s.missing_message()).as_deref(), Some("shard 1 of 3 is missing (numbered from 0)"));
        assert!(m.clone().merge(&part(0), ("a", "b")).is_err(), "a shard twice");
        assert!(m.clone().merge(&example(9), ("a", "b")).is_err(), "a shard and a whole run");
        m.merge(&part(1), ("a", "b")).unwrap();
        assert_eq!(m.settings.shards, None, "all shards make the whole run");
        assert_eq!(m.accum.samples, 15);
    }

    #[test]
    fn adaptive_fields_round_trip() {
        let mut c = example(4);
        c.accum.per_pixel = true;
        c.accum.rates = vec![2, 4, 32];
        assert_eq!(Checkpoint::from_bytes(&c.to_bytes()).ok().as_ref(), Some(&c));
    }
}
