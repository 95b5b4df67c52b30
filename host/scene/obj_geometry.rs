//! The geometry of an OBJ file (`v`, `vt`, `vn`, `f`), parsed on every core.
//!
//! Where the time went before (406 MB, 10M triangles, 2 cores): 0.8 s reading and decoding, 5.3 s
//! in a checking pass that wrote a normalised copy of the text for tobj, 8.0 s in tobj (its
//! per-model index maps), 0.6 s turning tobj's models into triangles. Both passes were single
//! threaded and parsed every number. This module checks and parses in one go, with the same
//! messages, and splits the text into chunks at line ends that the cores parse at once:
//!
//! 1. *census* (parallel): per chunk, how many lines, vertices, texture coordinates, normals
//!    and triangles it has, and its `mtllib` / `usemtl` lines, without parsing numbers;
//! 2. the caller resolves materials in file order (it loads the libraries; tobj parses MTL);
//! 3. *attributes* (parallel): each chunk parses its `v`, `vt`, `vn` lines into its part of the
//!    global arrays, at offsets the census gave;
//! 4. *faces* (parallel): each chunk parses its `f` lines, fan-triangulated in place, into its
//!    part of the triangle list.
//!
//! Indices are global (1-based, negative ones count back from the last element defined), so a
//! chunk needs the counts of all chunks before it: the census provides them. The first error in
//! line order wins, whichever pass found it.

use std::mem::MaybeUninit;
use std::path::Path;

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::Triangle;
use crate::error::InputError;

/// Chunks are at least this big: below it, a chunk's start-up costs more than its parse.
const MIN_CHUNK_BYTES: usize = 1 << 20;

/// A `mtllib` or `usemtl` line: the caller resolves them in file order.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialLine {
    Library { name: String, line: usize },
    Use { name: String, line: usize },
}

/// What the census found in one chunk.
#[derive(Debug, Default)]
pub struct Census {
    lines: usize,
    counts: [usize; 3],
    triangles: usize,
    /// The chunk's `mtllib` and `usemtl` lines (global line numbers).
    pub material_lines: Vec<MaterialLine>,
    polylines: usize,
    /// The first bad line: its number (the chunk's own until [`census`] shifts it) and message.
    error: Option<(usize, String)>,
}

/// An OBJ text cut into chunks, with each chunk's census and where its elements start.
pub struct ObjChunks<'a> {
    path: &'a Path,
    chunks: Vec<&'a str>,
    pub census: Vec<Census>,
    /// Per chunk: the global line number of its first line less one, and the counts of
    /// vertices, texture coordinates and normals before it.
    first_line: Vec<usize>,
    bases: Vec<[usize; 3]>,
    /// Per chunk: the number of `usemtl` lines before it.
    use_bases: Vec<u32>,
    totals: [usize; 3],
    triangle_total: usize,
}

/// A triangle's material before the libraries are read: the ordinal of the `usemtl` line in
/// force (0 for the file's first), or this for none.
pub const NO_USEMTL: u32 = u32::MAX;

/// An error and its line, to find the first in line order.
type LineError = (usize, InputError);

/// The part of a line before a `#` comment, split into words.
pub fn words(line: &str) -> impl Iterator<Item = &str> {
    line.split('#').next().unwrap_or("").split_whitespace()
}

/// Parses an f32 that must be finite (f32 overflows to inf past 3.4e38, so `1e39` is rejected).
pub fn finite(path: &Path, line: usize, word: &str) -> Result<f32, InputError> {
    match word.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(InputError::at_line(path, line, format!("'{word}' is NaN or infinite (f32 holds up to 3.4e38)"))),
        Err(_) => Err(InputError::at_line(path, line, format!("'{word}' is not a number"))),
    }
}

/// The name after `mtllib` or `usemtl`: names may contain spaces (everything after the keyword),
/// but not `#`, which starts a comment here as everywhere else.
fn name_after<'l>(line: &'l str, keyword: &str) -> &'l str {
    let name = line.split('#').next().unwrap_or("").trim();
    name.get(keyword.len()..).unwrap_or("").trim()
}

