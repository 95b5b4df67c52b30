//! The steps both loaders (`obj`, `lab_yaml`) share: adding triangles (dropping degenerate
//! ones), finishing a scene (camera, textures) and the default light of an unlit scene.

use std::path::Path;

use glam::Vec3;

use super::{Camera, Light, Scene, Triangle};
use crate::error::InputError;
use crate::geom::Aabb;

/// The most triangles a scene may hold as copies in the world: glTF meshes placed once, and
/// every copy of the instanced meshes when a one-level BVH needs them placed
/// (`Scene::expanded`). Each costs about 110-160 bytes on the host before the BVH is built, so
/// 2^28 of them take 30-40 GiB: more than the machines vkrt is for. A file past it is refused
/// with its count before a triangle is copied. (Instanced meshes are kept once: their copies
/// are bounded by `MAX_PRIMITIVES`.)
pub const MAX_PLACED_TRIANGLES: u64 = 1 << 28;

/// Adds triangles to the scene in order, dropping zero-area ones (counted in `stats`) and
/// shading normals that cannot be normalised (zero, NaN, inf) for that triangle.
pub fn push_triangles(scene: &mut Scene, triangles: impl IntoIterator<Item = Triangle>) {
    for t in triangles {
        push_triangle(scene, t);
    }
}

/// Adds one triangle as [`push_triangles`] does; false if it was dropped as degenerate (a
/// loader that keeps a per-triangle array beside `Scene::triangles`, as glTF's tangents, keeps
/// it in step with this).
pub fn push_triangle(scene: &mut Scene, t: Triangle) -> bool {
    let Some(t) = kept(t) else {
        scene.stats.dropped_degenerate += 1;
        return false;
    };
    scene.triangles.push(t);
    true
}

/// The triangle as a scene keeps it, or None if it is degenerate: zero or non-finite area (it
/// can never be hit and would break sampling by area). Shading normals that cannot be
/// normalised (zero, NaN, inf) are dropped for that triangle.
pub fn kept(mut t: Triangle) -> Option<Triangle> {
    let len = t.cross().length();
    // NaN fails both tests: a triangle with a non-finite vertex is unusable too.
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    t.n = t.n.and_then(normalised_normals);
    Some(t)
}

/// Unit shading normals, or None if one cannot be normalised.
pub fn normalised_normals(n: [Vec3; 3]) -> Option<[Vec3; 3]> {
    let n = n.map(|v| v.normalize_or_zero());
    n.iter().all(|v| *v != Vec3::ZERO && v.is_finite()).then_some(n)
}

/// What both loaders do last: refuse an empty scene, choose the camera (the file's first, or a
/// default), and decode the materials' textures.
pub fn finish_scene(scene: &mut Scene, file: &Path, cameras: Vec<Camera>) -> anyhow::Result<()> {
    scene.number_instances().map_err(|e| InputError::new(file, None, e))?;
    if scene.placed_triangles() == 0 {
        let dropped = scene.stats.dropped_degenerate;
        let msg = if dropped > 0 { format!("the scene has no triangles (all {dropped} were degenerate)") } else { "the scene has no triangles".to_string() };
        return Err(InputError::new(file, None, msg).into());
    }
    scene.stats.interior = cameras.is_empty() && looks_like_a_room(scene);
    scene.camera = cameras.first().copied().unwrap_or_else(|| default_camera(scene));
    scene.cameras = cameras;
    // Textures are decoded once per file, here, so that both loaders share the rule.
    super::material_textures::load_material_textures(scene, file, &mut super::texture::TextureCache::default())?;
    // After the textures: MTL's normal maps are only known once loaded.
    super::tangents::fill_missing_tangents(scene);
    Ok(())
}

/// The ambient term that comes with the default light where the file names none: faces
/// turned away from the light are not pitch black.
pub const DEFAULT_AMBIENT: Vec3 = Vec3::splat(0.05);

/// Every loader's rule for a scene whose file lights nothing (no light, no emitting material),
/// which would render black: it gets [`default_light`] and `ambient`, and
/// `LoadStats::default_light` says so, so that an environment map given on the command line
/// replaces both (`prepare::GpuScene::set_environment`, `prepare::Features::without_default_light`).
/// Returns whether it lit the scene.
pub fn light_if_unlit(scene: &mut Scene, ambient: Vec3) -> bool {
    if !scene.lights.is_empty() || scene.emits() {
        return false;
    }
    scene.lights.push(default_light(scene));
    scene.stats.default_light = true;
    scene.ambient = ambient;
    true
}

/// The light a scene without any gets. Inside a room (`LoadStats::interior`), a point light
/// below the ceiling above the bounds' centre (a directional light would not get in); else a
/// directional light from over the camera's shoulder (up and behind the eye), so that what the
/// camera sees is lit from the front.
pub fn default_light(scene: &Scene) -> Light {
    if scene.stats.interior {
        let bounds = scene.bounds();
        let centre = bounds.center();
        // 80 % of the way up to the first surface above the centre.
        let up = closest_face(scene, centre, Vec3::Y).map_or(0.25 * bounds.extent().y, |(t, _)| 0.8 * t);
        // Irradiance about 1 at a third of the room's size: I / d^2 (scene::Light's units).
        let reach = ROOM_LIGHT_REACH * bounds.extent().max_element();
        return Light::Point { position: centre + Vec3::Y * up, intensity: Vec3::splat(reach * reach) };
    }
    let camera = &scene.camera;
    let back = (camera.eye - camera.target).normalize_or_zero();
    let direction = (camera.up.normalize_or_zero() + back).normalize_or_zero();
    let direction = if direction == Vec3::ZERO { Vec3::Y } else { direction };
    Light::Directional { direction, intensity: Vec3::ONE }
}

