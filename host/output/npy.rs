//! NumPy `.npy` files for batch ray queries (`vkrt trace`): rays in, hits out, streamed in
//! batches so a file of any size needs bounded memory. Self-contained: the format is a magic
//! string, a version, a little-endian header length and a Python-literal header dict
//! (https://numpy.org/doc/stable/reference/generated/numpy.lib.format.html), then raw data.
//!
//! - Rays: `<f4`, C order, shape (N, 8): origin xyz, tmin, direction xyz, tmax (`GpuRay`).
//! - Hits: structured `[('t','<f4'),('prim','<u4'),('u','<f4'),('v','<f4')]`, shape (N,):
//!   t = +inf and prim = 0xFFFFFFFF on a miss; prim is the triangle's index in the scene's
//!   triangle order (`Scene::triangles`: file order after degenerate triangles are dropped);
//!   u, v are the barycentric weights of the triangle's second and third vertices.
//!
//! Reading never panics: a malformed file is an error naming the file and what is wrong. Hits are
//! written to a temporary file beside the target and renamed into place when complete.

use crate::files;
use crate::gpu_abi::{GpuHit, GpuRay};
use anyhow::{bail, Context as _, Result};
use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, Write};
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 6] = b"\x93NUMPY";
/// The structured dtype of hit files, as numpy writes it.
pub const HIT_DESCR: &str = "[('t', '<f4'), ('prim', '<u4'), ('u', '<f4'), ('v', '<f4')]";
/// A header longer than this is not a ray file (numpy's own limit for safe loading is 10 000).
const MAX_HEADER: usize = 1 << 16;

/// The fields of an `.npy` header that vkrt reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    pub descr: String,
    pub fortran_order: bool,
    pub shape: Vec<u64>,
}

/// Parse the header dict, e.g. `{'descr': '<f4', 'fortran_order': False, 'shape': (3, 8), }`.
pub fn parse_header(text: &str) -> Result<Header, String> {
    let body = text.trim().strip_prefix('{').and_then(|t| t.strip_suffix('}')).ok_or("header is not a {...} dict")?;
    let value_of = |key: &str| -> Result<&str, String> {
        let needle = format!("'{key}':");
        let start = body.find(&needle).ok_or(format!("header has no '{key}'"))? + needle.len();
        Ok(body[start..].trim_start())
    };
    let descr_v = value_of("descr")?;
    let descr = if let Some(rest) = descr_v.strip_prefix('\'') {
        rest.split('\'').next().unwrap_or_default().to_string()
    } else if descr_v.starts_with('[') {
        // A structured dtype: keep the list literal up to its closing bracket.
        let end = descr_v.find(']').ok_or("unterminated 'descr' list")?;
        descr_v[..=end].to_string()
    } else {
        return Err("'descr' is neither a string nor a list".into());
    };
    let fortran_order = match value_of("fortran_order")? {
        v if v.starts_with("False") => false,
        v if v.starts_with("True") => true,
        _ => return Err("'fortran_order' is not True or False".into()),
    };
    let shape_v = value_of("shape")?.strip_prefix('(').ok_or("'shape' is not a tuple")?;
    let inner = &shape_v[..shape_v.find(')').ok_or("unterminated 'shape' tuple")?];
    let shape = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.trim_end_matches('L').parse::<u64>().map_err(|_| format!("shape entry '{s}' is not a count")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Header { descr, fortran_order, shape })
}

/// Read the magic, version and header; leaves `r` at the start of the data.
fn read_header(r: &mut impl Read) -> Result<Header, String> {
    let mut pre = [0u8; 8];
    r.read_exact(&mut pre).map_err(|_| "too short for an .npy header".to_string())?;
    if &pre[..6] != MAGIC {
        return Err("not an .npy file (bad magic)".into());
    }
    let len = match pre[6] {
        1 => {
            let mut b = [0u8; 2];
            r.read_exact(&mut b).map_err(|_| "truncated header length".to_string())?;
            u16::from_le_bytes(b) as usize
        }
        2 | 3 => {
            let mut b = [0u8; 4];
            r.read_exact(&mut b).map_err(|_| "truncated header length".to_string())?;
            u32::from_le_bytes(b) as usize
        }
        v => return Err(format!("unsupported .npy version {v}.{}", pre[7])),
    };
    if len > MAX_HEADER {
        return Err(format!("header of {len} bytes is implausibly long"));
    }
    let mut text = vec![0u8; len];
    r.read_exact(&mut text).map_err(|_| "truncated header".to_string())?;
    let text = String::from_utf8(text).map_err(|_| "header is not text".to_string())?;
    parse_header(&text)
}

