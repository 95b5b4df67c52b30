//! The planar mirrors the path tracer samples light through (shaders/include/mirror_light.glsl).
//!
//! Light that reaches a diffuse surface by way of a mirror (a caustic: lamp -> mirror -> wall)
//! is found by BSDF sampling alone unless next-event estimation can aim through the mirror: the
//! Mirror Cornell box's tall box throws the ceiling light over the back wall and the ceiling,
//! and that light was most of the image's error. A flat mirror is the one case where aiming is
//! exact: the light seen in it is the light seen from the point's mirror image, so light
//! sampling from that image point gives the path point -> mirror -> lamp in closed form (the
//! planar case of manifold next-event estimation, Hanika et al. 2015).
//!
//! Which triangles qualify is decided here once, for both the light-sampling side (the list)
//! and the BSDF-sampling side (`MATERIAL_PLANAR_MIRROR` on the material, which the path
//! tracer reads where a path bounces off a mirror): their MIS weights must agree path by path.
//! A material qualifies if it is a plain mirror (not a dielectric or metallic-roughness, no
//! texture, cut-out or normal map: the reflectance and the lobe choice are the same at every
//! point) and every triangle using it is flat (vertex normals along the face normal, so the
//! reflection is about the plane the virtual image is taken in).

use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuMaterial, GpuMirror, GpuMirrorPlane, GpuShading, GpuTriangle};
use glam::Vec3;

/// How far a vertex normal may turn from the face normal (1 - cosine) for the face to count as
/// flat: float rounding of a file's normals, not shading.
const FLAT_TOLERANCE: f32 = 1e-6;

/// The materials with `MATERIAL_PLANAR_MIRROR` set where they qualify, and the triangles
/// (in `triangles` order) of those materials.
pub fn planar_mirrors(triangles: &[GpuTriangle], shading: &[GpuShading], materials: &[GpuMaterial]) -> (Vec<GpuMaterial>, Vec<GpuMirror>) {
    let mut qualifies: Vec<bool> = materials.iter().map(plain_mirror).collect();
    let material_of = |t: &GpuTriangle| shading.get(t.prim as usize).map(|s| s.material as usize);
    for t in triangles {
        let Some(m) = material_of(t) else { continue };
        if qualifies.get(m).copied().unwrap_or(false) && !is_flat(t, &shading[t.prim as usize]) {
            qualifies[m] = false;
        }
    }
    let mut flagged = materials.to_vec();
    for (m, q) in flagged.iter_mut().zip(&qualifies) {
        if *q {
            m.flags |= MATERIAL_PLANAR_MIRROR;
        }
    }
    // Files repeat faces (the Mirror Cornell box's "bottom face" indexes its front face again):
    // each vertex set is listed once. Overlaps that are not repeats are handled by the planes
    // (`by_plane`).
    let mut seen = std::collections::HashSet::new();
    let mirrors = triangles
        .iter()
        .filter_map(|t| {
            let m = material_of(t)?;
            let mut key = [t.v0, t.v1, t.v2].map(|v| v.map(f32::to_bits));
            key.sort();
            (qualifies.get(m).copied().unwrap_or(false) && seen.insert(key)).then_some(GpuMirror {
                v0: t.v0,
                material: m as u32,
                v1: t.v1,
                _pad0: 0,
                v2: t.v2,
                _pad1: 0,
            })
        })
        .collect::<Vec<GpuMirror>>();
    (flagged, mirrors)
}

/// Whether `m` is a plain mirror, one whose flat triangles light sampling may aim through.
pub fn plain_mirror(m: &GpuMaterial) -> bool {
    m.flags & MATERIAL_MIRROR != 0
        && m.flags & (MATERIAL_DIELECTRIC | MATERIAL_METALLIC_ROUGHNESS | MATERIAL_ALPHA | MATERIAL_NORMAL_MAP) == 0
        && m.specular.iter().any(|&k| k > 0.0)
        && m.diffuse_texture == TEXTURE_NONE
        && m.emission_texture == TEXTURE_NONE
}

/// The most mirror planes light sampling aims through. It picks one plane uniformly, so with
/// many planes most aims miss (a faceted mirror ball): past this the scene's mirrors are left
/// to BSDF sampling alone, and grouping stops before its cost (planes x triangles) grows.
pub const MAX_MIRROR_PLANES: usize = 64;
/// The most triangles of one plane: an aim is tested against each (three texel fetches), so a
/// finely meshed flat mirror is left to BSDF sampling too. Limits drop all mirrors, never some:
/// the BSDF side weighs every path off a `MATERIAL_PLANAR_MIRROR` material against light
/// sampling, which must then be able to aim through it.
pub const MAX_PLANE_TRIANGLES: usize = 32;

