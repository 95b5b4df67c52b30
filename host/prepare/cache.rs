//! The prepared-scene cache: a scene's GPU arrays (BVH nodes in their layout, triangles,
//! shading arrays, texture atlas, light table) and what the command line needs of the CPU
//! scene (`SceneSummary`), stored in one file that a later run maps and uploads without
//! parsing the scene or building its BVH.
//!
//! An entry's name is a hash of everything that shapes its contents apart from the input files'
//! bytes: the cache format, the build (`BUILD`: vkrt's version and a hash of its sources), the
//! scene file's absolute path, the builder, the layout and the build settings (`entry_key`).
//! The entry then lists every file the loader read with its content hash (xxh3), and a load
//! re-hashes them all: a changed mesh, material library or texture makes the entry stale. A
//! stale, corrupt (checksum), truncated or foreign (magic, format, build) entry is never used:
//! the scene is prepared again, with a warning, and the entry rewritten. Entries are written to
//! a temporary file and renamed into place, so
//! concurrent runs preparing the same scene (shards of one array job) each leave a whole entry
//! and readers never see half of one; an entry is never changed in place, so a mapping stays
//! valid while another run replaces or evicts the file.
//!
//! File layout (little-endian): a 64-byte header (magic, format, metadata length, checksum:
//! xxh3-128 of everything after the header), the metadata (`Meta`), then the arrays, each at a
//! 64-byte boundary so that a mapped file can be read as the arrays' types in place.

use super::features::{self, Features};
use super::{PrepareOptions, PrepareTimes, PreparedScene, SceneArrays, SceneInfo};
use crate::accel::LayoutKind;
use crate::bytes::{ByteReader, ByteWriter};
use crate::files::{self, Bound};
use crate::geom::Aabb;
use crate::gpu_abi::GpuPush;
use crate::scene::{self, Camera, LoadStats, SceneSummary, Sky};
use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;
use xxhash_rust::xxh3::{xxh3_128, Xxh3};

/// The build that writes and reads entries: vkrt's version and a hash of its host sources,
/// Cargo.toml and Cargo.lock (host/build.rs). Entries of another build are never read: two
/// builds of one version can lay out the same scene differently (an experiment's binary once
/// left an entry with a tree of its own in the user's cache, which main's binary then
/// rendered wrongly), and no number bumped by hand catches every such change.
const BUILD: &str = concat!(env!("CARGO_PKG_VERSION"), "+", env!("VKRT_SOURCE_HASH"));

/// Bumped whenever the file layout or the meaning of a stored array changes.
pub const CACHE_FORMAT: u32 = 9; // 9: GpuPush grew to 96 bytes (top_order_nodes, a multi-order two-level BVH's); 8: glTF scenes without lights record their default light (LoadStats::default_light); 7: the triangle list (push.list_first, list_count; the tree leaves its triangles out); 6: reinsertion starts from the binned tree (was the sweep's), so its entries differ; 5: light picks store their alias's pmf (was padding); 4: GpuPush grew to 80 bytes
const MAGIC: &[u8; 8] = b"VKRTPREP";
const HEADER_BYTES: usize = 64;
/// Arrays start at multiples of this: every GPU struct's alignment divides it.
const ARRAY_ALIGN: usize = 64;
/// Entries are files `<key>.vkrtscene` in the cache folder.
const EXTENSION: &str = "vkrtscene";

/// In the default cache, scenes prepared faster than this are not stored: reading and checking
/// an entry costs about as much, and the folder would fill with copies of small scenes. A
/// folder given with `--cache` stores every scene.
pub const DEFAULT_MIN_PREPARE_SECONDS: f64 = 0.5;
/// The default cache keeps at most this many bytes of entries, evicting the least recently
/// used ones (a 10M-triangle scene takes about 2 GiB).
pub const DEFAULT_MAX_BYTES: u64 = 16 << 30;

