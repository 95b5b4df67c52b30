//! The shading data of a two-level BVH (`accel::two_level`): one block per mesh, in the
//! meshes' order (`two_level::meshes`: each instance group's, then the scene's own
//! triangles), instead of an entry per copy of each triangle. An instanced mesh's entries are
//! its object-space data as the loader kept it (`scene::instance::InstanceGroup`); the shaders
//! turn them out into each hit copy's world (`instance.glsl`, `surface.glsl`). Emitters are
//! one per copy of each emitting triangle (each copy is its own light), in the world, in
//! primitive-id order, each naming its mesh's entry.

use super::scene_buffers::emitter;
use super::SceneBuffers;
use crate::gpu_abi::constants::EMITTER_SWAPPED;
use crate::scene::Scene;

/// The scene's arrays with a block of shading data per mesh of its two-level BVH.
pub fn per_mesh(scene: &Scene) -> SceneBuffers {
    let mut b = SceneBuffers::without_triangles(scene);
    let group_bases: Vec<u32> = scene.instances.iter().map(|g| b.add_block(scene, &g.mesh, &g.tangents)).collect();
    let own_base = b.add_block(scene, &scene.triangles, &scene.tangents);
    // Emitters in primitive-id order: the scene's own, then each group's copy by copy.
    b.add_own_emitters(scene, own_base);
    for (g, base) in scene.instances.iter().zip(group_bases) {
        let emitting: Vec<usize> = (0..g.mesh.len()).filter(|&i| scene.is_emissive(&g.mesh[i])).collect();
        for (c, placement) in g.placements.iter().enumerate() {
            // A mirrored copy's placed triangle has its second and third vertices swapped
            // against its shading entry's.
            let flags = if placement.mirrored() { EMITTER_SWAPPED } else { 0 };
            b.emitters.extend(emitting.iter().map(|&i| emitter(scene, &g.placed(c, i), base + i as u32, flags)));
        }
    }
    b
}