/// The camera of a scene file that has none. A model seen from its bounds' centre as a room
/// (`looks_like_a_room`: Sponza, Conference) gets a camera there, looking along the longer
/// horizontal axis of the bounds; anything else is framed from outside (`Camera::framing`).
pub fn default_camera(scene: &Scene) -> Camera {
    let bounds = scene.bounds();
    if bounds.is_empty() || !looks_like_a_room(scene) {
        return Camera::framing(&bounds);
    }
    let centre = bounds.center();
    let e = bounds.extent();
    let along = if e.x >= e.z { Vec3::X } else { Vec3::Z };
    Camera { eye: centre, target: centre + along * e.max_element(), up: Vec3::Y, fov_y_deg: ROOM_FOV_DEG, ..Camera::default() }
}

/// Vertical field of view of the default camera inside a room: wide, as architecture is shot.
pub const ROOM_FOV_DEG: f32 = 60.0;
/// The default point light of a room gives irradiance 1 at this fraction of its largest extent.
const ROOM_LIGHT_REACH: f32 = 0.35;

/// Horizontal directions from the bounds' centre that the room test casts.
const ROOM_PROBES: usize = 8;

/// True if, from the centre of the scene's bounds, every horizontal direction (the four axes
/// and the four diagonals) hits a surface, and most of those surfaces face the centre (their
/// front side, by winding or by the file's normals): the centre is in the open space of an
/// enclosure. A closed object has its centre inside the solid, where the faces seen are back
/// faces; an open model lets some rays escape. Brute force over the triangles: 8 rays, run once
/// per bare model.
pub fn looks_like_a_room(scene: &Scene) -> bool {
    let centre = scene.bounds().center();
    let mut facing = 0;
    for k in 0..ROOM_PROBES {
        let a = k as f32 * std::f32::consts::TAU / ROOM_PROBES as f32;
        let dir = Vec3::new(a.cos(), 0.0, a.sin());
        let Some((t, front)) = closest_face(scene, centre, dir) else { return false };
        debug_assert!(t > 0.0);
        facing += front as usize;
    }
    2 * facing > ROOM_PROBES
}

/// The closest triangle along the ray: its distance, and whether the ray meets its front.
/// Copies of instanced meshes are met in object space (the ray's direction not renormalised,
/// so t stays the world's), only those whose placed box the ray meets.
pub fn closest_face(scene: &Scene, origin: Vec3, dir: Vec3) -> Option<(f32, bool)> {
    let mut best = closest_in(&scene.triangles, origin, dir, None);
    for g in &scene.instances {
        let object = g.object_bounds();
        for p in &g.placements {
            let world = p.world();
            let limit = best.map_or(f32::INFINITY, |(t, _)| t);
            if !meets_box(&super::instance::placed_box(&world, &object), origin, dir, limit) {
                continue;
            }
            let to_object = world.inverse();
            let (o, d) = (to_object.transform_point3(origin), to_object.transform_vector3(dir));
            // The side met is the object's: a normal n goes out as the inverse transpose times
            // n, whose dot with the world direction is n's with the object direction (a
            // mirror's swapped winding included, `Placement::place`).
            if let Some(hit) = closest_in(&g.mesh, o, d, best.map(|(t, _)| t)) {
                best = Some(hit);
            }
        }
    }
    best
}

/// Whether the ray from `origin` along `dir` meets the box before `limit` (slabs).
fn meets_box(b: &Aabb, origin: Vec3, dir: Vec3, limit: f32) -> bool {
    let inv = dir.recip();
    let (t0, t1) = ((b.min - origin) * inv, (b.max - origin) * inv);
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(limit);
    near <= far
}

/// The closest of `triangles` along the ray nearer than `limit`, as [`closest_face`].
fn closest_in(triangles: &[Triangle], origin: Vec3, dir: Vec3, limit: Option<f32>) -> Option<(f32, bool)> {
    let mut best: Option<(f32, bool)> = None;
    for tri in triangles {
        // Möller & Trumbore 1997: a heuristic needs no watertightness.
        let (e1, e2) = (tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]);
        let pv = dir.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = origin - tri.p[0];
        let u = s.dot(pv) / det;
        let q = s.cross(e1);
        let v = dir.dot(q) / det;
        let t = e2.dot(q) / det;
        // Written as what a hit is, so that a NaN (coordinates near f32::MAX overflow the
        // products) is no hit.
        let hit = u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0;
        let nearest = best.map(|(b, _)| b).or(limit);
        if !hit || nearest.is_some_and(|b| t >= b) {
            continue;
        }
        let normal = match tri.n {
            Some(n) => n[0] * (1.0 - u - v) + n[1] * u + n[2] * v,
            None => e1.cross(e2),
        };
        best = Some((t, normal.dot(dir) < 0.0));
    }
    best
}
