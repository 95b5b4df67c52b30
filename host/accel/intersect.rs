//! The CPU twin of `shaders/include/intersect.glsl`: the ray-box and ray-triangle tests every
//! layout's walk uses, with the same arithmetic as the shader, so that the GPU can be checked
//! against the CPU hit for hit and traversal changes can be debugged on the CPU.
//!
//! Keep the two in step: every function here names its GLSL counterpart.

use crate::gpu_abi::GpuRay;
use glam::Vec3;

/// Ize 2013, "Robust BVH ray traversal": multiplying the far slab distance by 1 + 2*gamma(3)
/// (gamma(n) = n*eps / (1 - n*eps), eps = 2^-24) makes the float slab test conservative.
pub const SLAB_FAR_PAD: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Per-ray values precomputed once: the slab test's reciprocal direction and the watertight
/// triangle test's shear (`RayPre` in traverse.glsl).
#[derive(Debug, Clone, Copy)]
pub struct RayPre {
    pub origin: Vec3,
    pub inv_dir: Vec3,
    pub tmin: f32,
    /// Axis of the largest |direction| component, and the two others, ordered so that the
    /// sheared coordinates keep the triangle's winding (Woop, Benthin & Wald 2013, sec. 3).
    pub kx: usize,
    pub ky: usize,
    pub kz: usize,
    /// Shear constants Sx, Sy, Sz.
    pub shear: Vec3,
}

/// `safe_reciprocal` in GLSL: 1/d, with d = 0 mapped to the largest float of the same sign
/// rather than infinity. An origin exactly on a slab plane then gives 0 * MAX = 0 instead of
/// 0 * inf = NaN, and the slab counts as entered (boundaries inclusive).
pub fn safe_reciprocal(d: f32) -> f32 {
    if d == 0.0 {
        f32::MAX.copysign(d)
    } else {
        1.0 / d
    }
}

impl RayPre {
    pub fn new(ray: &GpuRay) -> Self {
        let origin = Vec3::from(ray.origin);
        let d = Vec3::from(ray.direction);
        let inv_dir = Vec3::new(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z));
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let shear = Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        // `ray_pre`: a ray with a NaN anywhere gets origin 0, inverse direction 0 and tmin =
        // +inf, so every slab distance is 0 and the first box test fails (t_enter = +inf >
        // t_exit <= 0), whatever tmax is.
        let nan_ray = origin.is_nan() || d.is_nan() || ray.tmin.is_nan() || ray.tmax.is_nan();
        if nan_ray {
            return Self { origin: Vec3::ZERO, inv_dir: Vec3::ZERO, tmin: f32::INFINITY, kx, ky, kz, shear };
        }
        Self { origin, inv_dir, tmin: ray.tmin, kx, ky, kz, shear }
    }
}

/// `intersect_box`: the entry distance if the ray overlaps the box within [tmin, tmax], else
/// None. Conservative per Ize 2013. Boxes are finite, and a NaN ray misses every box
/// (`RayPre::new`).
pub fn intersect_box(r: &RayPre, bmin: Vec3, bmax: Vec3, tmax: f32) -> Option<f32> {
    let t0 = (bmin - r.origin) * r.inv_dir;
    let t1 = (bmax - r.origin) * r.inv_dir;
    let near = Vec3::new(sel_min(t0.x, t1.x), sel_min(t0.y, t1.y), sel_min(t0.z, t1.z));
    let far = Vec3::new(sel_max(t0.x, t1.x), sel_max(t0.y, t1.y), sel_max(t0.z, t1.z));
    let t_enter = sel_max(r.tmin, sel_max(sel_max(near.x, near.y), near.z));
    let t_exit = sel_min(tmax, sel_min(sel_min(far.x, far.y), far.z)) * SLAB_FAR_PAD;
    if t_enter <= t_exit {
        Some(t_enter)
    } else {
        None
    }
}

/// `sel_min` in intersect.glsl: `a < b ? a : b` (b if either is NaN), what x86's minps does;
/// unlike `f32::min` it does not skip a NaN.
pub fn sel_min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `sel_max` in intersect.glsl: `a > b ? a : b`.
pub fn sel_max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// A triangle hit: distance and the barycentric weights of v1 and v2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriHit {
    pub t: f32,
    pub u: f32,
    pub v: f32,
}

/// `intersect_triangle`: the watertight test of Woop, Benthin & Wald 2013 ("Watertight
/// ray/triangle intersection", JCGT 2(1)). No epsilon: the edge functions of a shared edge are
/// exact negations of each other (a*b - c*d evaluated without fused multiply-add, which the
/// shader enforces with `precise`), so a ray can never pass between two triangles; an edge
/// value of exactly 0 counts as inside for both. Accepts hits with tmin < t < tmax.
pub fn intersect_triangle(r: &RayPre, v0: Vec3, v1: Vec3, v2: Vec3, tmax: f32) -> Option<TriHit> {
    let a = v0 - r.origin;
    let b = v1 - r.origin;
    let c = v2 - r.origin;
    let (kx, ky, kz) = (r.kx, r.ky, r.kz);
    let s = r.shear;
    let ax = a[kx] - s.x * a[kz];
    let ay = a[ky] - s.y * a[kz];
    let bx = b[kx] - s.x * b[kz];
    let by = b[ky] - s.y * b[kz];
    let cx = c[kx] - s.x * c[kz];
    let cy = c[ky] - s.y * c[kz];
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 || det.is_nan() {
        return None;
    }
    let az = s.z * a[kz];
    let bz = s.z * b[kz];
    let cz = s.z * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t > r.tmin && t < tmax) {
        return None;
    }
    Some(TriHit { t, u: v * inv_det, v: w * inv_det })
}