/// Where prepared scenes are kept, and which of them.
#[derive(Debug, Clone, PartialEq)]
pub struct Cache {
    pub dir: PathBuf,
    /// Scenes whose preparation took less are not stored.
    pub min_prepare_seconds: f64,
    /// After a store, the least recently used entries are removed until the rest fit.
    pub max_bytes: u64,
}

impl Cache {
    /// `--cache DIR`: every scene is stored there, and nothing is evicted.
    pub fn at(dir: PathBuf) -> Self {
        Self { dir, min_prepare_seconds: 0.0, max_bytes: u64::MAX }
    }

    /// The user's cache folder (`$XDG_CACHE_HOME/vkrt`, else `~/.cache/vkrt`), or None when
    /// neither variable is set.
    pub fn default_for_user() -> Option<Self> {
        let base = std::env::var_os("XDG_CACHE_HOME")
            .filter(|v| !v.is_empty())
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").filter(|v| !v.is_empty()).map(|h| PathBuf::from(h).join(".cache")))?;
        Some(Self { dir: base.join("vkrt"), min_prepare_seconds: DEFAULT_MIN_PREPARE_SECONDS, max_bytes: DEFAULT_MAX_BYTES })
    }
}

/// A prepared scene, built now or mapped from the cache.
pub enum Prepared {
    Built { prepared: std::sync::Arc<PreparedScene>, summary: SceneSummary },
    Cached(Box<CachedScene>),
}

/// Where a [`Prepared`] came from, for `--verbose`.
#[derive(Debug, Clone, PartialEq)]
pub enum CacheOutcome {
    /// No cache (`--no-cache`, or no cache folder).
    Off,
    /// Mapped from this entry; seconds to map, check and read it.
    Hit {
        entry: PathBuf,
        seconds: f64,
    },
    /// Prepared now and stored in this entry (seconds to write it), or not stored (why).
    Stored {
        entry: PathBuf,
        seconds: f64,
    },
    NotStored {
        why: String,
    },
    /// Prepared now; the entry is being written by [`Storing`].
    Storing {
        entry: PathBuf,
    },
}

/// An entry being written on a thread of its own while the render runs (a 10M-triangle scene's
/// entry takes seconds to write). [`Storing::finish`] waits for it; dropping it waits too, so
/// that no run exits with a half-written temporary file.
pub struct Storing(Option<std::thread::JoinHandle<CacheOutcome>>);

impl Storing {
    /// Waits for the store; its outcome (a failure is `NotStored`, already described).
    pub fn finish(mut self) -> CacheOutcome {
        self.wait()
    }

    fn wait(&mut self) -> CacheOutcome {
        match self.0.take().map(std::thread::JoinHandle::join) {
            Some(Ok(outcome)) => outcome,
            Some(Err(_)) => CacheOutcome::NotStored { why: "the thread storing the entry panicked".into() },
            None => CacheOutcome::Off,
        }
    }
}

impl Drop for Storing {
    fn drop(&mut self) {
        let _ = self.wait();
    }
}

impl Prepared {
    pub fn summary(&self) -> &SceneSummary {
        match self {
            Prepared::Built { summary, .. } => summary,
            Prepared::Cached(c) => &c.meta.summary,
        }
    }

