//! Wavefront OBJ + MTL loading.
//!
//! `tobj` parses and fan-triangulates, but it reports errors without a line number, silently
//! mis-reads some legal files (trailing comments, vertex colours on only some vertices, faces
//! that lack normals next to faces that have them) and panics on a short `Kd` line in an MTL.
//! So every file first goes through a cheap pass of our own ([`sanitize_obj`], [`sanitize_mtl`])
//! that rejects bad input with file and line and hands tobj a normalised copy it handles.

use std::cell::RefCell;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use super::assemble::{default_light, finish_scene, push_triangles};
use super::{Material, Scene, Triangle};
use crate::error::InputError;

/// The triangles and materials of one OBJ file, before they join a [`Scene`].
#[derive(Debug, Clone, Default)]
pub struct ObjMesh {
    /// File order, faces fan-triangulated in place. Degenerate triangles are still here: they
    /// are dropped by [`super::assemble::push_triangles`], after any transform a caller applies.
    pub triangles: Vec<Triangle>,
    /// The MTL materials; `Triangle::material` indexes this (or is the caller's override).
    pub materials: Vec<Material>,
    /// Warnings, not yet printed: the caller passes them to `LoadStats::warn` so that they
    /// end up in the scene's statistics.
    pub warnings: Vec<String>,
    /// The files read: the OBJ, then the material libraries it loaded.
    pub inputs: Vec<PathBuf>,
}

/// Loads a bare OBJ file as a whole scene: framing camera, and a default light unless the file
/// has an emitter.
pub fn load_obj(path: &Path) -> anyhow::Result<Scene> {
    let mesh = load_obj_meshes(path, None)?;
    let mut scene = Scene { materials: mesh.materials, ..Scene::default() };
    for w in mesh.warnings {
        scene.stats.warn(w);
    }
    for p in &mesh.inputs {
        scene.stats.read_input(p);
    }
    push_triangles(&mut scene, mesh.triangles);
    finish_scene(&mut scene, path, Vec::new())?;
    if scene.emissive_triangles().is_empty() {
        // Without an emitter the image would be black: light from over the camera's shoulder,
        // plus a little ambient so that faces turned away are not pitch black.
        scene.lights.push(default_light(&scene));
        scene.ambient = Vec3::splat(0.05);
    }
    Ok(scene)
}

