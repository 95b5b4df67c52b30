//! Mesh primitives (glTF 2.0 spec section 3.7.2) into world-space triangles.
//!
//! - Modes: TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (section 3.7.2.1 gives the vertex order
//!   of each); points and lines are an error naming the primitive.
//! - Attributes: POSITION, NORMAL, TANGENT and TEXCOORD_0. Positions go through the world
//!   matrix M, normals through its inverse transpose (then normalised), tangents through M's
//!   upper 3x3 with their handedness w negated where det M < 0.
//! - A transform with a negative determinant mirrors the mesh and would turn its
//!   counter-clockwise front faces clockwise (section 3.7.2.1: "When a mesh primitive uses any
//!   triangle-based topology, the determinant of the node's global transform defines the
//!   winding order"), so those triangles get two vertices swapped.
//! - UVs: glTF's v = 0 is the image's top row (section 3.8.4.1); vkrt stores OBJ's convention,
//!   v = 0 the bottom (shaders/include/texture.glsl), so v is stored as 1 - v, after the
//!   material's KHR_texture_transform.

use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use super::at;
use super::materials::{transform_uv, MaterialTable};
use std::collections::BTreeMap;

use crate::scene::assemble::{push_triangle, MAX_PLACED_TRIANGLES};
use crate::scene::{Scene, Triangle, MAX_PRIMITIVES};

/// How many copies the placed nodes make of each mesh (counted from the nodes, times each
/// node's `EXT_mesh_gpu_instancing` instance count), by mesh index. Fails, with the count,
/// before anything is read, if the meshes placed once (each expanded into the scene) would
/// pass [`MAX_PLACED_TRIANGLES`] triangles, or every copy counted [`MAX_PRIMITIVES`] (a mesh
/// placed more than once is kept once, `scene::instance`). Triangles are counted from the
/// accessors' element counts.
pub fn count_copies(placed: &[super::nodes::Placed], document: &::gltf::Document, file: &Path) -> anyhow::Result<BTreeMap<usize, u64>> {
    let mut copies: BTreeMap<usize, u64> = BTreeMap::new();
    for p in placed {
        let Some(mesh) = p.node.mesh() else { continue };
        let entry = copies.entry(mesh.index()).or_default();
        *entry = entry.saturating_add(super::instancing::copies(&p.node, document, file)?);
    }
    let (mut expanded, mut all) = (0u64, 0u64);
    for (&index, &n) in &copies {
        let Some(mesh) = document.meshes().nth(index) else { continue };
        let mut mesh_triangles = 0u64;
        for prim in mesh.primitives() {
            let corners = prim.indices().map(|a| a.count()).or_else(|| prim.get(&::gltf::Semantic::Positions).map(|a| a.count())).unwrap_or(0) as u64;
            mesh_triangles += match prim.mode() {
                ::gltf::mesh::Mode::Triangles => corners / 3,
                ::gltf::mesh::Mode::TriangleStrip | ::gltf::mesh::Mode::TriangleFan => corners.saturating_sub(2),
                _ => 0,
            };
        }
        if n == 1 {
            expanded += mesh_triangles;
        }
        all = all.saturating_add(mesh_triangles.saturating_mul(n));
    }
    let placements: u64 = copies.values().fold(0u64, |a, &n| a.saturating_add(n));
    if expanded > MAX_PLACED_TRIANGLES {
        let msg = format!("the meshes placed once hold {expanded} triangles; vkrt copies each into the scene and takes at most {MAX_PLACED_TRIANGLES}");
        return Err(at(file, "nodes", msg));
    }
    if all > MAX_PRIMITIVES {
        let msg = format!("the scene places {placements} meshes with {all} triangles in all; a primitive id names at most {MAX_PRIMITIVES}");
        return Err(at(file, "nodes", msg));
    }
    Ok(copies)
}

