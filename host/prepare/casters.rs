//! The caustic casters the path tracer aims some of its diffuse bounces at
//! (shaders/include/caster_guide.glsl).
//!
//! Light a curved glossy, mirror or glass object throws onto diffuse surfaces (lamp -> sphere
//! -> wall: a caustic) reaches a wall point only through a small spot of the object, and only a
//! cosine-sampled bounce that happens to hit that spot finds it: on the Sphere Cornell box
//! (a Ks 1, Ns 1000 ball) those rare, bright paths were 70 % of the image's error, fireflies all
//! over the walls. Light sampling cannot aim through a curved object in closed form (that takes
//! manifold walks, Hanika et al. 2015), but BSDF sampling can be told where such objects are:
//! a share of each diffuse bounce is drawn towards a caster, uniformly in the cone of its
//! bounding sphere and, for a ball, in a narrow cone around the spot where it would mirror the
//! lights' centre towards the point; the bounce's density is then the mixture's, so the
//! estimate stays unbiased whatever the proposal (a one-sample mixture, Veach 1997, 9.2.2).
//!
//! Decided at every upload from the triangles, like the planar mirrors (`super::mirrors`).

use crate::geom::Aabb;
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuCaster, GpuEmitter, GpuMaterial, GpuShading, GpuTriangle};
use glam::Vec3;
use std::collections::HashMap;

/// The most casters a scene's bounces are aimed at. A bounce aims at one of them, picked
/// uniformly: with many (a table of glass marbles) each gets too small a share to pay for the
/// aimed rays that miss, and the scene is left to plain BSDF sampling.
pub const MAX_CASTERS: usize = 8;
/// A glossy lobe casts a caustic worth aiming at if it reflects at least this much (max Ks) ...
const MIN_GLOSSY_KS: f32 = 0.5;
/// ... and is at most this rough (GGX alpha; Ns >= 48): a rougher lobe spreads the light it
/// reflects, which cosine sampling and light sampling at the lobe then find well enough.
const MAX_GLOSSY_ALPHA: f32 = 0.2;
/// A piece larger than this share of the scene's bounding radius is no caster: most points
/// are inside its sphere or see it fill much of their sky, where cosine sampling hits it
/// anyway (the Water Cornell box's water surface).
const MAX_SCENE_SHARE: f32 = 0.5;
/// A caster is a ball (its spot can be aimed at) if no vertex is closer to the centre than this
/// share of the radius (tessellated spheres have every vertex on the sphere) and its box is
/// at least this share of the diameter on every axis (a square's corners lie on a circle too).
const BALL_MIN_RADIUS_SHARE: f32 = 0.9;

/// The glossy spread the spot cone allows for, in GGX alphas: a reflected direction rarely
/// turns further than 2 alpha from the mirror direction.
const SPOT_LOBE_ALPHAS: f32 = 2.0;

/// How a material casts a caustic, if it does.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Cast {
    /// Glass: light passes through, so the mirror spot does not apply.
    Through,
    /// A mirror (spread 0) or a sharp glossy lobe (its spread, radians).
    Reflect(f32),
}

/// Whether triangles of `m` may be a caster's (before the planar mirrors are flagged, a
/// plain mirror may: those are left out later).
pub fn casts(m: &GpuMaterial) -> bool {
    cast_of(m).is_some()
}

fn cast_of(m: &GpuMaterial) -> Option<Cast> {
    if m.flags & (MATERIAL_METALLIC_ROUGHNESS | MATERIAL_EMISSIVE) != 0 {
        return None;
    }
    if m.flags & MATERIAL_DIELECTRIC != 0 {
        return Some(Cast::Through);
    }
    let ks = m.specular.iter().copied().fold(0.0f32, f32::max);
    if m.flags & MATERIAL_MIRROR != 0 {
        // Flat mirrors are sampled through exactly (`super::mirrors`).
        return (m.flags & MATERIAL_PLANAR_MIRROR == 0 && ks > 0.0).then_some(Cast::Reflect(0.0));
    }
    // The shader's alpha (bsdf.glsl, lobes_of).
    let alpha = (2.0 / (m.shininess.max(0.0) + 2.0)).sqrt().clamp(1e-3, 1.0);
    (ks >= MIN_GLOSSY_KS && alpha <= MAX_GLOSSY_ALPHA).then_some(Cast::Reflect(SPOT_LOBE_ALPHAS * alpha))
}