    /// The arrays to upload (a cached entry's were checked when it was opened).
    pub fn arrays(&self) -> Result<SceneArrays<'_>> {
        match self {
            Prepared::Built { prepared, .. } => Ok(prepared.arrays()),
            Prepared::Cached(c) => c.arrays(),
        }
    }

    /// The scene seen from its own camera under its own sky (`SceneInfo::with_view` for others).
    pub fn info(&self) -> SceneInfo {
        match self {
            Prepared::Built { prepared, .. } => prepared.info.clone(),
            Prepared::Cached(c) => {
                let s = &c.meta.summary;
                SceneInfo::new(&s.camera, s.ambient, &s.sky, c.meta.bounds, c.meta.features.clone())
            }
        }
    }

    /// Warnings about textures halved to fit the atlas.
    pub fn downsampled(&self) -> &[String] {
        match self {
            Prepared::Built { prepared, .. } => &prepared.atlas.downsampled,
            Prepared::Cached(c) => &c.meta.downsampled,
        }
    }

    /// The input files with the content hashes the cache checked them against when it opened
    /// the entry, in `SceneSummary::stats.inputs` order; None for a scene prepared now.
    pub fn input_hashes(&self) -> Option<&[(PathBuf, u64)]> {
        match self {
            Prepared::Built { .. } => None,
            Prepared::Cached(c) => Some(&c.meta.inputs),
        }
    }

    /// The prepare stage's times (zero for a cached scene: nothing was built).
    pub fn times(&self) -> PrepareTimes {
        match self {
            Prepared::Built { prepared, .. } => prepared.times,
            Prepared::Cached(_) => PrepareTimes::default(),
        }
    }
}

/// Loads and prepares `scene_path` as `options` say, through `cache` if there is one: an
/// entry that is whole and current is mapped; otherwise the scene is prepared and (if the
/// cache takes it) stored, on a thread of its own (the returned [`Storing`]), so that the
/// upload and the render need not wait for the disk. Problems with the cache itself are
/// warnings (`warn`, or the store's `NotStored` reason), never errors: the render goes on
/// without it. Also returns the seconds spent loading the scene file.
pub fn prepare_scene(
    scene_path: &Path,
    options: &PrepareOptions,
    cache: Option<&Cache>,
    warn: &mut dyn FnMut(String),
) -> Result<(Prepared, CacheOutcome, Option<Storing>, f64)> {
    let entry = cache.map(|c| c.dir.join(format!("{:032x}.{EXTENSION}", entry_key(scene_path, options))));
    if let Some(entry) = &entry {
        if entry.exists() {
            let start = Instant::now();
            match CachedScene::open(entry) {
                Ok(scene) => {
                    // The modification time orders entries for eviction: a hit keeps one.
                    let _ = std::fs::File::options().append(true).open(entry).and_then(|f| f.set_modified(std::time::SystemTime::now()));
                    let seconds = start.elapsed().as_secs_f64();
                    return Ok((Prepared::Cached(Box::new(scene)), CacheOutcome::Hit { entry: entry.clone(), seconds }, None, 0.0));
                }
                Err(e) => warn(format!("prepared-scene cache: not using {}: {e:#}; preparing the scene again", entry.display())),
            }
        }
    }
    let start = Instant::now();
    let scene = scene::load_scene(scene_path)?;
    let load_seconds = start.elapsed().as_secs_f64();
    let prepared = std::sync::Arc::new(PreparedScene::new(&scene, options)?);
    let summary = scene.summary();
    drop(scene);
    let (Some(cache), Some(entry)) = (cache, entry) else {
        return Ok((Prepared::Built { prepared, summary }, CacheOutcome::Off, None, load_seconds));
    };
    let spent = load_seconds + prepared.times.bvh() + prepared.times.shading;
    if !prepared.flat.nodes.instances().is_empty() {
        // Its trees are over one copy of each mesh: quick to build again, and the entry format
        // has no place for the instances.
        let why = format!("a scene with instances builds its two-level BVH in {:.2} s; it is not cached", prepared.times.bvh());
        return Ok((Prepared::Built { prepared, summary }, CacheOutcome::NotStored { why }, None, load_seconds));
    }
    if spent < cache.min_prepare_seconds {
        let why = format!("prepared in {spent:.2} s, under the {:.1} s worth caching", cache.min_prepare_seconds);
        return Ok((Prepared::Built { prepared, summary }, CacheOutcome::NotStored { why }, None, load_seconds));
    }
    let (cache, job, stored_summary, target) = (cache.clone(), prepared.clone(), summary.clone(), entry.clone());
    let handle = std::thread::Builder::new()
        .name("vkrt-cache-store".into())
        .spawn(move || {
            let start = Instant::now();
            match store(&cache, &target, &job, &stored_summary) {
                Ok(()) => CacheOutcome::Stored { entry: target, seconds: start.elapsed().as_secs_f64() },
                Err(e) => CacheOutcome::NotStored { why: format!("could not store {}: {e:#}", target.display()) },
            }
        })
        .context("starting the thread that stores the prepared scene")?;
    Ok((Prepared::Built { prepared, summary }, CacheOutcome::Storing { entry }, Some(Storing(Some(handle))), load_seconds))
}

