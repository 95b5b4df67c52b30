//! The shading data of a two-level BVH (`accel::two_level`): one block per mesh, in object
//! space, instead of an entry per copy of each triangle. A mesh's entries are its first copy's
//! (the scene's, in the world) turned back into object space: normals by the transpose of the
//! placement's linear part (the inverse of the inverse transpose that placed them), tangents by
//! its inverse, a mirror's swap of the second and third vertices undone. The shaders turn them
//! out again into each hit copy's world (`instance.glsl`, `surface.glsl`). Emitters keep their
//! world triangles (one per copy: each copy is its own light) and name their shading entry.

use glam::{Mat3, Vec3};

use super::SceneBuffers;
use crate::accel::two_level::Mesh;
use crate::gpu_abi::constants::EMITTER_SWAPPED;
use crate::gpu_abi::{GpuShading, GpuTangents, GpuUv};
use crate::scene::Scene;

/// `buffers` (by the scene's primitive ids) made per mesh of `meshes` (`two_level::meshes`).
pub fn per_mesh(buffers: &mut SceneBuffers, scene: &Scene, meshes: &[Mesh]) {
    let mut entry_of = vec![u32::MAX; scene.triangles.len()];
    let mut swapped = vec![false; scene.triangles.len()];
    let (mut shading, mut uvs, mut tangents) = (Vec::new(), Vec::new(), Vec::new());
    for mesh in meshes {
        let base = shading.len() as u32;
        // The scene's primitives whose entry this mesh's is: every copy's, or the rest's own.
        if mesh.copies.is_empty() {
            for (k, &prim) in mesh.prims.iter().enumerate() {
                entry_of[prim as usize] = base + k as u32;
            }
        }
        for &(first, placement) in &mesh.copies {
            for i in 0..mesh.positions.len() as u32 {
                entry_of[(first + i) as usize] = base + i;
                swapped[(first + i) as usize] = placement.mirrored();
            }
        }
        let (linear, mirrored) = mesh.placement().map_or((Mat3::IDENTITY, false), |p| (Mat3::from_mat4(p.world()), p.mirrored()));
        let to_object_normal = linear.transpose();
        let to_object_tangent = linear.inverse();
        let order = |mut a: [[f32; 3]; 3]| {
            if mirrored {
                a.swap(1, 2);
            }
            a
        };
        for i in 0..mesh.positions.len() {
            let p = mesh.shading_from(i) as usize;
            let s = buffers.shading[p];
            let n = order([s.n0, s.n1, s.n2]).map(|n| (to_object_normal * Vec3::from(n)).normalize_or_zero().to_array());
            shading.push(GpuShading { n0: n[0], n1: n[1], n2: n[2], ..s });
            if let Some(uv) = buffers.uvs.get(p) {
                let (uv1, uv2) = if mirrored { (uv.uv2, uv.uv1) } else { (uv.uv1, uv.uv2) };
                uvs.push(GpuUv { uv1, uv2, ..*uv });
            }
            if let Some(t) = buffers.tangents.get(p) {
                let sign = if mirrored { -1.0 } else { 1.0 };
                let object = |t: [f32; 4]| (to_object_tangent * Vec3::new(t[0], t[1], t[2])).normalize_or_zero().extend(t[3] * sign).to_array();
                let (t1, t2) = if mirrored { (t.t2, t.t1) } else { (t.t1, t.t2) };
                tangents.push(GpuTangents { t0: object(t.t0), t1: object(t1), t2: object(t2) });
            }
        }
    }
    for e in &mut buffers.emitters {
        if swapped.get(e.prim as usize).copied().unwrap_or(false) {
            e.flags |= EMITTER_SWAPPED;
        }
        e.prim = entry_of.get(e.prim as usize).copied().unwrap_or(e.prim);
    }
    buffers.shading = shading;
    buffers.uvs = uvs;
    buffers.tangents = tangents;
}