/// Splits `text` at line ends into about as many chunks as there are cores (several each, so
/// that uneven chunks balance), and takes each chunk's census.
pub fn census<'a>(path: &'a Path, text: &'a str) -> ObjChunks<'a> {
    let parts = rayon::current_num_threads() * 4;
    let size = (text.len() / parts.max(1)).max(MIN_CHUNK_BYTES);
    let mut chunks = Vec::new();
    let mut rest = text;
    while !rest.is_empty() {
        let cut = if rest.len() <= size { rest.len() } else { rest[size..].find('\n').map_or(rest.len(), |i| size + i + 1) };
        let (chunk, tail) = rest.split_at(cut);
        chunks.push(chunk);
        rest = tail;
    }
    // Line numbers are needed for messages only, but a chunk cannot know its own before the
    // chunks before it are counted: the census counts locally, messages are renumbered below.
    let mut census: Vec<Census> = chunks.par_iter().map(|c| chunk_census(c)).collect();
    let (mut first_line, mut bases, mut use_bases) = (Vec::new(), Vec::new(), Vec::new());
    let (mut line, mut totals, mut triangle_total, mut uses) = (0usize, [0usize; 3], 0usize, 0u32);
    for c in &mut census {
        first_line.push(line);
        bases.push(totals);
        use_bases.push(uses);
        for m in &mut c.material_lines {
            match m {
                MaterialLine::Library { line: l, .. } => *l += line,
                MaterialLine::Use { line: l, .. } => {
                    *l += line;
                    uses += 1;
                }
            }
        }
        if let Some((l, _)) = &mut c.error {
            *l += line;
        }
        line += c.lines;
        for k in 0..3 {
            totals[k] += c.counts[k];
        }
        triangle_total += c.triangles;
    }
    ObjChunks { path, chunks, census, first_line, bases, use_bases, totals, triangle_total }
}

/// Counts one chunk's lines by kind, without parsing numbers. Line numbers are the chunk's own
/// (from 1) until [`census`] shifts them.
fn chunk_census(chunk: &str) -> Census {
    let mut c = Census::default();
    for line in chunk.lines() {
        c.lines += 1;
        let ln = c.lines;
        let mut w = words(line);
        match w.next() {
            Some("v") => c.counts[0] += 1,
            Some("vt") => c.counts[1] += 1,
            Some("vn") => c.counts[2] += 1,
            Some("f") => c.triangles += w.count().saturating_sub(2),
            Some("l") => c.polylines += 1,
            Some(k @ ("mtllib" | "usemtl")) => {
                let name = name_after(line, k);
                if name.is_empty() {
                    // The first error only; counting goes on, so the other passes stay in step.
                    c.error.get_or_insert((ln, format!("{k} needs a name")));
                    continue;
                }
                let name = name.to_string();
                c.material_lines.push(if k == "mtllib" { MaterialLine::Library { name, line: ln } } else { MaterialLine::Use { name, line: ln } });
            }
            _ => {}
        }
    }
    c
}

/// The parsed geometry, in file order.
pub struct Geometry {
    /// `Triangle::material` is the `usemtl` ordinal in force ([`NO_USEMTL`] for none) until the
    /// caller has read the material libraries and maps it.
    pub triangles: Vec<Triangle>,
    /// `l` lines skipped.
    pub polylines: usize,
}

