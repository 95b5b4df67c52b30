//! Tangents for normal mapping: MikkTSpace (Mikkelsen 2008, "Simulation of wrinkled surfaces
//! revisited"), the tangent frame glTF 2.0 prescribes when a file has none ("When tangents are
//! not specified, client implementations SHOULD calculate tangents using default MikkTSpace
//! algorithms") and that normal-map bakers use, so a baked map reads back as it was baked.
//!
//! A tangent is (xyz, w): xyz along increasing u in the triangle's plane, and the bitangent
//! w * cross(normal, tangent) along increasing v (glTF's TANGENT; surface.glsl builds the frame
//! from it). Only triangles whose material has a normal map get tangents, and only where the
//! file gave none (zero entries of `Scene::tangents`).

use super::{Scene, Triangle};
use glam::{Vec3, Vec4};

/// Fills the zero entries of `scene.tangents` of normal-mapped triangles with MikkTSpace
/// tangents (sizing `tangents` to the triangles first), and those of each instanced mesh's in
/// object space (the copies place them). Does nothing when no material has a normal map.
/// Vertices are welded by MikkTSpace itself (same position, normal and uv), so triangles that
/// share a vertex share its tangent. Triangles without texture coordinates get MikkTSpace's
/// fallback frame; their normal map has no defined orientation anyway.
pub fn fill_missing_tangents(scene: &mut Scene) {
    let mapped: Vec<bool> = scene.materials.iter().map(|m| m.normal_texture.is_some()).collect();
    if !mapped.iter().any(|&m| m) {
        return;
    }
    let mut failed = fill(&scene.triangles, &mut scene.tangents, &mapped);
    for g in &mut scene.instances {
        failed += fill(&g.mesh, &mut g.tangents, &mapped);
    }
    if failed > 0 {
        scene.stats.warn(format!("MikkTSpace made no tangents for {failed} normal-mapped triangles: their normal maps are ignored"));
    }
}

/// [`fill_missing_tangents`] for one list of triangles and its tangents; returns how many
/// normal-mapped triangles MikkTSpace gave none.
fn fill(triangles: &[Triangle], tangents: &mut Vec<[Vec4; 3]>, mapped: &[bool]) -> usize {
    tangents.resize(triangles.len(), [Vec4::ZERO; 3]);
    let missing: Vec<usize> = (0..triangles.len())
        .filter(|&i| mapped.get(triangles[i].material as usize).copied().unwrap_or(false) && tangents[i].iter().all(|t| t.truncate() == Vec3::ZERO))
        .collect();
    if missing.is_empty() {
        return 0;
    }
    let mut geometry = Faces { triangles, faces: &missing, out: vec![[Vec4::ZERO; 3]; missing.len()] };
    if !mikktspace::generate_tangents(&mut geometry) {
        return missing.len();
    }
    for (&i, t) in missing.iter().zip(geometry.out) {
        tangents[i] = t;
    }
    0
}

/// The triangles `faces` of a list as MikkTSpace sees them, and the tangents it gives back.
struct Faces<'a> {
    triangles: &'a [Triangle],
    faces: &'a [usize],
    out: Vec<[Vec4; 3]>,
}

impl mikktspace::Geometry for Faces<'_> {
    fn num_faces(&self) -> usize {
        self.faces.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.triangles[self.faces[face]].p[vert].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        let t = &self.triangles[self.faces[face]];
        t.n.map_or_else(|| t.cross().normalize_or_zero(), |n| n[vert]).to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.triangles[self.faces[face]].uv.map_or([0.0; 2], |uv| uv[vert].to_array())
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.out[face][vert] = Vec4::from_array(tangent);
    }
}