/// The entry name's hash: everything but the input files' bytes that shapes an entry.
pub fn entry_key(scene_path: &Path, options: &PrepareOptions) -> u128 {
    entry_key_of(BUILD, scene_path, options)
}

/// [`entry_key`] as `build` would name the entry.
fn entry_key_of(build: &str, scene_path: &Path, options: &PrepareOptions) -> u128 {
    let path = std::path::absolute(scene_path).unwrap_or_else(|_| scene_path.to_path_buf());
    let b = &options.build;
    // The thread count is left out: the tree does not depend on it.
    let text = format!(
        "format {CACHE_FORMAT}; vkrt {}; scene {}; builder {}; layout {}; triangle list {}; leaf {}; bins {}; costs {} {}; texel budget {}",
        build,
        path.display(),
        options.builder.name(),
        options.layout.name(),
        options.triangle_list,
        b.max_leaf_size,
        b.sah_bins,
        b.traversal_cost,
        b.intersection_cost,
        super::texture_atlas::TEXEL_BUDGET_BYTES,
    );
    xxh3_128(text.as_bytes())
}

/// What an entry holds besides its arrays.
#[derive(Debug, Clone, PartialEq)]
struct Meta {
    version: String,
    /// Every input file with its length and content hash when the entry was made.
    inputs: Vec<(PathBuf, u64)>,
    summary: SceneSummary,
    bounds: Aabb,
    features: Features,
    layout: LayoutKind,
    push: GpuPush,
    total_weight: f64,
    downsampled: Vec<String>,
    /// (offset, length) in bytes of each array, in [`ARRAYS`] order.
    arrays: Vec<(u64, u64)>,
}

/// The arrays of an entry, in file order.
const ARRAYS: [&str; 11] = ["nodes", "triangles", "shading", "materials", "lights", "emitters", "uvs", "textures", "texels", "light picks", "tangents"];

fn array_bytes<'a>(a: &SceneArrays<'a>) -> [&'a [u8]; 11] {
    use bytemuck::cast_slice as b;
    [a.nodes, b(a.triangles), b(a.shading), b(a.materials), b(a.lights), b(a.emitters), b(a.uvs), b(a.textures), b(a.texels), b(a.picks), b(a.tangents)]
}

/// A mapped cache entry, checked.
pub struct CachedScene {
    map: memmap2::Mmap,
    meta: Meta,
}

impl CachedScene {
    fn open(path: &Path) -> Result<Self> {
        let file = std::fs::File::open(path).context("opening it")?;
        // SAFETY: entries are never written in place (stores rename a new file over the old
        // one, eviction unlinks), so the mapped bytes cannot change under us; a file cut short
        // by something else is caught by the length and checksum checks below before any read
        // past what exists.
        let map = unsafe { memmap2::Mmap::map(&file) }.context("mapping it")?;
        let header = map.get(..HEADER_BYTES).context("truncated: shorter than its header")?;
        if &header[..8] != MAGIC {
            bail!("not a vkrt prepared-scene file");
        }
        let format = u32::from_le_bytes(header[8..12].try_into()?);
        if format != CACHE_FORMAT {
            bail!("cache format {format}, this vkrt reads {CACHE_FORMAT}");
        }
        let meta_len = u64::from_le_bytes(header[16..24].try_into()?) as usize;
        let total = u64::from_le_bytes(header[24..32].try_into()?);
        if total != map.len() as u64 {
            bail!("truncated: {} bytes of {total}", map.len());
        }
        let checksum = u128::from_le_bytes(header[32..48].try_into()?);
        if xxh3_128(&map[HEADER_BYTES..]) != checksum {
            bail!("corrupt: its checksum does not match its contents");
        }
        let meta_bytes = map.get(HEADER_BYTES..HEADER_BYTES + meta_len).context("truncated metadata")?;
        let meta = Reader(ByteReader::new(meta_bytes)).meta().context("reading its metadata")?;
        if meta.version != BUILD {
            bail!("made by vkrt {}", meta.version);
        }
        for (input, hash) in &meta.inputs {
            let now = super::content_hash(input).with_context(|| format!("stale: {} cannot be read", input.display()))?;
            if now != *hash {
                bail!("stale: {} changed since it was cached", input.display());
            }
        }
        let scene = Self { map, meta };
        // Every array within the file and aligned for its type.
        scene.arrays()?;
        Ok(scene)
    }