impl ObjChunks<'_> {
    /// Checks and parses the chunks' attributes and faces. The first error in line order,
    /// whichever pass found it, is the one returned.
    pub fn parse(self) -> Result<Geometry, InputError> {
        let path = self.path;
        let [nv, nvt, nvn] = self.totals;
        let mut positions = vec![Vec3::ZERO; nv];
        let mut uvs = vec![Vec2::ZERO; nvt];
        let mut normals = vec![Vec3::ZERO; nvn];
        // Each chunk's part of the three arrays, then its attributes parsed into it.
        let mut parts = Vec::with_capacity(self.chunks.len());
        let (mut p_rest, mut t_rest, mut n_rest) = (positions.as_mut_slice(), uvs.as_mut_slice(), normals.as_mut_slice());
        for c in &self.census {
            let (p, pr) = std::mem::take(&mut p_rest).split_at_mut(c.counts[0]);
            let (t, tr) = std::mem::take(&mut t_rest).split_at_mut(c.counts[1]);
            let (n, nr) = std::mem::take(&mut n_rest).split_at_mut(c.counts[2]);
            (p_rest, t_rest, n_rest) = (pr, tr, nr);
            parts.push((p, t, n));
        }
        let attribute_errors: Vec<Option<LineError>> = self
            .chunks
            .par_iter()
            .zip(parts)
            .zip(&self.first_line)
            .map(|((chunk, (p, t, n)), &first)| parse_attributes(path, chunk, first, p, t, n).err())
            .collect();

        let mut triangles: Vec<Triangle> = Vec::with_capacity(self.triangle_total);
        let mut slots: Vec<&mut [MaybeUninit<Triangle>]> = Vec::with_capacity(self.chunks.len());
        let mut rest = &mut triangles.spare_capacity_mut()[..self.triangle_total];
        for c in &self.census {
            let (slot, r) = std::mem::take(&mut rest).split_at_mut(c.triangles);
            rest = r;
            slots.push(slot);
        }
        let attributes = Attributes { positions: &positions, uvs: &uvs, normals: &normals };
        let face_errors: Vec<Option<LineError>> = (0..self.chunks.len())
            .into_par_iter()
            .zip(slots)
            .map(|(i, slot)| parse_faces(path, self.chunks[i], self.first_line[i], self.bases[i], self.use_bases[i], &attributes, slot).err())
            .collect();
        let census_errors = self.census.iter().map(|c| c.error.as_ref().map(|(l, m)| (*l, InputError::at_line(path, *l, m.clone()))));
        let first_error = census_errors.chain(attribute_errors).chain(face_errors).flatten().min_by_key(|(line, _)| *line);
        if let Some((_, e)) = first_error {
            return Err(e);
        }
        // SAFETY: with no error, every chunk's `parse_faces` returned Ok, which it does only
        // after writing exactly its census's number of triangles into its slot, and the slots
        // tile the first `triangle_total` elements of the spare capacity.
        unsafe { triangles.set_len(self.triangle_total) };
        Ok(Geometry { triangles, polylines: self.census.iter().map(|c| c.polylines).sum() })
    }
}

/// Chunk `chunk` (first line `first + 1`)'s `v`, `vt` and `vn` lines, checked and parsed into
/// its parts of the arrays. `v x y z w` is divided by w (tobj's reading); `v x y z r g b`
/// drops the colour; `vt u` is `(u, 0)`.
fn parse_attributes(path: &Path, chunk: &str, first: usize, p: &mut [Vec3], t: &mut [Vec2], n: &mut [Vec3]) -> Result<(), LineError> {
    let at = |ln: usize, msg: String| (ln, InputError::at_line(path, ln, msg));
    let (mut ip, mut it, mut inn) = (0, 0, 0);
    let mut nums: Vec<f32> = Vec::with_capacity(8);
    for (i, line) in chunk.lines().enumerate() {
        let ln = first + i + 1;
        let mut w = words(line);
        let keyword = w.next();
        if !matches!(keyword, Some("v" | "vt" | "vn")) {
            continue;
        }
        nums.clear();
        for word in w {
            nums.push(finite(path, ln, word).map_err(|e| (ln, e))?);
        }
        match keyword {
            Some("v") => {
                let v = match *nums.as_slice() {
                    [x, y, z] | [x, y, z, _, _, _] => Vec3::new(x, y, z),
                    [x, y, z, w] => {
                        if w == 0.0 || !(x / w).is_finite() || !(y / w).is_finite() || !(z / w).is_finite() {
                            return Err(at(ln, format!("vertex weight w = {w} gives a non-finite position")));
                        }
                        Vec3::new(x / w, y / w, z / w)
                    }
                    _ => {
                        return Err(at(ln, format!("a vertex is x y z [w] or x y z r g b; found {} numbers", nums.len())));
                    }
                };
                *p.get_mut(ip).ok_or_else(|| at(ln, "internal: more vertices than counted".into()))? = v;
                ip += 1;
            }
            Some("vn") => {
                let [x, y, z] = *nums.as_slice() else {
                    return Err(at(ln, format!("a normal is x y z; found {} numbers", nums.len())));
                };
                *n.get_mut(inn).ok_or_else(|| at(ln, "internal: more normals than counted".into()))? = Vec3::new(x, y, z);
                inn += 1;
            }
            _ => {
                let uv = match *nums.as_slice() {
                    [u] => Vec2::new(u, 0.0),
                    [u, v] | [u, v, _] => Vec2::new(u, v),
                    _ => {
                        return Err(at(ln, format!("a texture coordinate is u [v [w]]; found {} numbers", nums.len())));
                    }
                };
                *t.get_mut(it).ok_or_else(|| at(ln, "internal: more texture coordinates than counted".into()))? = uv;
                it += 1;
            }
        }
    }
    Ok(())
}

struct Attributes<'a> {
    positions: &'a [Vec3],
    uvs: &'a [Vec2],
    normals: &'a [Vec3],
}

