//! glTF 2.0 scenes: `.gltf` (JSON, with external or embedded `data:` buffers and images) and
//! `.glb` (the binary container), after the Khronos glTF 2.0 specification.
//!
//! The `gltf` crate parses the JSON and the GLB container, validates indices and reads accessors
//! (sparse ones included), after [`accessors`] has checked the sizes it would compute unchecked;
//! buffers and images are resolved here ([`buffers`], [`images`]), so
//! that every file read lands in `LoadStats::inputs` (checkpoints hash them) and every error is
//! an [`InputError`] naming the file and the JSON location (`meshes[2].primitives[0]`).
//!
//! What is read: the default scene (`scene`, else `scenes[0]`, else every root node), its node
//! hierarchy ([`nodes`]), every mesh primitive placed by it ([`mesh`]; a mesh used by several
//! nodes, or drawn many times by one node through `EXT_mesh_gpu_instancing` ([`instancing`]), is
//! kept once in object space with its placements, an `InstanceGroup`, whose two-level BVH keeps
//! one tree of the mesh and a top level of instances, `accel::two_level`), materials
//! ([`materials`]), `KHR_lights_punctual` lights ([`lights`]) and perspective cameras
//! ([`cameras`]). Skins, morph targets and animations are not read: the static pose is used.
//! Which extensions are supported: [`extensions`].
//!
//! Triangle order (= primitive ids): nodes in depth-first order from the scene's roots, each
//! node's primitives in file order, each primitive's triangles in index order; the copies of
//! meshes placed more than once after all of those, mesh by mesh in the order first placed,
//! each copy's triangles in that order.

mod accessors;
mod buffers;
mod cameras;
mod extensions;
mod images;
mod instancing;
mod lights;
mod materials;
mod mesh;
mod nodes;

use std::path::Path;

use super::assemble::{finish_scene, light_if_unlit, DEFAULT_AMBIENT};
use super::instance::{InstanceGroup, Placement};
use super::Scene;
use crate::error::InputError;
use crate::scene::input_file::{read_bounded, MAX_GEOMETRY_BYTES};

pub use extensions::SUPPORTED_EXTENSIONS;

/// An error at a JSON location of a glTF file.
fn at(file: &Path, location: impl Into<String>, message: impl Into<String>) -> anyhow::Error {
    InputError::new(file, Some(location.into()), message).into()
}

/// Loads a `.gltf` or `.glb` file as a whole scene: its cameras (or the default camera), its
/// lights, and for a file with neither lights nor emissive materials the same default light
/// as a bare OBJ.
pub fn load_gltf(path: &Path) -> anyhow::Result<Scene> {
    let bytes = read_bounded(path, MAX_GEOMETRY_BYTES).map_err(|e| InputError::new(path, None, e))?;
    let mut scene = Scene::default();
    scene.stats.read_input(path);
    check_glb_header(&bytes, path)?;
    // Parsed without validation first, so that an unsupported required extension is reported
    // as such (the crate's validator would only say "unsupported").
    let ::gltf::Gltf { document, blob } = ::gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| parse_error(path, e))?;
    drop(bytes);
    extensions::check(&document, path, &mut scene.stats)?;
    let json = document.into_json();
    // Checks of what the crate would otherwise panic on (found by fuzz/fuzz_targets/gltf.rs).
    accessors::check(&json, path)?;
    images::check_sources(&json, path)?;
    let document = ::gltf::Document::from_json(json).map_err(|e| parse_error(path, e))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let buffers = buffers::load(&document, blob, path, dir, &mut scene.stats)?;

    let mut images = images::Images::new(&document, &buffers, path, dir);
    let table = materials::convert(&document, path, &mut images, &mut scene)?;
    let placed = nodes::walk(&document, path)?;
    let copies = mesh::count_copies(&placed, &document, path)?;
    let mut cameras = Vec::new();
    // Meshes placed more than once are kept once, in object space, with their placements
    // (scene::instance), in the order first placed.
    let mut groups: std::collections::BTreeMap<usize, usize> = std::collections::BTreeMap::new();
    for p in &placed {
        if let Some(mesh) = p.node.mesh() {
            let worlds = instancing::worlds(&p.node, &document, &buffers, p.world, path)?;
            match copies.get(&mesh.index()).copied().unwrap_or(1) {
                0 | 1 => {
                    for world in worlds {
                        mesh::add_mesh(&mut scene, &mesh, world, &buffers, &table, path)?;
                    }
                }
                n => add_copies(&mut scene, &mut groups, &mesh, n, worlds, (&buffers, &table), path)?,
            }
        }
        if let Some(camera) = p.node.camera() {
            cameras.extend(cameras::camera(&camera, p.node.index(), p.world, path, &mut scene.stats)?);
        }
        if let Some(light) = p.node.light() {
            scene.lights.push(lights::light(&light, p.world));
        }
    }
    scene.instances.retain(|g| !g.mesh.is_empty() && !g.placements.is_empty());
    if !scene.materials.iter().any(|m| m.normal_texture.is_some()) {
        // Scene::tangents (and an instanced mesh's) is empty unless a normal map needs it.
        scene.tangents.clear();
        scene.instances.iter_mut().for_each(|g| g.tangents.clear());
    }
    finish_scene(&mut scene, path, cameras)?;
    // As a bare OBJ: the default light and a little ambient, so that the render is never black.
    light_if_unlit(&mut scene, DEFAULT_AMBIENT);
    Ok(scene)
}