    fn array<T: bytemuck::Pod>(&self, i: usize) -> Result<&[T]> {
        let (offset, len) = self.meta.arrays[i];
        let bytes = self.map.get(offset as usize..(offset + len) as usize).with_context(|| format!("its {} lie past its end", ARRAYS[i]))?;
        bytemuck::try_cast_slice(bytes).map_err(|e| anyhow::anyhow!("its {} are misaligned: {e:?}", ARRAYS[i]))
    }

    /// The arrays, each checked to lie within the file and be aligned for its type.
    fn arrays(&self) -> Result<SceneArrays<'_>> {
        if self.meta.arrays.len() != ARRAYS.len() {
            bail!("{} arrays, not {}", self.meta.arrays.len(), ARRAYS.len());
        }
        let (triangles, shading) = (self.array(1)?, self.array(2)?);
        Ok(SceneArrays {
            layout: self.meta.layout,
            nodes: self.array(0)?,
            push: self.meta.push,
            triangles,
            // Never stored for a two-level BVH (`prepare_scene`).
            instances: &[],
            world_triangles: triangles,
            world_shading: shading,
            shading,
            materials: self.array(3)?,
            lights: self.array(4)?,
            emitters: self.array(5)?,
            uvs: self.array(6)?,
            textures: self.array(7)?,
            texels: self.array(8)?,
            picks: self.array(9)?,
            tangents: self.array(10)?,
            total_weight: self.meta.total_weight,
        })
    }
}