/// Adds every primitive of `mesh`, placed by `world`, to the scene (degenerate triangles
/// dropped as the other loaders do, `Scene::tangents` kept in step). With the identity, the
/// mesh in object space: what an `InstanceGroup` keeps.
pub fn add_mesh(scene: &mut Scene, mesh: &::gltf::Mesh, world: Mat4, buffers: &[Vec<u8>], materials: &MaterialTable, file: &Path) -> anyhow::Result<()> {
    for prim in mesh.primitives() {
        let loc = format!("meshes[{}].primitives[{}]", mesh.index(), prim.index());
        let material = materials.index(prim.material().index());
        let uv_transform = materials.uv_transform.get(material as usize).copied().flatten();
        let v = read_vertices(&prim, buffers, file, &loc)?;
        let corners = triangle_corners(&prim, buffers, v.positions.len(), file, &loc)?;

        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        let det = Mat3::from_mat4(world).determinant();
        let mirrored = det < 0.0;
        let w_sign = if mirrored { -1.0 } else { 1.0 };
        let positions: Vec<Vec3> = v.positions.iter().map(|&p| world.transform_point3(Vec3::from(p))).collect();
        let normals: Option<Vec<Vec3>> = v.normals.map(|ns| ns.iter().map(|&n| (normal_matrix * Vec3::from(n)).normalize_or_zero()).collect());
        let uvs: Option<Vec<Vec2>> = v.uvs.map(|uvs| {
            uvs.iter()
                .map(|&uv| {
                    let uv = Vec2::from(uv);
                    let uv = uv_transform.map_or(uv, |m| transform_uv(&m, uv));
                    Vec2::new(uv.x, 1.0 - uv.y)
                })
                .collect()
        });
        let tangents: Option<Vec<Vec4>> = v.tangents.map(|ts| {
            ts.iter()
                .map(|&t| {
                    let xyz = world.transform_vector3(Vec3::new(t[0], t[1], t[2])).normalize_or_zero();
                    xyz.extend(if t[3] < 0.0 { -w_sign } else { w_sign })
                })
                .collect()
        });
        for mut c in corners {
            if mirrored {
                c.swap(1, 2);
            }
            let t =
                Triangle { p: c.map(|i| positions[i]), n: normals.as_ref().map(|n| c.map(|i| n[i])), uv: uvs.as_ref().map(|uv| c.map(|i| uv[i])), material };
            if push_triangle(scene, t) {
                scene.tangents.push(tangents.as_ref().map_or([Vec4::ZERO; 3], |ts| c.map(|i| ts[i])));
            }
        }
    }
    Ok(())
}

/// A primitive's vertex attributes, each as long as `positions`.
struct Vertices {
    positions: Vec<[f32; 3]>,
    normals: Option<Vec<[f32; 3]>>,
    tangents: Option<Vec<[f32; 4]>>,
    uvs: Option<Vec<[f32; 2]>>,
}

fn read_vertices(prim: &::gltf::Primitive, buffers: &[Vec<u8>], file: &Path, loc: &str) -> anyhow::Result<Vertices> {
    use ::gltf::mesh::Semantic;
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    use ::gltf::accessor::DataType::{F32, U16, U8};
    // The crate reads the first three as f32 whatever their accessor says; the core spec
    // requires float for them (KHR_mesh_quantization, which allows integers, is not supported).
    // Texture coordinates may also be normalized unsigned bytes or shorts (section 3.7.2.1).
    let allowed: [(Semantic, &str, &[DataType], Dimensions); 4] = [
        (Semantic::Positions, "POSITION", &[F32], Dimensions::Vec3),
        (Semantic::Normals, "NORMAL", &[F32], Dimensions::Vec3),
        (Semantic::Tangents, "TANGENT", &[F32], Dimensions::Vec4),
        (Semantic::TexCoords(0), "TEXCOORD_0", &[F32, U8, U16], Dimensions::Vec2),
    ];
    for (semantic, name, types, dimensions) in allowed {
        if let Some(a) = prim.get(&semantic) {
            check_accessor(&a, name, types, dimensions).map_err(|msg| at(file, loc, msg))?;
        }
    }
    let unreadable = |name: &str, a: Option<::gltf::Accessor>| {
        let which = a.map_or(String::new(), |a| format!(" (accessor {})", a.index()));
        at(file, loc, format!("{name}{which} cannot be read: it lies outside its buffer or buffer view"))
    };
    if prim.get(&Semantic::Positions).is_none() {
        return Err(at(file, loc, "the primitive has no POSITION attribute"));
    }
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or_else(|| unreadable("POSITION", prim.get(&Semantic::Positions)))?.collect();
    let n = positions.len();
    let same_length = |name: &str, len: usize| -> anyhow::Result<()> {
        if len == n {
            Ok(())
        } else {
            Err(at(file, loc, format!("{name} has {len} elements but POSITION has {n}")))
        }
    };
    let normals = match prim.get(&Semantic::Normals) {
        None => None,
        Some(a) => Some(reader.read_normals().ok_or_else(|| unreadable("NORMAL", Some(a)))?.collect::<Vec<_>>()),
    };
    let tangents = match prim.get(&Semantic::Tangents) {
        None => None,
        Some(a) => Some(reader.read_tangents().ok_or_else(|| unreadable("TANGENT", Some(a)))?.collect::<Vec<_>>()),
    };
    let uvs = match prim.get(&Semantic::TexCoords(0)) {
        None => None,
        Some(a) => Some(reader.read_tex_coords(0).ok_or_else(|| unreadable("TEXCOORD_0", Some(a)))?.into_f32().collect::<Vec<_>>()),
    };
    if let Some(v) = &normals {
        same_length("NORMAL", v.len())?;
    }
    if let Some(v) = &tangents {
        same_length("TANGENT", v.len())?;
    }
    if let Some(v) = &uvs {
        same_length("TEXCOORD_0", v.len())?;
    }
    Ok(Vertices { positions, normals, tangents, uvs })
}