/// Streams rays from an `.npy` file of shape (N, 8), `<f4`.
pub struct RayReader {
    path: PathBuf,
    file: BufReader<File>,
    count: u64,
    read: u64,
}

impl RayReader {
    pub fn open(path: &Path) -> Result<Self> {
        let ctx = || format!("reading rays from {}", path.display());
        let file = File::open(path).with_context(ctx)?;
        let size = file.metadata().with_context(ctx)?.len();
        let mut file = BufReader::new(file);
        let header = read_header(&mut file).map_err(anyhow::Error::msg).with_context(ctx)?;
        if header.descr != "<f4" {
            bail!("{}: rays must be little-endian float32 ('<f4'), found dtype {}", path.display(), header.descr);
        }
        if header.fortran_order {
            bail!("{}: rays must be in C order (fortran_order is True)", path.display());
        }
        let count = match header.shape[..] {
            [n, 8] => n,
            _ => bail!("{}: rays must have shape (N, 8), found {:?}", path.display(), header.shape),
        };
        let data_start = file.stream_position().with_context(ctx)?;
        let expected = count.checked_mul(32).and_then(|b| b.checked_add(data_start));
        if expected != Some(size) {
            bail!("{}: shape ({count}, 8) needs {} bytes of data, the file has {}", path.display(), count.saturating_mul(32), size.saturating_sub(data_start));
        }
        Ok(Self { path: path.to_path_buf(), file, count, read: 0 })
    }
    /// Rays in the file.
    pub fn count(&self) -> u64 {
        self.count
    }
    /// The next at most `max` rays; empty at the end.
    pub fn next_batch(&mut self, max: usize) -> Result<Vec<GpuRay>> {
        let n = (self.count - self.read).min(max as u64) as usize;
        let mut bytes = vec![0u8; n * std::mem::size_of::<GpuRay>()];
        self.file.read_exact(&mut bytes).with_context(|| format!("reading rays {}..{} from {}", self.read, self.read + n as u64, self.path.display()))?;
        self.read += n as u64;
        Ok(bytes
            .chunks_exact(32)
            .map(|c| {
                let f: [f32; 8] = std::array::from_fn(|i| f32::from_le_bytes([c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]]));
                GpuRay { origin: [f[0], f[1], f[2]], tmin: f[3], direction: [f[4], f[5], f[6]], tmax: f[7] }
            })
            .collect())
    }
}

/// A version 1.0 header for `descr` and `shape`, padded with spaces and a newline so the data
/// starts on a 64-byte boundary (what numpy writes).
fn header_bytes(descr: &str, shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': {descr}, 'fortran_order': False, 'shape': {shape}, }}");
    let unpadded = MAGIC.len() + 2 + 2 + dict.len() + 1;
    let pad = (64 - unpadded % 64) % 64;
    let text = format!("{dict}{}\n", " ".repeat(pad));
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(text.len() as u16).to_le_bytes());
    out.extend_from_slice(text.as_bytes());
    out
}

/// Writes rays as (N, 8) `<f4` (for tools and tests), atomically.
pub fn write_rays(path: &Path, rays: &[GpuRay]) -> Result<()> {
    write_atomically(path, |w| {
        w.write_all(&header_bytes("'<f4'", &format!("({}, 8)", rays.len())))?;
        for r in rays {
            for x in r.origin.iter().chain([&r.tmin]).chain(&r.direction).chain([&r.tmax]) {
                w.write_all(&x.to_le_bytes())?;
            }
        }
        Ok(())
    })
}