/// Writes `prepared` as the entry `entry`: to a temporary file beside it, renamed into place.
fn store(cache: &Cache, entry: &Path, prepared: &PreparedScene, summary: &SceneSummary) -> Result<()> {
    std::fs::create_dir_all(&cache.dir).with_context(|| format!("creating {}", cache.dir.display()))?;
    let inputs = summary.stats.inputs.iter().map(|p| Ok((p.clone(), super::content_hash(p)?))).collect::<Result<Vec<_>>>()?;
    let a = prepared.arrays();
    let arrays = array_bytes(&a);
    let mut meta = Meta {
        version: BUILD.to_string(),
        inputs,
        summary: summary.clone(),
        bounds: prepared.info.bounds,
        features: prepared.info.features.clone(),
        layout: a.layout,
        push: a.push,
        total_weight: a.total_weight,
        downsampled: prepared.atlas.downsampled.clone(),
        arrays: Vec::new(),
    };
    // The metadata's length does not depend on the offsets' values, so lay it out once with
    // placeholders, then again with the real offsets.
    meta.arrays = vec![(0, 0); ARRAYS.len()];
    let meta_len = encode(&meta).len();
    let mut offset = (HEADER_BYTES + meta_len).next_multiple_of(ARRAY_ALIGN) as u64;
    for (slot, bytes) in meta.arrays.iter_mut().zip(arrays) {
        *slot = (offset, bytes.len() as u64);
        offset = (offset + bytes.len() as u64).next_multiple_of(ARRAY_ALIGN as u64);
    }
    let meta_bytes = encode(&meta);
    let total = offset;

    files::write_whole(entry, |tmp| {
        let file = std::fs::File::create(tmp)?;
        let mut out = std::io::BufWriter::with_capacity(1 << 20, file);
        let mut hasher = Xxh3::new();
        let mut body = |out: &mut std::io::BufWriter<std::fs::File>, bytes: &[u8]| -> std::io::Result<()> {
            hasher.update(bytes);
            out.write_all(bytes)
        };
        out.write_all(&[0u8; HEADER_BYTES])?;
        let mut at = HEADER_BYTES as u64;
        body(&mut out, &meta_bytes)?;
        at += meta_bytes.len() as u64;
        for ((offset, len), bytes) in meta.arrays.iter().zip(arrays) {
            body(&mut out, &vec![0u8; (offset - at) as usize])?;
            body(&mut out, bytes)?;
            at = offset + len;
        }
        body(&mut out, &vec![0u8; (total - at) as usize])?;
        let mut header = [0u8; HEADER_BYTES];
        header[..8].copy_from_slice(MAGIC);
        header[8..12].copy_from_slice(&CACHE_FORMAT.to_le_bytes());
        header[16..24].copy_from_slice(&(meta_bytes.len() as u64).to_le_bytes());
        header[24..32].copy_from_slice(&total.to_le_bytes());
        header[32..48].copy_from_slice(&hasher.digest128().to_le_bytes());
        let mut file = out.into_inner().map_err(|e| e.into_error())?;
        use std::io::Seek as _;
        file.seek(std::io::SeekFrom::Start(0))?;
        file.write_all(&header)?;
        // No fsync: after a crash a renamed entry may hold less than was written, which the
        // length and checksum checks of `open` catch; waiting for the disk would add seconds
        // to the first run of a big scene.
        Ok(())
    })?;
    evict(cache, entry);
    Ok(())
}

/// Removes the least recently used entries (by modification time: `prepare_scene` touches the
/// entry it uses) until the cache fits in `max_bytes`; never `keep`.
fn evict(cache: &Cache, keep: &Path) {
    if cache.max_bytes != u64::MAX {
        files::remove_oldest(&cache.dir, EXTENSION, Bound::Bytes(cache.max_bytes), Some(keep));
    }
}

// ---------------------------------------------------------------------------------------------
// The metadata's encoding: fixed-width little-endian numbers, strings as a length and UTF-8.

fn encode(m: &Meta) -> Vec<u8> {
    let mut w = ByteWriter::default();
    w.str(&m.version);
    w.u64(m.inputs.len() as u64);
    for (p, h) in &m.inputs {
        w.str(&p.to_string_lossy());
        w.u64(*h);
    }
    let s = &m.summary;
    w.camera(&s.camera);
    w.u64(s.cameras.len() as u64);
    for c in &s.cameras {
        w.camera(c);
    }
    w.vec3(s.ambient);
    match s.sky {
        Sky::None => w.u32(0),
        Sky::Constant(c) => {
            w.u32(1);
            w.vec3(c);
        }
        Sky::CubeMap { first_texture, scale } => {
            w.u32(2);
            w.u32(first_texture);
            w.vec3(scale);
        }
        // Scene files have no environment map (it comes from the command line), but the
        // summary can hold one.
        Sky::Environment { scale, rotation_deg } => {
            w.u32(3);
            w.f32(scale);
            w.f32(rotation_deg);
        }
    }
    w.u64(s.stats.dropped_degenerate as u64);
    w.strs(&s.stats.warnings);
    w.u64(s.stats.inputs.len() as u64);
    for p in &s.stats.inputs {
        w.str(&p.to_string_lossy());
    }
    w.u32(s.stats.interior as u32);
    w.u32(s.stats.default_light as u32);
    for n in [s.triangles, s.materials, s.lights] {
        w.u64(n as u64);
    }
    w.vec3(m.bounds.min);
    w.vec3(m.bounds.max);
    w.u64(m.features.entries.len() as u64);
    for (f, on, why) in &m.features.entries {
        w.str(f.name);
        w.u32(*on as u32);
        w.str(why);
    }
    w.str(m.layout.name());
    w.bytes_u64(bytemuck::bytes_of(&m.push));
    w.f64(m.total_weight);
    w.strs(&m.downsampled);
    w.u64(m.arrays.len() as u64);
    for (o, l) in &m.arrays {
        w.u64(*o);
        w.u64(*l);
    }
    w.into_inner()
}