/// How far (relative to the coordinates' magnitude) a vertex may lie off a plane and still be on it.
const PLANE_TOLERANCE: f32 = 1e-5;

/// `mirrors` sorted into groups of one plane and one material, and the groups. Light sampling
/// picks a group and tests the point it aims at against all of the group's triangles: a path
/// through a mirror is aimed at from one group whichever of its triangles, overlapping or
/// not, holds the point (two triangulations of one face, a face given twice), so the
/// density the MIS weights use, one over the number of groups, is the true one. (If one point
/// lies on triangles of two materials in one plane, it is aimed at from both groups: such a
/// z-fighting mirror is counted twice. Files do not do that on purpose.) Nothing if there are
/// more than [`MAX_MIRROR_PLANES`], or a plane of more than [`MAX_PLANE_TRIANGLES`].
pub fn by_plane(mirrors: &[GpuMirror]) -> (Vec<GpuMirror>, Vec<GpuMirrorPlane>) {
    // (unit normal with its largest component positive, offset, material) of each group.
    let mut groups: Vec<(Vec3, f32, u32, Vec<GpuMirror>)> = Vec::new();
    for m in mirrors {
        let (a, b, c) = (Vec3::from(m.v0), Vec3::from(m.v1), Vec3::from(m.v2));
        let mut n = (b - a).cross(c - a).normalize_or_zero();
        if n == Vec3::ZERO {
            continue;
        }
        if n.max_element() < -n.min_element() {
            n = -n;
        }
        let scale = a.abs().max(b.abs()).max(c.abs()).max_element().max(1.0);
        let on = |g: &(Vec3, f32, u32, Vec<GpuMirror>)| {
            g.2 == m.material && [a, b, c].iter().all(|v| (g.0.dot(*v) - g.1).abs() <= PLANE_TOLERANCE * scale) && g.0.dot(n).abs() >= 1.0 - PLANE_TOLERANCE
        };
        match groups.iter().position(on) {
            Some(g) => groups[g].3.push(*m),
            None if groups.len() == MAX_MIRROR_PLANES => return (Vec::new(), Vec::new()),
            None => groups.push((n, n.dot(a), m.material, vec![*m])),
        }
    }
    if groups.iter().any(|g| g.3.len() > MAX_PLANE_TRIANGLES) {
        return (Vec::new(), Vec::new());
    }
    let mut sorted = Vec::with_capacity(mirrors.len());
    let mut planes = Vec::with_capacity(groups.len());
    for (_, _, _, members) in groups {
        planes.push(GpuMirrorPlane { first: sorted.len() as u32, count: members.len() as u32, _pad0: 0, _pad1: 0 });
        sorted.extend(members);
    }
    (sorted, planes)
}