/// Streams hits into a temporary file; `finish` checks the count and renames it into place.
/// Dropped unfinished, it deletes the temporary file.
pub struct HitWriter {
    path: PathBuf,
    tmp: PathBuf,
    file: Option<BufWriter<File>>,
    count: u64,
    written: u64,
}

impl HitWriter {
    pub fn create(path: &Path, count: u64) -> Result<Self> {
        let tmp = files::temp_beside(path);
        let file = File::create(&tmp).with_context(|| format!("{}: cannot write the output here", path.display()))?;
        let mut w = Self { path: path.to_path_buf(), tmp, file: Some(BufWriter::new(file)), count, written: 0 };
        let header = header_bytes(HIT_DESCR, &format!("({count},)"));
        w.writer()?.write_all(&header).with_context(|| format!("writing {}", w.tmp.display()))?;
        Ok(w)
    }
    fn writer(&mut self) -> Result<&mut BufWriter<File>> {
        self.file.as_mut().ok_or_else(|| anyhow::anyhow!("{} is already finished", self.path.display()))
    }
    pub fn write(&mut self, hits: &[GpuHit]) -> Result<()> {
        let tmp = self.tmp.clone();
        let w = self.writer()?;
        for h in hits {
            let mut rec = [0u8; 16];
            rec[..4].copy_from_slice(&h.t.to_le_bytes());
            rec[4..8].copy_from_slice(&h.prim.to_le_bytes());
            rec[8..12].copy_from_slice(&h.u.to_le_bytes());
            rec[12..].copy_from_slice(&h.v.to_le_bytes());
            w.write_all(&rec).with_context(|| format!("writing {}", tmp.display()))?;
        }
        self.written += hits.len() as u64;
        Ok(())
    }
    pub fn finish(mut self) -> Result<()> {
        if self.written != self.count {
            bail!("{}: wrote {} hits, header says {}", self.path.display(), self.written, self.count);
        }
        let w = self.file.take().ok_or_else(|| anyhow::anyhow!("{} is already finished", self.path.display()))?;
        let file = w.into_inner().map_err(|e| e.into_error()).with_context(|| format!("writing {}", self.tmp.display()))?;
        file.sync_all().with_context(|| format!("writing {}", self.tmp.display()))?;
        std::fs::rename(&self.tmp, &self.path).with_context(|| format!("renaming {} to {}", self.tmp.display(), self.path.display()))
    }
}

impl Drop for HitWriter {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// One hit record as read back (for tests and tools).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HitRecord {
    pub t: f32,
    pub prim: u32,
    pub u: f32,
    pub v: f32,
}

/// Reads a whole hit file written by [`HitWriter`].
pub fn read_hits(path: &Path) -> Result<Vec<HitRecord>> {
    let ctx = || format!("reading hits from {}", path.display());
    let mut file = BufReader::new(File::open(path).with_context(ctx)?);
    let header = read_header(&mut file).map_err(anyhow::Error::msg).with_context(ctx)?;
    if header.descr != HIT_DESCR || header.fortran_order || header.shape.len() != 1 {
        bail!("{}: not a vkrt hit file (dtype {}, shape {:?})", path.display(), header.descr, header.shape);
    }
    let mut data = Vec::new();
    file.read_to_end(&mut data).with_context(ctx)?;
    if data.len() as u64 != header.shape[0].saturating_mul(16) {
        bail!("{}: {} bytes of data for {} hits", path.display(), data.len(), header.shape[0]);
    }
    let word = |c: &[u8], i: usize| [c[4 * i], c[4 * i + 1], c[4 * i + 2], c[4 * i + 3]];
    Ok(data
        .chunks_exact(16)
        .map(|c| HitRecord {
            t: f32::from_le_bytes(word(c, 0)),
            prim: u32::from_le_bytes(word(c, 1)),
            u: f32::from_le_bytes(word(c, 2)),
            v: f32::from_le_bytes(word(c, 3)),
        })
        .collect())
}

fn write_atomically(path: &Path, body: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>) -> Result<()> {
    files::write_whole(path, |tmp| {
        let mut w = BufWriter::new(File::create(tmp)?);
        body(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        Ok(())
    })
}