/// The metadata's own field kinds over the shared little-endian writer.
trait MetaWriter {
    fn vec3(&mut self, v: Vec3);
    fn str(&mut self, s: &str);
    fn strs(&mut self, v: &[String]);
    fn camera(&mut self, c: &Camera);
}

impl MetaWriter for ByteWriter {
    fn vec3(&mut self, v: Vec3) {
        for x in v.to_array() {
            self.f32(x);
        }
    }
    fn str(&mut self, s: &str) {
        self.bytes_u64(s.as_bytes());
    }
    fn strs(&mut self, v: &[String]) {
        self.u64(v.len() as u64);
        for s in v {
            self.str(s);
        }
    }
    fn camera(&mut self, c: &Camera) {
        self.vec3(c.eye);
        self.vec3(c.target);
        self.vec3(c.up);
        self.f32(c.fov_y_deg);
    }
}

/// Reads the metadata ([`encode`]'s fields) with the shared little-endian reader.
struct Reader<'a>(ByteReader<'a>);

impl Reader<'_> {
    fn vec3(&mut self, field: &str) -> Result<Vec3> {
        Ok(Vec3::new(self.0.f32(field)?, self.0.f32(field)?, self.0.f32(field)?))
    }
    fn str(&mut self, field: &str) -> Result<String> {
        self.0.str_u64(field)
    }
    fn strs(&mut self, field: &str) -> Result<Vec<String>> {
        (0..self.0.count_u64(8, field)?).map(|_| self.str(field)).collect()
    }
    fn camera(&mut self, field: &str) -> Result<Camera> {
        Ok(Camera { eye: self.vec3(field)?, target: self.vec3(field)?, up: self.vec3(field)?, fov_y_deg: self.0.f32(field)?, ..Camera::default() })
    }

    fn meta(mut self) -> Result<Meta> {
        let version = self.str("version")?;
        let inputs = (0..self.0.count_u64(16, "inputs")?)
            .map(|_| Ok((PathBuf::from(self.str("input path")?), self.0.u64("input hash")?)))
            .collect::<Result<Vec<_>>>()?;
        let camera = self.camera("camera")?;
        let cameras = (0..self.0.count_u64(40, "cameras")?).map(|_| self.camera("cameras")).collect::<Result<Vec<_>>>()?;
        let ambient = self.vec3("ambient")?;
        let sky = match self.0.u32("sky kind")? {
            0 => Sky::None,
            1 => Sky::Constant(self.vec3("sky colour")?),
            2 => Sky::CubeMap { first_texture: self.0.u32("sky texture")?, scale: self.vec3("sky scale")? },
            3 => Sky::Environment { scale: self.0.f32("sky scale")?, rotation_deg: self.0.f32("sky rotation")? },
            other => bail!("unknown sky kind {other}"),
        };
        let dropped_degenerate = self.0.u64("dropped triangles")? as usize;
        let warnings = self.strs("warnings")?;
        let stat_inputs = (0..self.0.count_u64(8, "files read")?).map(|_| Ok(PathBuf::from(self.str("file read")?))).collect::<Result<Vec<_>>>()?;
        let interior = self.0.u32("interior")? != 0;
        let default_light = self.0.u32("default light")? != 0;
        let (triangles, materials, lights) = (self.0.u64("triangles")? as usize, self.0.u64("materials")? as usize, self.0.u64("lights")? as usize);
        let bounds = Aabb { min: self.vec3("bounds")?, max: self.vec3("bounds")? };
        let mut entries = Vec::new();
        for _ in 0..self.0.count_u64(20, "features")? {
            let name = self.str("feature")?;
            let feature = *features::ALL.iter().find(|f| f.name == name).with_context(|| format!("unknown shader feature {name:?}"))?;
            entries.push((feature, self.0.u32("feature on")? != 0, self.str("feature reason")?));
        }
        let layout_name = self.str("layout")?;
        let layout = *LayoutKind::ALL.iter().find(|l| l.name() == layout_name).with_context(|| format!("unknown layout {layout_name:?}"))?;
        let push = bytemuck::try_pod_read_unaligned::<GpuPush>(self.0.bytes_u64("push constants")?).map_err(|e| anyhow::anyhow!("push constants: {e:?}"))?;
        let total_weight = self.0.f64("light weight")?;
        let downsampled = self.strs("downsampled textures")?;
        let arrays =
            (0..self.0.count_u64(16, "arrays")?).map(|_| Ok((self.0.u64("array offset")?, self.0.u64("array length")?))).collect::<Result<Vec<_>>>()?;
        Ok(Meta {
            version,
            inputs,
            summary: SceneSummary {
                camera,
                cameras,
                ambient,
                sky,
                stats: LoadStats { dropped_degenerate, warnings, inputs: stat_inputs, interior, default_light },
                triangles,
                materials,
                lights,
            },
            bounds,
            features: Features { entries },
            layout,
            push,
            total_weight,
            downsampled,
            arrays,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two builds of one version (say main and an experiment's branch) name the same scene's
    /// entry differently, so neither ever maps the other's arrays.
    #[test]
    fn entries_are_named_by_the_build_that_writes_them() {
        let (version, hash) = BUILD.split_once('+').expect("BUILD is version+hash");
        assert_eq!(version, env!("CARGO_PKG_VERSION"));
        assert!(hash.len() == 16 && hash.bytes().all(|b| b.is_ascii_hexdigit()), "source hash {hash}");
        let options = PrepareOptions::default();
        let scene = Path::new("/scenes/room.obj");
        let other = format!("{version}+{:016x}", u64::from_str_radix(hash, 16).unwrap() ^ 1);
        assert_eq!(entry_key(scene, &options), entry_key_of(BUILD, scene, &options));
        assert_ne!(entry_key_of(BUILD, scene, &options), entry_key_of(&other, scene, &options));
    }

    #[test]
    fn metadata_round_trips_and_a_cut_is_an_error() {
        let meta = Meta {
            version: "9.9.9".into(),
            inputs: vec![(PathBuf::from("/a/b.obj"), 7), (PathBuf::from("/a/ü.mtl"), u64::MAX)],
            summary: SceneSummary {
                camera: Camera::default(),
                cameras: vec![Camera::default(), Camera { fov_y_deg: 30.0, ..Camera::default() }],
                ambient: Vec3::new(0.1, 0.2, 0.3),
                sky: Sky::CubeMap { first_texture: 3, scale: Vec3::ONE },
                stats: LoadStats { dropped_degenerate: 5, warnings: vec!["w".into()], inputs: vec!["/a/b.obj".into()], interior: true, default_light: true },
                triangles: 10,
                materials: 2,
                lights: 1,
            },
            bounds: Aabb { min: Vec3::splat(-1.0), max: Vec3::splat(2.0) },
            features: Features::all(),
            layout: LayoutKind::Compact,
            push: GpuPush { node_count: 17, ..bytemuck::Zeroable::zeroed() },
            total_weight: 12.5,
            downsampled: vec![],
            arrays: vec![(64, 10), (128, 0)],
        };
        let bytes = encode(&meta);
        assert_eq!(Reader(ByteReader::new(&bytes)).meta().unwrap(), meta);
        for cut in [0, 1, bytes.len() / 2, bytes.len() - 1] {
            assert!(Reader(ByteReader::new(&bytes[..cut])).meta().is_err(), "cut at {cut}");
        }
    }
}