/// The casters of a scene: each connected piece (triangles joined by shared vertex positions)
/// of the triangles whose material casts, as its bounding sphere; none if there are more than
/// [`MAX_CASTERS`] or nothing emits light of any kind (`lights_present`); pieces larger than
/// [`MAX_SCENE_SHARE`] of the scene's bounding radius (`SceneInfo::radius`) are left out.
/// `materials` as uploaded (planar mirrors flagged). The spot is aimed at the emissive
/// triangles' bounding sphere; without emissive triangles only the whole-cone share is drawn.
pub fn caustic_casters(
    triangles: &[GpuTriangle],
    shading: &[GpuShading],
    materials: &[GpuMaterial],
    emitters: &[GpuEmitter],
    lights_present: bool,
    scene_radius: f32,
) -> Vec<GpuCaster> {
    if !lights_present && emitters.is_empty() {
        return Vec::new();
    }
    let casts: Vec<Option<Cast>> = materials.iter().map(cast_of).collect();
    let cast_of_triangle = |t: &GpuTriangle| {
        let m = shading.get(t.prim as usize)?.material as usize;
        casts.get(m).copied().flatten()
    };
    let members: Vec<(&GpuTriangle, Cast)> = triangles.iter().filter_map(|t| Some((t, cast_of_triangle(t)?))).collect();
    if members.is_empty() {
        return Vec::new();
    }
    // Union-find over the member triangles, joined where they share a vertex position.
    let mut parent: Vec<usize> = (0..members.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_at: HashMap<[u32; 3], usize> = HashMap::new();
    for (i, (t, _)) in members.iter().enumerate() {
        for v in [t.v0, t.v1, t.v2] {
            let key = v.map(f32::to_bits);
            match first_at.get(&key) {
                Some(&j) => {
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    parent[a] = b;
                }
                None => {
                    first_at.insert(key, i);
                }
            }
        }
    }
    // Per piece: its vertices and how it casts (a piece of mixed materials casts as its
    // sharpest: reflect over through, the smallest spread).
    let mut pieces: Vec<(usize, Vec<Vec3>, Cast)> = Vec::new();
    for (i, &(t, cast)) in members.iter().enumerate() {
        let r = root(&mut parent, i);
        let at = match pieces.iter().position(|p| p.0 == r) {
            Some(at) => at,
            None if pieces.len() == MAX_CASTERS => return Vec::new(),
            None => {
                pieces.push((r, Vec::new(), cast));
                pieces.len() - 1
            }
        };
        let piece = &mut pieces[at];
        piece.1.extend([t.v0, t.v1, t.v2].map(Vec3::from));
        piece.2 = match (piece.2, cast) {
            (Cast::Reflect(a), Cast::Reflect(b)) => Cast::Reflect(a.min(b)),
            (Cast::Reflect(a), Cast::Through) | (Cast::Through, Cast::Reflect(a)) => Cast::Reflect(a),
            (Cast::Through, Cast::Through) => Cast::Through,
        };
    }
    let emitter_vertices: Vec<Vec3> = emitters.iter().flat_map(|e| [e.v0, e.v1, e.v2].map(Vec3::from)).collect();
    let target = bounding_sphere(&emitter_vertices);
    pieces
        .into_iter()
        .filter_map(|(_, vertices, cast)| {
            let (center, radius, bounds) = bounding_sphere(&vertices)?;
            if radius.is_nan() || radius <= 0.0 || radius > MAX_SCENE_SHARE * scene_radius {
                return None;
            }
            let nearest = vertices.iter().map(|v| v.distance(center)).fold(f32::INFINITY, f32::min);
            let ball = nearest >= BALL_MIN_RADIUS_SHARE * radius && bounds.extent().min_element() >= BALL_MIN_RADIUS_SHARE * 2.0 * radius;
            let (target, target_radius, spread) = match (cast, target, ball) {
                (Cast::Reflect(s), Some((c, r, _)), true) => (c, r, s),
                _ => (Vec3::ZERO, 0.0, -1.0),
            };
            Some(GpuCaster { center: center.into(), radius, target: target.into(), target_radius, spot_spread: spread, _pad0: 0, _pad1: 0, _pad2: 0 })
        })
        .collect()
}

/// The sphere around the points' box centre through the farthest point (not the smallest
/// sphere, but a cone from it still holds every point), and the box; None without points.
fn bounding_sphere(points: &[Vec3]) -> Option<(Vec3, f32, Aabb)> {
    let bounds = Aabb::from_points(points);
    if bounds.is_empty() {
        return None;
    }
    let center = bounds.center();
    let radius = points.iter().map(|p| p.distance(center)).fold(0.0f32, f32::max);
    Some((center, radius, bounds))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material(flags: u32, ks: f32, ns: f32) -> GpuMaterial {
        GpuMaterial {
            flags,
            specular: [ks; 3],
            shininess: ns,
            diffuse_texture: TEXTURE_NONE,
            alpha_texture: TEXTURE_NONE,
            emission_texture: TEXTURE_NONE,
            ..bytemuck::Zeroable::zeroed()
        }
    }

    fn shading(material: u32) -> GpuShading {
        GpuShading { material, ..bytemuck::Zeroable::zeroed() }
    }

    fn triangle(prim: u32, v: [[f32; 3]; 3]) -> GpuTriangle {
        GpuTriangle { v0: v[0], prim, v1: v[1], shading: 0, v2: v[2], _pad1: 0 }
    }

    /// An octahedron of radius r around c: every vertex on the sphere (a ball).
    fn octahedron(c: Vec3, r: f32, prim0: u32) -> Vec<GpuTriangle> {
        let p = |v: Vec3| (c + r * v).into();
        let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
        let faces = [(x, y, z), (y, -x, z), (-x, -y, z), (-y, x, z), (y, x, -z), (-x, y, -z), (-y, -x, -z), (x, -y, -z)];
        faces.iter().enumerate().map(|(i, &(a, b, d))| triangle(prim0 + i as u32, [p(a), p(b), p(d)])).collect()
    }

    /// The bounding radius of the scene the test casters stand in: large against them.
    const ROOM_RADIUS: f32 = 5.0;

    fn emitter() -> GpuEmitter {
        GpuEmitter { v0: [-0.5, 2.0, -0.5], v1: [0.5, 2.0, -0.5], v2: [0.5, 2.0, 0.5], ..bytemuck::Zeroable::zeroed() }
    }

    #[test]
    fn which_materials_cast() {
        let alpha = |ns: f32| (2.0 / (ns + 2.0)).sqrt();
        assert_eq!(cast_of(&material(0, 1.0, 1000.0)), Some(Cast::Reflect(2.0 * alpha(1000.0))));
        // Too rough, too faint, plain diffuse.
        assert_eq!(cast_of(&material(0, 1.0, 20.0)), None);
        assert_eq!(cast_of(&material(0, 0.04, 1000.0)), None);
        assert_eq!(cast_of(&material(0, 0.0, 0.0)), None);
        assert_eq!(cast_of(&material(MATERIAL_MIRROR, 0.9, 0.0)), Some(Cast::Reflect(0.0)));
        // Flat mirrors are the planar mirrors' (light is aimed through them exactly).
        assert_eq!(cast_of(&material(MATERIAL_MIRROR | MATERIAL_PLANAR_MIRROR, 0.9, 0.0)), None);
        assert_eq!(cast_of(&material(MATERIAL_DIELECTRIC, 0.0, 0.0)), Some(Cast::Through));
        assert_eq!(cast_of(&material(MATERIAL_METALLIC_ROUGHNESS, 1.0, 1000.0)), None);
    }

    #[test]
    fn a_ball_is_one_caster_aimed_at_the_lights() {
        let tris = octahedron(Vec3::new(0.0, 0.5, 0.0), 0.3, 0);
        let shades: Vec<GpuShading> = (0..8).map(|_| shading(0)).collect();
        let casters = caustic_casters(&tris, &shades, &[material(0, 1.0, 1000.0)], &[emitter()], false, ROOM_RADIUS);
        assert_eq!(casters.len(), 1);
        let c = casters[0];
        assert!(Vec3::from(c.center).distance(Vec3::new(0.0, 0.5, 0.0)) < 1e-6);
        assert!((c.radius - 0.3).abs() < 1e-6);
        assert!((Vec3::from(c.target) - Vec3::new(0.0, 2.0, 0.0)).length() < 1e-6);
        assert!((c.target_radius - 0.5f32.sqrt()).abs() < 1e-6);
        assert!(c.spot_spread > 0.0);
    }

    #[test]
    fn pieces_split_by_shared_vertices_and_glass_gets_no_spot() {
        let mut tris = octahedron(Vec3::ZERO, 0.3, 0);
        tris.extend(octahedron(Vec3::new(2.0, 0.0, 0.0), 0.3, 8));
        let shades: Vec<GpuShading> = (0..16).map(|_| shading(0)).collect();
        let casters = caustic_casters(&tris, &shades, &[material(MATERIAL_DIELECTRIC, 0.0, 0.0)], &[emitter()], false, ROOM_RADIUS);
        assert_eq!(casters.len(), 2);
        assert!(casters.iter().all(|c| c.spot_spread < 0.0 && (c.radius - 0.3).abs() < 1e-6));
    }

    #[test]
    fn no_spot_without_emitters_or_for_a_non_ball() {
        let tris = octahedron(Vec3::ZERO, 0.3, 0);
        let shades: Vec<GpuShading> = (0..8).map(|_| shading(0)).collect();
        let mats = [material(0, 1.0, 1000.0)];
        // A point light only: aimed at as a whole, not by spot.
        let casters = caustic_casters(&tris, &shades, &mats, &[], true, ROOM_RADIUS);
        assert_eq!(casters.len(), 1);
        assert!(casters[0].spot_spread < 0.0);
        // Nothing emits: nothing to aim for.
        assert!(caustic_casters(&tris, &shades, &mats, &[], false, ROOM_RADIUS).is_empty());
        // A flat glossy quad is not a ball.
        let quad = [triangle(0, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]), triangle(1, [[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])];
        let quad_shades = [shading(0), shading(0)];
        let casters = caustic_casters(&quad, &quad_shades, &mats, &[emitter()], false, ROOM_RADIUS);
        assert_eq!(casters.len(), 1);
        assert!(casters[0].spot_spread < 0.0);
    }

    #[test]
    fn a_piece_as_large_as_the_scene_is_no_caster() {
        let mut tris = octahedron(Vec3::ZERO, 0.3, 0);
        tris.extend(octahedron(Vec3::ZERO, 2.0, 8));
        let mut shades: Vec<GpuShading> = (0..8).map(|_| shading(0)).collect();
        shades.extend((0..8).map(|_| shading(1)));
        let mats = [material(0, 1.0, 1000.0), material(MATERIAL_DIELECTRIC, 0.0, 0.0)];
        // The large piece is the scene: its bounding radius is half its box's diagonal.
        let scene_radius = 2.0 * 3f32.sqrt();
        let casters = caustic_casters(&tris, &shades, &mats, &[emitter()], false, scene_radius);
        assert_eq!(casters.len(), 1);
        assert!((casters[0].radius - 0.3).abs() < 1e-6);
    }

    #[test]
    fn too_many_pieces_give_none() {
        let mut tris = Vec::new();
        for i in 0..=MAX_CASTERS {
            tris.extend(octahedron(Vec3::new(i as f32, 0.0, 0.0), 0.2, 8 * i as u32));
        }
        let shades: Vec<GpuShading> = (0..tris.len()).map(|_| shading(0)).collect();
        assert!(caustic_casters(&tris, &shades, &[material(0, 1.0, 1000.0)], &[emitter()], false, ROOM_RADIUS).is_empty());
        assert_eq!(caustic_casters(&tris[8..], &shades, &[material(0, 1.0, 1000.0)], &[emitter()], false, ROOM_RADIUS).len(), MAX_CASTERS);
    }
}