/// Chunk `chunk`'s faces, fan-triangulated in file order into `out` (exactly its census's
/// count). `bases`: the vertex, texture-coordinate and normal counts before the chunk, and
/// `uses` its `usemtl` lines. A face gets normals (texture coordinates) only if every corner
/// names one; its material is the ordinal of the `usemtl` in force.
fn parse_faces(
    path: &Path,
    chunk: &str,
    first: usize,
    bases: [usize; 3],
    uses: u32,
    a: &Attributes,
    out: &mut [MaybeUninit<Triangle>],
) -> Result<(), LineError> {
    let mut counts = bases;
    let mut material = if uses == 0 { NO_USEMTL } else { uses - 1 };
    let mut next_use = uses;
    let mut written = 0usize;
    let at = |ln: usize, msg: String| (ln, InputError::at_line(path, ln, msg));
    let mut corners: Vec<[Option<usize>; 3]> = Vec::with_capacity(8);
    for (i, line) in chunk.lines().enumerate() {
        let ln = first + i + 1;
        let mut w = words(line);
        match w.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("usemtl") => {
                material = next_use;
                next_use += 1;
            }
            Some("f") => {
                corners.clear();
                for corner in w {
                    corners.push(parse_corner(path, ln, corner, counts).map_err(|e| (ln, e))?);
                }
                if corners.len() < 3 {
                    return Err(at(ln, format!("a face needs at least 3 vertices; found {}", corners.len())));
                }
                let with_uv = corners.iter().all(|c| c[1].is_some());
                let with_n = corners.iter().all(|c| c[2].is_some());
                // Indices were checked against the counts so far, which the arrays hold.
                let pos = |c: &[Option<usize>; 3]| a.positions[c[0].unwrap_or(0)];
                let uv = |c: &[Option<usize>; 3]| a.uvs[c[1].unwrap_or(0)];
                let nor = |c: &[Option<usize>; 3]| a.normals[c[2].unwrap_or(0)];
                let c0 = corners[0];
                for pair in corners[1..].windows(2) {
                    let (c1, c2) = (pair[0], pair[1]);
                    let tri = Triangle {
                        p: [pos(&c0), pos(&c1), pos(&c2)],
                        n: with_n.then(|| [nor(&c0), nor(&c1), nor(&c2)]),
                        uv: with_uv.then(|| [uv(&c0), uv(&c1), uv(&c2)]),
                        material,
                    };
                    let slot = out.get_mut(written).ok_or_else(|| at(ln, "internal: more triangles than counted".into()))?;
                    slot.write(tri);
                    written += 1;
                }
            }
            _ => {}
        }
    }
    if written != out.len() {
        return Err((first + 1, InputError::new(path, None, format!("internal: {written} triangles parsed, {} counted", out.len()))));
    }
    Ok(())
}

/// One face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, checked against the counts defined so far
/// (negative indices count back from the latest element): its 0-based global indices.
fn parse_corner(path: &Path, ln: usize, corner: &str, counts: [usize; 3]) -> Result<[Option<usize>; 3], InputError> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let mut parts = corner.split('/');
    let mut out = [None; 3];
    let not_a_corner = || InputError::at_line(path, ln, format!("'{corner}' is not a face corner (v, v/vt, v//vn or v/vt/vn)"));
    if corner.matches('/').count() > 2 || corner.starts_with('/') {
        return Err(not_a_corner());
    }
    for (k, what) in WHAT.iter().enumerate() {
        let Some(part) = parts.next() else { break };
        if part.is_empty() {
            continue;
        }
        let index: i64 = part.parse().map_err(|_| InputError::at_line(path, ln, format!("{what} index '{part}' in '{corner}' is not an integer")))?;
        let count = counts[k] as u64;
        let resolved = match index {
            i if i > 0 && i as u64 <= count => Some(i as u64 - 1),
            i if i < 0 && i.unsigned_abs() <= count => Some(count - i.unsigned_abs()),
            _ => None,
        };
        let Some(resolved) = resolved else {
            let msg = if index == 0 {
                format!("{what} index 0 in '{corner}': OBJ indices start at 1 (negative ones count back)")
            } else {
                format!("{what} index {index} in '{corner}' is out of range: {count} defined so far")
            };
            return Err(InputError::at_line(path, ln, msg));
        };
        out[k] = Some(resolved as usize);
    }
    Ok(out)
}