/// True if the triangle has an area and its vertex normals lie along its face normal (either side).
fn is_flat(t: &GpuTriangle, s: &GpuShading) -> bool {
    let (a, b, c) = (Vec3::from(t.v0), Vec3::from(t.v1), Vec3::from(t.v2));
    let n = (b - a).cross(c - a);
    // Zero area or NaN vertices: not a mirror to aim at.
    if n.length_squared().is_nan() || n.length_squared() <= 0.0 {
        return false;
    }
    let n = n.normalize();
    [s.n0, s.n1, s.n2].iter().all(|v| {
        let v = Vec3::from(*v);
        v.length_squared() > 0.0 && 1.0 - v.normalize().dot(n).abs() <= FLAT_TOLERANCE
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(flags: u32) -> GpuMaterial {
        GpuMaterial {
            flags,
            specular: [0.9; 3],
            diffuse_texture: TEXTURE_NONE,
            alpha_texture: TEXTURE_NONE,
            emission_texture: TEXTURE_NONE,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    fn triangle(prim: u32, z: f32) -> GpuTriangle {
        GpuTriangle { v0: [0.0, 0.0, z], prim, v1: [1.0, 0.0, z], shading: 0, v2: [0.0, 1.0, z], _pad1: 0 }
    }

    fn shading(material: u32, n: [[f32; 3]; 3]) -> GpuShading {
        GpuShading { n0: n[0], material, n1: n[1], _pad0: 0, n2: n[2], _pad1: 0 }
    }

    #[test]
    fn flat_plain_mirrors_qualify_and_smooth_or_textured_ones_do_not() {
        let up = [[0.0, 0.0, 1.0]; 3];
        let tilted = [[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0]];
        let mut textured = material(MATERIAL_MIRROR);
        textured.diffuse_texture = 0;
        // Materials: 0 a flat mirror (two triangles, one facing down), 1 a mirror with one
        // smooth-shaded triangle, 2 a textured mirror, 3 Lambert, 4 a dielectric.
        let materials = [material(MATERIAL_MIRROR), material(MATERIAL_MIRROR), textured, material(0), material(MATERIAL_MIRROR | MATERIAL_DIELECTRIC)];
        let shading = [shading(0, up), shading(0, [[0.0, 0.0, -1.0]; 3]), shading(1, up), shading(1, tilted), shading(2, up), shading(3, up), shading(4, up)];
        let triangles: Vec<GpuTriangle> = (0..shading.len() as u32).map(|p| triangle(p, p as f32)).collect();
        let (flagged, mirrors) = planar_mirrors(&triangles, &shading, &materials);
        let planar: Vec<bool> = flagged.iter().map(|m| m.flags & MATERIAL_PLANAR_MIRROR != 0).collect();
        assert_eq!(planar, [true, false, false, false, false]);
        assert_eq!(mirrors.len(), 2);
        assert!(mirrors.iter().all(|m| m.material == 0));
        assert_eq!(mirrors[1].v0, [0.0, 0.0, 1.0], "the list follows the triangle order");
        // A repeated face (same vertices, another order) is listed once.
        let mut repeated = triangles.clone();
        repeated.push(GpuTriangle { v0: triangles[0].v2, v2: triangles[0].v0, ..triangles[0] });
        assert_eq!(planar_mirrors(&repeated, &shading, &materials).1.len(), 2);
        // Nothing else about the materials changes.
        for (a, b) in flagged.iter().zip(&materials) {
            assert_eq!(a.flags & !MATERIAL_PLANAR_MIRROR, b.flags);
        }
    }

    fn mirror(v: [[f32; 3]; 3], material: u32) -> GpuMirror {
        GpuMirror { v0: v[0], material, v1: v[1], _pad0: 0, v2: v[2], _pad1: 0 }
    }

    #[test]
    fn mirrors_group_by_plane_and_material() {
        // A quad in z = 1 in two triangles, the same quad cut along the other diagonal (facing
        // the other way), a triangle in z = 2, and one in z = 1 of another material.
        let quad = [mirror([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]], 0), mirror([[0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]], 0)];
        let other_cut = [mirror([[1.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 1.0, 1.0]], 0), mirror([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0]], 0)];
        let higher = mirror([[0.0, 0.0, 2.0], [1.0, 0.0, 2.0], [0.0, 1.0, 2.0]], 0);
        let other_material = mirror([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]], 1);
        let all = [quad[0], higher, other_cut[0], other_material, quad[1], other_cut[1]];
        let (sorted, planes) = by_plane(&all);
        assert_eq!(sorted.len(), all.len());
        let counts: Vec<u32> = planes.iter().map(|p| p.count).collect();
        assert_eq!(counts, [4, 1, 1]);
        assert!(sorted[..4].iter().all(|m| m.material == 0 && m.v0[2] == 1.0));
        assert_eq!((sorted[4].v0[2], sorted[5].material), (2.0, 1));
        assert_eq!((planes[1].first, planes[2].first), (4, 5));
        // A faceted mirror of more planes than light sampling aims through: none.
        let facets: Vec<GpuMirror> = (0..=MAX_MIRROR_PLANES).map(|k| mirror([[0.0, 0.0, k as f32], [1.0, 0.0, k as f32], [0.0, 1.0, k as f32]], 0)).collect();
        assert_eq!(by_plane(&facets[..MAX_MIRROR_PLANES]).1.len(), MAX_MIRROR_PLANES);
        assert!(by_plane(&facets).0.is_empty() && by_plane(&facets).1.is_empty());
        // A finely meshed flat mirror: none either.
        let mesh: Vec<GpuMirror> =
            (0..=MAX_PLANE_TRIANGLES).map(|k| mirror([[k as f32, 0.0, 1.0], [k as f32 + 1.0, 0.0, 1.0], [k as f32, 1.0, 1.0]], 0)).collect();
        assert_eq!(by_plane(&mesh[..MAX_PLANE_TRIANGLES]).1.len(), 1);
        assert!(by_plane(&mesh).1.is_empty());
    }
}