/// Reads one OBJ file into triangles and materials.
///
/// With `material_override`, every triangle gets that material index and no MTL file is read
/// (the lab YAML's `Models` assign materials by name). Otherwise materials come from the
/// `mtllib` files; a missing MTL file is a warning and the default material is used.
pub fn load_obj_meshes(path: &Path, material_override: Option<u32>) -> anyhow::Result<ObjMesh> {
    let bytes =
        std::fs::read(path).map_err(|e| InputError::new(path, None, format!("cannot read the file: {e}")))?;
    let (text, encoding_warning) = decode_text(path, &bytes)?;
    let checked = sanitize_obj(path, &text)?;
    let obj_dir = path.parent().unwrap_or(Path::new("")).to_path_buf();

    // tobj calls this once per `mtllib`; it must be `Fn`, so results are kept in RefCells.
    let mtl_error: RefCell<Option<anyhow::Error>> = RefCell::new(None);
    let mtl_dirs: RefCell<Vec<PathBuf>> = RefCell::new(Vec::new());
    let mtl_warnings: RefCell<Vec<String>> = RefCell::new(Vec::new());
    let mtl_inputs: RefCell<Vec<PathBuf>> = RefCell::new(Vec::new());
    let mtl_missing = std::cell::Cell::new(false);
    let load_mtl = |rel: &Path| -> tobj::MTLLoadResult {
        let empty = Ok((Vec::new(), Default::default()));
        if material_override.is_some() {
            return empty;
        }
        let mtl_path = obj_dir.join(rel);
        let line = checked.mtllib_lines.iter().find(|(n, _)| Path::new(n) == rel).map_or(0, |l| l.1);
        match read_mtl(&mtl_path) {
            Ok(None) => {
                let msg =
                    format!("material library {} cannot be read; default material used", mtl_path.display());
                mtl_warnings.borrow_mut().push(InputError::at_line(path, line, msg).to_string());
                mtl_missing.set(true);
                empty
            }
            Ok(Some((lib, warning))) => {
                mtl_inputs.borrow_mut().push(mtl_path.clone());
                mtl_warnings.borrow_mut().extend(warning);
                let dir = mtl_path.parent().unwrap_or(Path::new("")).to_path_buf();
                mtl_dirs.borrow_mut().extend(std::iter::repeat(dir).take(lib.0.len()));
                Ok(lib)
            }
            Err(e) => {
                *mtl_error.borrow_mut() = Some(e);
                Err(tobj::LoadError::MaterialParseError)
            }
        }
    };
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        // `sanitize_obj` rejects faces with fewer than 3 vertices and removes `l` lines, so
        // nothing reaches tobj that it would turn into a zero-area "triangle".
        ignore_points: true,
        ignore_lines: true,
    };
    let loaded = tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, load_mtl);
    if let Some(e) = mtl_error.into_inner() {
        return Err(e);
    }
    let (models, tobj_materials) =
        loaded.map_err(|e| InputError::new(path, None, format!("OBJ parser (tobj) failed: {e}")))?;

    let mut inputs = vec![path.to_path_buf()];
    inputs.extend(mtl_inputs.into_inner());
    let mut mesh = ObjMesh { warnings: encoding_warning.into_iter().collect(), inputs, ..ObjMesh::default() };
    mesh.warnings.extend(mtl_warnings.into_inner());
    // With a library missing, every usemtl of it would warn again; one warning says it all.
    let libraries_missing = mtl_missing.get();
    mesh.warnings.extend(checked.warnings);
    if material_override.is_none() {
        // An error here is only tobj passing on ours, already handled above.
        let tobj_materials = tobj_materials.unwrap_or_default();
        let dirs = mtl_dirs.into_inner();
        for (i, m) in tobj_materials.iter().enumerate() {
            let dir = dirs.get(i).map_or(Path::new(""), PathBuf::as_path);
            mesh.materials.push(convert_material(m, dir));
        }
        for (name, line) in &checked.usemtl_names {
            if !libraries_missing && !mesh.materials.iter().any(|m| &m.name == name) {
                let msg = format!("usemtl {name}: no such material; default material used");
                mesh.warnings.push(InputError::at_line(path, *line, msg).to_string());
            }
        }
    }
    mesh.triangles =
        collect_triangles(path, &models, &checked.faces, material_override, &mut mesh.materials)?;
    Ok(mesh)
}

/// Per-face facts from the sanitizing pass that tobj's output loses.
#[derive(Debug, Clone, Copy)]
struct FaceInfo {
    /// n - 2 for an n-gon.
    triangles: u32,
    /// Every corner names a normal (`v//vn`, `v/vt/vn`). tobj invents normals for corners
    /// without one (it repeats the previous index), so we only trust them when all are given.
    normals: bool,
    /// Every corner names a texture coordinate; same reason.
    uvs: bool,
}

/// An OBJ text tobj can load as is, and what we learnt while checking it.
struct CheckedObj {
    text: String,
    faces: Vec<FaceInfo>,
    /// Each `mtllib` name with its line, for warnings about the library.
    mtllib_lines: Vec<(String, usize)>,
    /// Each material name used, with the line of its first `usemtl`.
    usemtl_names: Vec<(String, usize)>,
    warnings: Vec<String>,
}