/// Adds the copies placed by `worlds` to `mesh`'s instance group (of `copies` in all), made on
/// its first placement: the mesh read once, in object space. A singular transform, which would
/// flatten every triangle of its copy, places none; a degenerate triangle of the mesh is
/// dropped from every copy (and counted so).
fn add_copies(
    scene: &mut Scene,
    groups: &mut std::collections::BTreeMap<usize, usize>,
    mesh: &::gltf::Mesh,
    copies: u64,
    worlds: Vec<glam::Mat4>,
    (buffers, table): (&[Vec<u8>], &materials::MaterialTable),
    path: &Path,
) -> anyhow::Result<()> {
    let g = match groups.get(&mesh.index()) {
        Some(&g) => g,
        None => {
            let mut object = Scene::default();
            mesh::add_mesh(&mut object, mesh, glam::Mat4::IDENTITY, buffers, table, path)?;
            scene.stats.warnings.append(&mut object.stats.warnings);
            scene.stats.dropped_degenerate += object.stats.dropped_degenerate * copies as usize;
            scene.instances.push(InstanceGroup::new(object.triangles, object.tangents, Vec::new()));
            groups.insert(mesh.index(), scene.instances.len() - 1);
            scene.instances.len() - 1
        }
    };
    let group = &mut scene.instances[g];
    for world in worlds {
        match Placement::new(world) {
            Ok(placement) => group.placements.push(placement),
            Err(_) => scene.stats.dropped_degenerate += group.mesh.len(),
        }
    }
    Ok(())
}

/// A GLB file's header (spec section 4.4.2: magic, version, total length) gives a length of at
/// least its own 12 bytes: the crate subtracts 12 from it unchecked.
fn check_glb_header(bytes: &[u8], file: &Path) -> anyhow::Result<()> {
    const HEADER_BYTES: usize = 12;
    if let Some(header) = bytes.strip_prefix(b"glTF").filter(|_| bytes.len() >= HEADER_BYTES) {
        let length = u32::from_le_bytes([header[4], header[5], header[6], header[7]]);
        if (length as usize) < HEADER_BYTES {
            let msg = format!("not a valid GLB container: its header gives a length of {length} bytes, less than the header's own {HEADER_BYTES}");
            return Err(InputError::new(file, None, msg).into());
        }
    }
    Ok(())
}

/// The crate's parse or validation error, located: JSON syntax errors by line and column,
/// validation errors by their JSON path (the first of them, with the count of the others).
fn parse_error(file: &Path, e: ::gltf::Error) -> anyhow::Error {
    match e {
        ::gltf::Error::Validation(errors) => {
            let Some((path, first)) = errors.first() else { return at(file, "(document)", "invalid glTF") };
            let more = match errors.len() {
                1 => String::new(),
                n => format!(" (and {} more validation error(s))", n - 1),
            };
            at(file, path.to_string(), format!("invalid glTF: {first}{more}"))
        }
        ::gltf::Error::Deserialize(e) => at(file, format!("line {}, column {}", e.line(), e.column()), format!("not valid glTF JSON: {e}")),
        ::gltf::Error::Binary(e) => InputError::new(file, None, format!("not a valid GLB container: {e}")).into(),
        e => InputError::new(file, None, format!("cannot read glTF: {e}")).into(),
    }
}
