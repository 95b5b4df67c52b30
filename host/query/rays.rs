//! The ray sets the comparisons use: camera (primary) rays, incoherent rays, and the shadow and
//! diffuse-bounce rays that start where primary rays hit. Deterministic for a given seed.

use crate::gpu_abi::constants::PRIM_NONE;
use crate::gpu_abi::{GpuHit, GpuRay};
use crate::rng::Pcg32;
use crate::scene::{Light, Scene};
use anyhow::{Context as _, Result};
use glam::Vec3;

fn ray(origin: Vec3, direction: Vec3, tmax: f32) -> GpuRay {
    GpuRay { origin: origin.to_array(), tmin: 0.0, direction: direction.to_array(), tmax }
}

/// One ray through each pixel centre of a `width` x `height` image from the scene's camera,
/// row by row from the top.
pub fn primary(scene: &Scene, width: u32, height: u32) -> Result<Vec<GpuRay>> {
    let cam = scene.camera.frame().context("camera for primary rays")?;
    Ok((0..height)
        .flat_map(|j| (0..width).map(move |i| (i, j)))
        .map(|(i, j)| ray(cam.origin, cam.ray_direction(i as f32 + 0.5, j as f32 + 0.5, width, height), f32::INFINITY))
        .collect())
}

/// Incoherent rays: origins uniform in the scene bounds, directions uniform on the sphere (the
/// distribution of the tinybvh and Embree comparisons in docs/experiments/).
pub fn incoherent(scene: &Scene, count: usize, seed: u64) -> Vec<GpuRay> {
    let b = scene.bounds();
    let mut rng = Pcg32::new(seed);
    (0..count)
        .map(|_| {
            let t = Vec3::new(rng.f32(), rng.f32(), rng.f32());
            ray(b.min + t * b.extent(), rng.unit_vector(), f32::INFINITY)
        })
        .collect()
}

/// Shadow rays (any-hit, toward the first light) and diffuse-bounce rays (closest hit,
/// cosine-weighted about the normal) from every primary hit. Origins are moved off the surface
/// by 1e-4 of the scene size. The light: a point or spot light's position, a directional
/// light's direction, or with no lights a point above the centre of the bounds.
pub fn secondary(scene: &Scene, primary: &[GpuRay], hits: &[GpuHit], seed: u64) -> (Vec<GpuRay>, Vec<GpuRay>) {
    let b = scene.bounds();
    let eps = 1e-4 * b.extent().max_element().max(f32::MIN_POSITIVE);
    let light = scene.lights.first().copied();
    let fallback = b.center() + Vec3::new(0.0, 0.4 * b.extent().y, 0.0);
    let mut rng = Pcg32::new(seed);
    let mut shadow = Vec::new();
    let mut diffuse = Vec::new();
    for (r, h) in primary.iter().zip(hits) {
        let Some(tri) = (h.prim != PRIM_NONE).then(|| scene.triangle(h.prim)).flatten() else { continue };
        let d = Vec3::from(r.direction);
        let mut n = tri.cross().normalize_or_zero();
        if n.dot(d) > 0.0 {
            n = -n;
        }
        let p = Vec3::from(r.origin) + h.t * d + eps * n;
        match light {
            Some(Light::Directional { direction, .. }) => shadow.push(ray(p, direction.normalize_or_zero(), f32::INFINITY)),
            Some(Light::Point { position, .. }) | Some(Light::Spot { position, .. }) | Some(Light::Cone { position, .. }) => {
                shadow.push(ray(p, position - p, 1.0));
            }
            None => shadow.push(ray(p, fallback - p, 1.0)),
        }
        // Cosine-weighted hemisphere (Malley's method) in a frame around n.
        let (u1, u2) = (rng.f32(), rng.f32());
        let (rad, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
        let (t1, t2) = n.any_orthonormal_pair();
        let dir = rad * phi.cos() * t1 + rad * phi.sin() * t2 + (1.0 - u1).max(0.0).sqrt() * n;
        diffuse.push(ray(p, dir.normalize_or_zero(), f32::INFINITY));
    }
    (shadow, diffuse)
}