/// Decodes a text file, rejecting binary content with the line it starts on. Text that is not
/// UTF-8 (older exporters write names in Latin-1 or Windows-1252, "Terraindæk") is read as
/// Latin-1: every byte becomes one character, so names keep their bytes and `usemtl` still
/// matches `newmtl`; the second value is then a warning to show once for the file.
fn decode_text<'a>(path: &Path, bytes: &'a [u8]) -> anyhow::Result<(std::borrow::Cow<'a, str>, Option<String>)> {
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(InputError::at_line(path, 1, "the file is UTF-16 text; save it as UTF-8").into());
    }
    let line_of = |at: usize| bytes.get(..at).map_or(1, |b| b.iter().filter(|&&c| c == b'\n').count() + 1);
    // ASCII control characters other than tab, line ends and form feed do not occur in text
    // (a ^Z that ends the file, as old DOS editors wrote, aside).
    let binary = |i: usize, c: u8| match c {
        0 => true,
        b'\t' | b'\n' | b'\r' | 0x0b | 0x0c => false,
        0x1a => i + 1 != bytes.len(),
        c => c < 0x20 || c == 0x7f,
    };
    if let Some(at) = bytes.iter().enumerate().position(|(i, &c)| binary(i, c)) {
        let what = if bytes[at] == 0 { "NUL byte" } else { "control character" };
        let msg = format!("{what} 0x{:02x}: a binary file, not OBJ/MTL text", bytes[at]);
        return Err(InputError::at_line(path, line_of(at), msg).into());
    }
    let bytes = bytes.strip_suffix(&[0x1a]).unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        // A UTF-8 byte-order mark would glue itself to the first keyword and hide that line.
        Ok(text) => Ok((std::borrow::Cow::Borrowed(text.strip_prefix('\u{feff}').unwrap_or(text)), None)),
        Err(e) => {
            let line = line_of(e.valid_up_to());
            let text: String = bytes.iter().map(|&b| char::from(b)).collect();
            let msg = format!("not UTF-8 (from line {line}); read as Latin-1, so names keep their bytes");
            Ok((std::borrow::Cow::Owned(text), Some(InputError::at_line(path, line, msg).to_string())))
        }
    }
}

/// The part of a line before a `#` comment, split into words.
fn words(line: &str) -> impl Iterator<Item = &str> {
    line.split('#').next().unwrap_or("").split_whitespace()
}

/// Parses an f32 that must be finite (f32 overflows to inf past 3.4e38, so `1e39` is rejected).
fn finite(path: &Path, line: usize, word: &str) -> Result<f32, InputError> {
    match word.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(InputError::at_line(
            path,
            line,
            format!("'{word}' is NaN or infinite (f32 holds up to 3.4e38)"),
        )),
        Err(_) => Err(InputError::at_line(path, line, format!("'{word}' is not a number"))),
    }
}