/// The vertex indices of each triangle, in the primitive's order (section 3.7.2.1).
fn triangle_corners(prim: &::gltf::Primitive, buffers: &[Vec<u8>], vertex_count: usize, file: &Path, loc: &str) -> anyhow::Result<Vec<[usize; 3]>> {
    use ::gltf::mesh::Mode;
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let indices: Vec<usize> = match prim.indices() {
        None => (0..vertex_count).collect(),
        Some(a) => {
            // Spec section 3.7.2.1: scalars of unsigned byte, short or int.
            use ::gltf::accessor::DataType::{U16, U32, U8};
            check_accessor(&a, "indices", &[U8, U16, U32], Dimensions::Scalar).map_err(|msg| at(file, loc, msg))?;
            let read =
                reader.read_indices().ok_or_else(|| at(file, loc, format!("indices (accessor {}) cannot be read: it lies outside its buffer", a.index())))?;
            let indices: Vec<usize> = read.into_u32().map(|i| i as usize).collect();
            if let Some((k, &i)) = indices.iter().enumerate().find(|(_, &i)| i >= vertex_count) {
                let msg = format!("index {k} is {i}, but the primitive has {vertex_count} vertices");
                return Err(at(file, loc, msg));
            }
            indices
        }
    };
    let n = indices.len();
    let v = |k: usize| indices[k];
    Ok(match prim.mode() {
        Mode::Triangles => indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
        // p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}: every other triangle reversed to keep the winding.
        Mode::TriangleStrip => (0..n.saturating_sub(2)).map(|i| [v(i), v(i + 1 + i % 2), v(i + 2 - i % 2)]).collect(),
        // p_i = {v_{i+1}, v_{i+2}, v_0}.
        Mode::TriangleFan => (0..n.saturating_sub(2)).map(|i| [v(i + 1), v(i + 2), v(0)]).collect(),
        mode => {
            let name = match mode {
                Mode::Points => "POINTS",
                Mode::Lines => "LINES",
                Mode::LineLoop => "LINE_LOOP",
                _ => "LINE_STRIP",
            };
            let msg = format!("mode {} ({name}) is not supported: vkrt renders triangles only (modes 4, 5, 6)", mode.as_gl_enum());
            return Err(at(file, loc, msg));
        }
    })
}

/// An accessor holds what the spec allows for its use (`name`): one of `types`, `dimensions`,
/// and a buffer view stride no smaller than an element. The crate's readers assume all three
/// (an unexpected component type is `unreachable!`, the others debug assertions), so a file
/// that breaks them is an error here, not a panic there.
fn check_accessor(a: &::gltf::Accessor, name: &str, types: &[DataType], dimensions: Dimensions) -> Result<(), String> {
    if !types.contains(&a.data_type()) {
        return Err(format!("{name} accessor {} is {}, not {}", a.index(), type_names(&[a.data_type()]), type_names(types)));
    }
    if a.dimensions() != dimensions {
        return Err(format!("{name} accessor {} is {:?}, not {dimensions:?}", a.index(), a.dimensions()));
    }
    if let Some(stride) = a.view().and_then(|v| v.stride()).filter(|&s| s < a.size()) {
        return Err(format!("{name} accessor {}: byteStride {stride} is less than its {}-byte element", a.index(), a.size()));
    }
    Ok(())
}

/// glTF's names for component types: "UNSIGNED_BYTE or FLOAT".
pub(super) fn type_names(types: &[DataType]) -> String {
    let name = |t: &DataType| match t {
        DataType::I8 => "BYTE",
        DataType::U8 => "UNSIGNED_BYTE",
        DataType::I16 => "SHORT",
        DataType::U16 => "UNSIGNED_SHORT",
        DataType::U32 => "UNSIGNED_INT",
        DataType::F32 => "FLOAT",
    };
    let names: Vec<&str> = types.iter().map(name).collect();
    names.join(" or ")
}
