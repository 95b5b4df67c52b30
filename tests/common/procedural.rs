//! Small generated scenes for tests and benchmarks, deterministic from a seed. Test support,
//! not part of the library: the tests include it as `common::procedural`, the benchmark tools
//! by path.
#![allow(dead_code)]

use glam::Vec3;
use vkrt::rng::Pcg32;
use vkrt::scene::{Camera, Light, Material, Scene, Triangle};

/// `n` random triangles with centres in the unit cube and edges up to 0.2 long, one white
/// material, a framing camera and one directional light. None is degenerate.
pub fn random_soup(n: usize, seed: u64) -> Scene {
    let mut rng = Pcg32::new(seed);
    let mut triangles = Vec::with_capacity(n);
    while triangles.len() < n {
        let c = rng.vec3();
        let p = [0, 1, 2].map(|_| c + (rng.vec3() - 0.5) * 0.2);
        let t = Triangle { p, n: None, uv: None, material: 0 };
        // Zero area is astronomically rare, but the promise is "none is degenerate".
        if t.cross().length() > 1e-12 {
            triangles.push(t);
        }
    }
    scene_of(triangles)
}

/// The two triangles of the parallelogram `corner`, `corner + u`, `corner + u + v`,
/// `corner + v`; front face (counter-clockwise) on the side of `u x v`.
pub fn quad(corner: Vec3, u: Vec3, v: Vec3, material: u32) -> [Triangle; 2] {
    let [a, b, c, d] = [corner, corner + u, corner + u + v, corner + v];
    let tri = |p| Triangle { p, n: None, uv: None, material };
    [tri([a, b, c]), tri([a, c, d])]
}

/// A scene of `triangles` with one default material, a framing camera and a light from the
/// camera's side.
pub fn scene_of(triangles: Vec<Triangle>) -> Scene {
    let mut scene = Scene { triangles, materials: vec![Material::default()], ..Scene::default() };
    scene.camera = Camera::framing(&scene.bounds());
    scene.lights.push(Light::Directional { direction: Vec3::new(0.0, 1.0, 1.0).normalize(), intensity: Vec3::ONE });
    scene.ambient = Vec3::splat(0.05);
    scene
}

/// A sphere tessellated from an octahedron whose faces are split `level` times (8 * 4^level
/// triangles), vertices on the sphere. Front faces (counter-clockwise) point outward, or
/// inward with `inward` (a furnace seen from inside). Faceted: its shading normals are the
/// geometric ones.
pub fn sphere(center: Vec3, radius: f32, level: u32, material: u32, inward: bool) -> Vec<Triangle> {
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    // Counter-clockwise seen from outside.
    let mut faces: Vec<[Vec3; 3]> = vec![[x, y, z], [y, -x, z], [-x, -y, z], [-y, x, z], [y, x, -z], [-x, y, -z], [-y, -x, -z], [x, -y, -z]];
    for _ in 0..level {
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = ((a + b).normalize(), (b + c).normalize(), (c + a).normalize());
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    faces
        .into_iter()
        .map(|[a, b, c]| {
            let p = [a, b, c].map(|v| center + radius * v);
            let p = if inward { [p[0], p[2], p[1]] } else { p };
            Triangle { p, n: None, uv: None, material }
        })
        .collect()
}