/// Checks the OBJ text line by line and writes the copy tobj will parse: comments stripped from
/// data lines, vertex colours dropped (unused, and tobj fails when only some vertices have
/// them), `vt u` completed to `vt u 0`, `l` lines blanked. Line numbers are kept.
fn sanitize_obj(path: &Path, text: &str) -> anyhow::Result<CheckedObj> {
    let mut out = String::with_capacity(text.len() + 64);
    let mut faces = Vec::new();
    let (mut nv, mut nvt, mut nvn) = (0usize, 0usize, 0usize);
    let mut mtllib_lines = Vec::new();
    let mut usemtl_names: Vec<(String, usize)> = Vec::new();
    let mut lines_ignored = 0usize;
    // Writing to a String cannot fail.
    macro_rules! line_out {
        ($($arg:tt)*) => {{ let _ = writeln!(out, $($arg)*); }};
    }
    for (i, line) in text.lines().enumerate() {
        let ln = i + 1;
        let mut w = words(line);
        let keyword = w.next();
        let rest: Vec<&str> = w.collect();
        let nums = || rest.iter().map(|s| finite(path, ln, s)).collect::<Result<Vec<f32>, _>>();
        match keyword {
            Some("v") => {
                match nums()?.as_slice() {
                    // Colours (x y z r g b) are dropped: unused, and tobj fails on a file
                    // where only some vertices have them.
                    [x, y, z] | [x, y, z, _, _, _] => line_out!("v {x} {y} {z}"),
                    &[x, y, z, w] => {
                        if w == 0.0 || !(x / w).is_finite() || !(y / w).is_finite() || !(z / w).is_finite() {
                            let msg = format!("vertex weight w = {w} gives a non-finite position");
                            return Err(InputError::at_line(path, ln, msg).into());
                        }
                        line_out!("v {x} {y} {z} {w}");
                    }
                    v => {
                        let msg = format!("a vertex is x y z [w] or x y z r g b; found {} numbers", v.len());
                        return Err(InputError::at_line(path, ln, msg).into());
                    }
                }
                nv += 1;
            }
            Some("vn") => {
                match nums()?.as_slice() {
                    [x, y, z] => line_out!("vn {x} {y} {z}"),
                    v => {
                        let msg = format!("a normal is x y z; found {} numbers", v.len());
                        return Err(InputError::at_line(path, ln, msg).into());
                    }
                }
                nvn += 1;
            }
            Some("vt") => {
                // `vt u` is legal (v defaults to 0) but tobj wants two numbers.
                match nums()?.as_slice() {
                    [u] => line_out!("vt {u} 0"),
                    [u, v] | [u, v, _] => line_out!("vt {u} {v}"),
                    t => {
                        let msg = format!("a texture coordinate is u [v [w]]; found {} numbers", t.len());
                        return Err(InputError::at_line(path, ln, msg).into());
                    }
                }
                nvt += 1;
            }
            Some("f") => {
                if rest.len() < 3 {
                    let msg = format!("a face needs at least 3 vertices; found {}", rest.len());
                    return Err(InputError::at_line(path, ln, msg).into());
                }
                let mut info = FaceInfo { triangles: (rest.len() - 2) as u32, normals: true, uvs: true };
                for corner in &rest {
                    let (has_vt, has_vn) = check_corner(path, ln, corner, [nv, nvt, nvn])?;
                    info.uvs &= has_vt;
                    info.normals &= has_vn;
                }
                faces.push(info);
                out.push_str("f ");
                out.push_str(&rest.join(" "));
                out.push('\n');
            }
            Some("l") => {
                // Polylines are not surfaces; tobj would triangulate one with 3+ points.
                lines_ignored += 1;
                out.push('\n');
            }
            Some(k @ ("mtllib" | "usemtl")) => {
                // Names may contain spaces (tobj takes everything after the keyword), but not
                // `#`: that starts a comment here as everywhere else.
                let name = line.split('#').next().unwrap_or("").trim();
                let name = name.get(k.len()..).unwrap_or("").trim();
                if name.is_empty() {
                    return Err(InputError::at_line(path, ln, format!("{k} needs a name")).into());
                }
                if k == "mtllib" {
                    mtllib_lines.push((name.to_string(), ln));
                } else if !usemtl_names.iter().any(|(n, _)| n == name) {
                    usemtl_names.push((name.to_string(), ln));
                }
                line_out!("{k} {name}");
            }
            _ => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    let mut warnings = Vec::new();
    if lines_ignored > 0 {
        warnings.push(
            InputError::new(path, None, format!("{lines_ignored} polyline(s) (l) ignored")).to_string(),
        );
    }
    Ok(CheckedObj { text: out, faces, mtllib_lines, usemtl_names, warnings })
}

/// Checks one face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against the counts read so far
/// (negative indices count back from the latest element). Returns whether vt and vn are given.
fn check_corner(
    path: &Path,
    ln: usize,
    corner: &str,
    counts: [usize; 3],
) -> Result<(bool, bool), InputError> {
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let parts: Vec<&str> = corner.split('/').collect();
    if parts.len() > 3 || parts.first().map_or(true, |p| p.is_empty()) {
        return Err(InputError::at_line(
            path,
            ln,
            format!("'{corner}' is not a face corner (v, v/vt, v//vn or v/vt/vn)"),
        ));
    }
    for ((part, what), count) in parts.iter().zip(WHAT).zip(counts) {
        if part.is_empty() {
            continue;
        }
        let index: i64 = part.parse().map_err(|_| {
            InputError::at_line(path, ln, format!("{what} index '{part}' in '{corner}' is not an integer"))
        })?;
        let ok = match index {
            0 => false,
            i if i > 0 => i as u64 <= count as u64,
            i => i.unsigned_abs() <= count as u64,
        };
        if !ok {
            let msg = if index == 0 {
                format!("{what} index 0 in '{corner}': OBJ indices start at 1 (negative ones count back)")
            } else {
                format!("{what} index {index} in '{corner}' is out of range: {count} defined so far")
            };
            return Err(InputError::at_line(path, ln, msg));
        }
    }
    let given = |k: usize| parts.get(k).is_some_and(|p| !p.is_empty());
    Ok((given(1), given(2)))
}

/// What `tobj::load_mtl_buf` returns: the materials and a name -> index map.
type MtlLib = <tobj::MTLLoadResult as IntoIterator>::Item;

/// Reads and checks an MTL file, with a warning if it is not UTF-8. `Ok(None)`: it cannot be
/// read (the caller warns).
fn read_mtl(path: &Path) -> anyhow::Result<Option<(MtlLib, Option<String>)>> {
    let Ok(bytes) = std::fs::read(path) else { return Ok(None) };
    let (text, warning) = decode_text(path, &bytes)?;
    let clean = sanitize_mtl(path, &text)?;
    let loaded = tobj::load_mtl_buf(&mut clean.as_bytes())
        .map_err(|e| InputError::new(path, None, format!("MTL parser (tobj) failed: {e}")))?;
    Ok(Some((loaded, warning)))
}

/// Checks the numeric MTL lines tobj reads (it panics on a colour with fewer than 3 numbers)
/// and writes a copy where a one-number colour `Kd 0.5` is spelled out as `Kd 0.5 0.5 0.5`.
/// `Tr` is left alone: files disagree on whether it means opacity or transparency (the
/// dragon/buddha MTLs have `Tr 1` next to `d 1`), so only `d` is trusted.
fn sanitize_mtl(path: &Path, text: &str) -> anyhow::Result<String> {
    let mut out = String::with_capacity(text.len() + 64);
    macro_rules! line_out {
        ($($arg:tt)*) => {{ let _ = writeln!(out, $($arg)*); }};
    }
    for (i, line) in text.lines().enumerate() {
        let ln = i + 1;
        let mut w = words(line);
        let keyword = w.next();
        let rest: Vec<&str> = w.collect();
        let nums = || rest.iter().map(|s| finite(path, ln, s)).collect::<Result<Vec<f32>, _>>();
        match keyword {
            Some(k @ ("Ka" | "Kd" | "Ks" | "Ke")) => match nums()?.as_slice() {
                [g] => line_out!("{k} {g} {g} {g}"),
                [r, g, b] => line_out!("{k} {r} {g} {b}"),
                c => {
                    let msg = format!("{k} needs r g b (or one grey value); found {} numbers", c.len());
                    return Err(InputError::at_line(path, ln, msg).into());
                }
            },
            Some(k @ ("Ns" | "Ni" | "d")) => match nums()?.as_slice() {
                [x] => line_out!("{k} {x}"),
                x => {
                    let msg = format!("{k} needs one number; found {}", x.len());
                    return Err(InputError::at_line(path, ln, msg).into());
                }
            },
            Some("illum") => match rest.as_slice() {
                [x] if x.parse::<u8>().is_ok() => line_out!("illum {x}"),
                _ => return Err(InputError::at_line(path, ln, "illum needs one integer 0-10").into()),
            },
            Some(
                k @ ("newmtl" | "map_Ka" | "map_Kd" | "map_Ks" | "map_Ns" | "map_d" | "map_bump" | "map_Bump"
                | "bump"),
            ) if rest.is_empty() => {
                return Err(InputError::at_line(path, ln, format!("{k} needs a name")).into());
            }
            _ => {
                out.push_str(line.trim());
                out.push('\n');
            }
        }
    }
    Ok(out)
}

/// A texture path from an MTL `map_*` line, relative to the MTL's folder. Options such as
/// `-s 1 1 1 file.png` come first, so when there are any the file is the last word.
fn texture_path(dir: &Path, spec: &str) -> PathBuf {
    let spec = spec.trim();
    let file = if spec.starts_with('-') { spec.split_whitespace().last().unwrap_or(spec) } else { spec };
    dir.join(file)
}

fn convert_material(m: &tobj::Material, dir: &Path) -> Material {
    let d = Material::default();
    let v3 = |c: Option<[f32; 3]>, default: Vec3| c.map_or(default, Vec3::from);
    // tobj 4.0.5 reads Ke itself; older ones left it in `unknown_param`.
    let ke = m.emissive.or_else(|| {
        let v: Vec<f32> =
            m.unknown_param.get("Ke")?.split_whitespace().filter_map(|s| s.parse().ok()).collect();
        Some([*v.first()?, *v.get(1)?, *v.get(2)?])
    });
    Material {
        name: m.name.clone(),
        diffuse: v3(m.diffuse, d.diffuse),
        specular: v3(m.specular, d.specular),
        shininess: m.shininess.unwrap_or(d.shininess),
        emission: v3(ke, d.emission),
        ior: m.optical_density.unwrap_or(d.ior),
        dissolve: m.dissolve.unwrap_or(d.dissolve),
        illum: m.illumination_model.map_or(d.illum, u32::from),
        diffuse_map: m.diffuse_texture.as_deref().map(|t| texture_path(dir, t)),
        alpha_map: m.dissolve_texture.as_deref().map(|t| texture_path(dir, t)),
        diffuse_texture: None,
        alpha_texture: None,
    }
}

/// Turns tobj's models back into one triangle list in file order. tobj keeps models in file
/// order and faces within a model in order, so triangle k of the concatenation belongs to the
/// k-th face's fan; `faces` says which of them really carry normals and uvs.
fn collect_triangles(
    path: &Path,
    models: &[tobj::Model],
    faces: &[FaceInfo],
    material_override: Option<u32>,
    materials: &mut Vec<Material>,
) -> anyhow::Result<Vec<Triangle>> {
    let expected: u64 = faces.iter().map(|f| u64::from(f.triangles)).sum();
    let got: u64 = models.iter().map(|m| m.mesh.indices.len() as u64 / 3).sum();
    let mismatch = || {
        InputError::new(path, None, format!("internal: tobj returned {got} triangles, expected {expected}"))
    };
    if got != expected {
        return Err(mismatch().into());
    }
    let mut default_material = None;
    let mut face_iter = faces.iter();
    let mut face = FaceInfo { triangles: 0, normals: false, uvs: false };
    let mut out = Vec::with_capacity(got as usize);
    for model in models {
        let mesh = &model.mesh;
        let material = match (material_override, mesh.material_id) {
            (Some(m), _) => m,
            (None, Some(id)) if id < materials.len() => id as u32,
            (None, _) => *default_material.get_or_insert_with(|| {
                materials.push(Material::default());
                (materials.len() - 1) as u32
            }),
        };
        for k in 0..mesh.indices.len() / 3 {
            while face.triangles == 0 {
                face = *face_iter.next().ok_or_else(mismatch)?;
            }
            face.triangles -= 1;
            let p = gather3(&mesh.indices, &mesh.positions, k).ok_or_else(mismatch)?;
            let n = if face.normals { gather3(&mesh.normal_indices, &mesh.normals, k) } else { None };
            let uv = if face.uvs { gather2(&mesh.texcoord_indices, &mesh.texcoords, k) } else { None };
            out.push(Triangle { p, n, uv, material });
        }
    }
    Ok(out)
}

/// Corner data of triangle `k` from one of tobj's index arrays; `None` if tobj's arrays are
/// shorter than its indices say.
fn gather3(indices: &[u32], data: &[f32], k: usize) -> Option<[Vec3; 3]> {
    let corner = |c: usize| -> Option<Vec3> {
        let i = *indices.get(3 * k + c)? as usize * 3;
        data.get(i..i + 3).map(Vec3::from_slice)
    };
    Some([corner(0)?, corner(1)?, corner(2)?])
}

fn gather2(indices: &[u32], data: &[f32], k: usize) -> Option<[Vec2; 3]> {
    let corner = |c: usize| -> Option<Vec2> {
        let i = *indices.get(3 * k + c)? as usize * 2;
        data.get(i..i + 2).map(Vec2::from_slice)
    };
    Some([corner(0)?, corner(1)?, corner(2)?])
}
