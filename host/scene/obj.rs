//! Wavefront OBJ + MTL loading.
//!
//! The geometry (`v`, `vt`, `vn`, `f`) is checked and parsed on every core by
//! [`super::obj_geometry`], with file and line in every error; it replaced tobj's OBJ parser,
//! which with the checking pass it needed took 13 of the 16 s a 10M-triangle file took to load
//! (BENCHMARKS.md). MTL files still go through `tobj`, after a cheap pass of our own
//! ([`sanitize_mtl`]): tobj reports errors without a line number and panics on a short `Kd` line.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;
use rayon::prelude::*;

use super::assemble::{finish_scene, light_if_unlit, push_triangles, DEFAULT_AMBIENT};
use super::input_file::{read_bounded, MAX_DESCRIPTION_BYTES, MAX_GEOMETRY_BYTES};
use super::obj_geometry::{self, finite, words, MaterialLine, NO_USEMTL};
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
    light_if_unlit(&mut scene, DEFAULT_AMBIENT);
    Ok(scene)
}

/// Reads one OBJ file into triangles and materials.
///
/// With `material_override`, every triangle gets that material index and no MTL file is read
/// (the lab YAML's `Models` assign materials by name). Otherwise materials come from the
/// `mtllib` files; a missing MTL file is a warning and the default material is used.
pub fn load_obj_meshes(path: &Path, material_override: Option<u32>) -> anyhow::Result<ObjMesh> {
    let bytes = read_bounded(path, MAX_GEOMETRY_BYTES).map_err(|e| InputError::new(path, None, e))?;
    let (text, encoding_warning) = decode_text(path, &bytes)?;
    let mut chunks = obj_geometry::census(path, &text);
    let material_lines: Vec<MaterialLine> = chunks.census.iter_mut().flat_map(|c| std::mem::take(&mut c.material_lines)).collect();
    let mut geometry = chunks.parse()?;
    drop(text);

    let mut mesh = ObjMesh { warnings: encoding_warning.into_iter().collect(), inputs: vec![path.to_path_buf()], ..ObjMesh::default() };
    // Material libraries are read in file order, as `mtllib` lines come; a `usemtl` selects
    // the material of that name among those read so far (the last of that name), or the
    // default one. With an override, no library is read.
    let obj_dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut by_name: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let mut use_ids: Vec<Option<u32>> = Vec::new();
    let mut usemtl_names: Vec<(String, usize)> = Vec::new();
    let mut libraries_missing = false;
    let mut mtl_warnings = Vec::new();
    for m in material_lines {
        match m {
            MaterialLine::Library { .. } if material_override.is_some() => {}
            MaterialLine::Library { name, line } => {
                let mtl_path = obj_dir.join(&name);
                match read_mtl(&mtl_path)? {
                    None => {
                        let msg = format!("material library {} cannot be read; default material used", mtl_path.display());
                        mtl_warnings.push(InputError::at_line(path, line, msg).to_string());
                        libraries_missing = true;
                    }
                    Some(((lib, names), warning)) => {
                        mesh.inputs.push(mtl_path.clone());
                        mtl_warnings.extend(warning);
                        let dir = mtl_path.parent().unwrap_or(Path::new("")).to_path_buf();
                        let offset = mesh.materials.len();
                        mesh.materials.extend(lib.iter().map(|m| convert_material(m, &dir)));
                        by_name.extend(names.into_iter().map(|(n, i)| (n, i + offset)));
                    }
                }
            }
            MaterialLine::Use { name, line } => {
                use_ids.push(if material_override.is_some() { None } else { by_name.get(&name).map(|&i| i as u32) });
                if !usemtl_names.iter().any(|(n, _)| *n == name) {
                    usemtl_names.push((name, line));
                }
            }
        }
    }
    mesh.warnings.extend(mtl_warnings);
    if geometry.polylines > 0 {
        mesh.warnings.push(InputError::new(path, None, format!("{} polyline(s) (l) ignored", geometry.polylines)).to_string());
    }
    if material_override.is_none() {
        // With a library missing, every usemtl of it would warn again; one warning says it all.
        for (name, line) in &usemtl_names {
            if !libraries_missing && !mesh.materials.iter().any(|m| &m.name == name) {
                let msg = format!("usemtl {name}: no such material; default material used");
                mesh.warnings.push(InputError::at_line(path, *line, msg).to_string());
            }
        }
    }
    let resolve = |ordinal: u32| if ordinal == NO_USEMTL { None } else { use_ids.get(ordinal as usize).copied().flatten() };
    let default = mesh.materials.len() as u32;
    if material_override.is_none() && geometry.triangles.par_iter().any(|t| resolve(t.material).is_none()) {
        mesh.materials.push(Material::default());
    }
    geometry.triangles.par_iter_mut().for_each(|t| t.material = material_override.unwrap_or_else(|| resolve(t.material).unwrap_or(default)));
    mesh.triangles = geometry.triangles;
    Ok(mesh)
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

/// What `tobj::load_mtl_buf` returns: the materials and a name -> index map.
type MtlLib = <tobj::MTLLoadResult as IntoIterator>::Item;

/// Reads and checks an MTL file, with a warning if it is not UTF-8. `Ok(None)`: there is no
/// such file (the caller warns); a path that exists but is not a regular file, is too large
/// or cannot be read is an error naming it (`input_file`), as the OBJ itself would be.
fn read_mtl(path: &Path) -> anyhow::Result<Option<(MtlLib, Option<String>)>> {
    if !path.exists() {
        return Ok(None);
    }
    let bytes = read_bounded(path, MAX_DESCRIPTION_BYTES).map_err(|e| InputError::new(path, None, e))?;
    let (text, warning) = decode_text(path, &bytes)?;
    let clean = sanitize_mtl(path, &text)?;
    let loaded = tobj::load_mtl_buf(&mut clean.as_bytes()).map_err(|e| InputError::new(path, None, format!("MTL parser (tobj) failed: {e}")))?;
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
            Some(k @ ("newmtl" | "map_Ka" | "map_Kd" | "map_Ks" | "map_Ns" | "map_d" | "map_bump" | "map_Bump" | "bump")) if rest.is_empty() => {
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
        let v: Vec<f32> = m.unknown_param.get("Ke")?.split_whitespace().filter_map(|s| s.parse().ok()).collect();
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
        // `norm` (the PBR extension of MTL) is a tangent-space normal map. `bump` and
        // `map_Bump`, which tobj reads as its `normal_texture`, are not used: the MTL
        // specification makes them scalar bump (height) maps, and most files that have them
        // (Crytek Sponza, the McGuire archive) hold height maps, which read as normals would
        // tilt every surface. README, "Materials".
        normal_map: m.unknown_param.get("norm").map(|t| texture_path(dir, t)),
        ..d
    }
}
