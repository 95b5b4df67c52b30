//! The environment map as a light: its texels for the GPU and the distribution the path
//! tracer samples directions from (`shaders/include/environment.glsl`, whose CPU twin is
//! [`EnvLight::sample`] and [`EnvLight::pdf`]).
//!
//! The radiance is bilinear between texels (`scene::envmap`: texel centres at u = (i + 0.5) / W,
//! rows on v = j / (H - 1)), so the map is W x (H - 1) bilinear cells, cell (i, j) spanning
//! texel columns i, i + 1 (wrapping) and rows j, j + 1. A cell is picked with probability
//! proportional to the mean luminance of its four corners (proportional to its bilinear
//! patch's integral in (u, v)) times sin(theta) at its centre: a piecewise-constant 2D
//! distribution, marginal over rows and conditional within a row (Pharr, Jakob & Humphreys,
//! PBRT 4th ed., sections A.5.2 and 12.5.2, `ImageInfiniteLight`). A point in the cell is
//! then drawn in proportion to the bilinear interpolation of its corners' luminances (PBRT 4th
//! ed., section A.4.4, `SampleBilinear`), as the radiance itself is interpolated: a sun one or
//! two texels wide lights a cell from one corner, and drawn uniformly over the cell its
//! samples' radiance over density ranged from 0 to 4 times the mean (the bilinear draw cut
//! relMSE by 38-40 % on the realistic ladder's dragon and Buddha and 10 % in Sponza at equal
//! time: docs/experiments/env-bilinear-sampling.md). The luminance that weighs both is the
//! texel's less the map's mean (MIS compensation, [`compensated_luminance`]): directions no
//! brighter than the mean are left to BSDF sampling, whose MIS weight there is 1. In solid
//! angle the density is p(u, v) / (2 pi^2 sin theta).

use crate::gpu_abi::constants::*;
use crate::gpu_abi::luminance;
use crate::scene::envmap::{direction_to_uv, grid_position, rotate_y, uv_to_direction, EnvMap};
use glam::{Vec2, Vec3};
use std::f64::consts::PI;

/// An environment map ready for the GPU.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvLight {
    pub width: u32,
    pub height: u32,
    /// Radiance texels (scaled), RGBA32F bits, alpha 0.
    pub texels: Vec<[u32; 4]>,
    /// The marginal CDF over rows of cells (height entries, 0 to 1), then each row's CDF over
    /// its cells (width + 1 entries each), floats as bits (BINDING_ENV_CDF).
    pub cdf: Vec<u32>,
    pub scale: f32,
    pub rotation_deg: f32,
    /// The mean radiance over the sphere of directions (scaled): what a Lambert surface under
    /// it would reflect times its albedo, unshadowed (the Whitted integrator's approximation).
    pub mean_radiance: Vec3,
    /// The integral of mean(RGB radiance) over the sphere (scaled), for the light picker.
    pub mean_integral: f64,
    /// The luminance taken off every texel's before it weighs the sampling (MIS compensation,
    /// [`compensated_luminance`]); 0 for a map without a texel above its mean.
    pub compensation: f32,
    marginal: Vec<f32>,
    conditional: Vec<f32>,
}

/// x in [0, 1) with density proportional to (1 - x) a + x b, a, b >= 0 (PBRT 4th ed.
/// `SampleLinear`, inverting the CDF in a form without cancellation); `u` itself where both
/// are 0. The CPU twin of the shader's `env_sample_linear`.
pub fn sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if !(a + b > 0.0) {
        return u;
    }
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    // The density does not change with the scale; a bright sun's squared luminance would
    // overflow without it.
    let m = a.max(b);
    let (a, b) = (a / m, b / m);
    // GLSL's mix(a^2, b^2, u), as the shader writes it.
    let x = u * (a + b) / (a + (a * a * (1.0 - u) + b * b * u).sqrt());
    // The largest f32 below 1: the shader's ONE_MINUS_EPSILON (sampling.glsl).
    x.min(1.0 - f32::EPSILON / 2.0)
}

/// The density over the unit square of the bilinear function with corner weights `w` (at
/// (0, 0), (1, 0), (0, 1), (1, 1)) at `f`; 0 where all are 0. The CPU twin of
/// `env_bilinear_pdf`.
pub fn bilinear_pdf(f: Vec2, w: [f32; 4]) -> f32 {
    // Scaled to at most 1 first, as in `sample_linear`: the sum must not overflow.
    let m = w[0].max(w[1]).max(w[2]).max(w[3]);
    if !(m > 0.0) {
        return 0.0;
    }
    let w = w.map(|x| x / m);
    let sum = w[0] + w[1] + w[2] + w[3];
    4.0 * mix(mix(w[0], w[1], f.x), mix(w[2], w[3], f.x), f.y) / sum
}

/// The texels' luminances as they weigh the map's sampling, and what was taken off them.
struct Compensated {
    texels: Vec<f64>,
    compensation: f32,
}

/// The luminance of each (scaled) texel less the map's mean luminance over the sphere, floored
/// at 0: MIS compensation (Karlik, Sik, Vevoda, Skrivan & Krivanek 2019, "MIS compensation:
/// optimizing sampling techniques in multiple importance sampling"; pbrt-v4's
/// ImageInfiniteLight samples such a distribution wherever MIS with BSDF sampling backs it).
/// Light sampling and BSDF sampling are combined by MIS at every vertex, and BSDF sampling
/// already finds the broad sky well, so light sampling's share of it only adds variance; taken
/// off, the map's light samples go to the sun and whatever else stands out. A direction the
/// compensated map never draws has light-sampling density 0, so BSDF sampling gets weight 1
/// there and the estimate stays unbiased. Measured: relMSE -70 % and -69 % on the realistic
/// ladder's dragon and Buddha and -13 % in Sponza at 64 spp, HDR-FLIP -34 / -31 / -4.4 %
/// (docs/experiments/env-mis-compensation.md). `mean_radiance` is the (scaled) map's mean over
/// solid angle; the luminances are the shader's f32 ones. A map with no texel above the mean
/// (a constant one) is left as it is.
fn compensated_luminance(map: &EnvMap, scale: f32, mean_radiance: Vec3) -> Compensated {
    let lum: Vec<f32> = map.texels.iter().map(|t| luminance((Vec3::from(*t) * scale).to_array())).collect();
    let mean = luminance(mean_radiance.to_array());
    let compensation = if lum.iter().any(|l| *l > mean) { mean } else { 0.0 };
    Compensated { texels: lum.iter().map(|l| compensate(*l, compensation) as f64).collect(), compensation }
}

/// A luminance less the compensation, floored at 0, in the shader's f32 arithmetic
/// (`env_cell_luminance`): the one rule for the cells' weights and the draw inside a cell.
fn compensate(luminance: f32, compensation: f32) -> f32 {
    (luminance - compensation).max(0.0)
}

/// GLSL's `mix`: x (1 - t) + y t.
fn mix(x: f32, y: f32, t: f32) -> f32 {
    x * (1.0 - t) + y * t
}

/// A CDF (n + 1 entries from 0 to 1) of `weights`; uniform if they are all 0.
fn cdf_of(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let mut out = Vec::with_capacity(weights.len() + 1);
    let mut acc = 0.0;
    out.push(0.0);
    for (k, w) in weights.iter().enumerate() {
        acc += w;
        out.push(if total > 0.0 { (acc / total) as f32 } else { (k + 1) as f32 / weights.len() as f32 });
    }
    // The sum rounds: close the CDF exactly, so that u < 1 always finds an interval.
    if let Some(last) = out.last_mut() {
        *last = 1.0;
    }
    out
}

/// The index k with cdf[k] <= u < cdf[k + 1] (skipping empty entries), as the shader finds it.
fn find_interval(cdf: &[f32], u: f32) -> usize {
    // The largest k < n with cdf[k] <= u.
    let n = cdf.len() - 1;
    let (mut lo, mut hi) = (0usize, n);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if cdf[mid] <= u {
            lo = mid
        } else {
            hi = mid
        }
    }
    lo
}

impl EnvLight {
    pub fn new(map: &EnvMap, scale: f32, rotation_deg: f32) -> Self {
        let (w, h) = (map.width as usize, map.height as usize);
        let rows = h - 1;
        let texels = map.texels.iter().map(|t| [(t[0] * scale).to_bits(), (t[1] * scale).to_bits(), (t[2] * scale).to_bits(), 0]).collect();
        // The mean radiance over the sphere: each cell's bilinear patch integrates to the mean of
        // its corners over (u, v); the solid angle of a row of cells is
        // 2 pi (cos theta_j - cos theta_j+1).
        let mut mean_rgb = glam::DVec3::ZERO;
        for j in 0..rows {
            let solid_angle = 2.0 * PI * ((PI * j as f64 / rows as f64).cos() - (PI * (j + 1) as f64 / rows as f64).cos());
            let mut row_rgb = glam::DVec3::ZERO;
            for i in 0..w {
                let i1 = (i + 1) % w;
                let c = map.texel(i as u32, j as u32) + map.texel(i1 as u32, j as u32) + map.texel(i as u32, j as u32 + 1) + map.texel(i1 as u32, j as u32 + 1);
                row_rgb += 0.25 * c.as_dvec3();
            }
            mean_rgb += row_rgb / w as f64 * solid_angle;
        }
        let mean_radiance = (mean_rgb / (4.0 * PI) * scale as f64).as_vec3();
        let lum = compensated_luminance(map, scale, mean_radiance);
        let l = &lum.texels;
        let mut row_weights = Vec::with_capacity(rows);
        let mut conditional = Vec::with_capacity(rows * (w + 1));
        for j in 0..rows {
            let sin_theta = (PI * (j as f64 + 0.5) / rows as f64).sin();
            let cells: Vec<f64> = (0..w)
                .map(|i| {
                    let i1 = (i + 1) % w;
                    0.25 * (l[j * w + i] + l[j * w + i1] + l[(j + 1) * w + i] + l[(j + 1) * w + i1]) * sin_theta
                })
                .collect();
            row_weights.push(cells.iter().sum::<f64>());
            conditional.extend(cdf_of(&cells));
        }
        let mean_integral = (mean_rgb.x + mean_rgb.y + mean_rgb.z) / 3.0 * scale as f64;
        let marginal = cdf_of(&row_weights);
        let cdf = marginal.iter().chain(&conditional).map(|x| x.to_bits()).collect();
        Self {
            width: map.width,
            height: map.height,
            texels,
            cdf,
            scale,
            rotation_deg,
            mean_radiance,
            mean_integral,
            marginal,
            conditional,
            compensation: lum.compensation,
        }
    }

    /// The selection weight of the map in the light picker: its power into the scene's bounding
    /// sphere of radius r, pi r^2 times the integral of mean(radiance) over directions (the
    /// same measure as a directional light's, `light_table`).
    pub fn weight(&self, scene_radius: f32) -> f64 {
        PI * (scene_radius as f64).powi(2) * self.mean_integral
    }

    /// The scaled texels at cell (i, j)'s corners (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1),
    /// as the shader reads them (`env_cell`).
    fn cell(&self, i: usize, j: usize) -> [Vec3; 4] {
        let w = self.width as usize;
        let i1 = (i + 1) % w;
        let texel = |i: usize, j: usize| {
            let t = self.texels[j * w + i];
            Vec3::new(f32::from_bits(t[0]), f32::from_bits(t[1]), f32::from_bits(t[2]))
        };
        [texel(i, j), texel(i1, j), texel(i, j + 1), texel(i1, j + 1)]
    }

    /// The compensated luminances of a cell's corners, which weigh the draw in the cell and its
    /// density (`env_cell_luminance`).
    fn corner_luminance(&self, cell: &[Vec3; 4]) -> [f32; 4] {
        cell.map(|t| compensate(luminance(t.to_array()), self.compensation))
    }

    fn row_cdf(&self, j: usize) -> &[f32] {
        let n = self.width as usize + 1;
        &self.conditional[j * n..(j + 1) * n]
    }

    /// The solid-angle density at point `f` of cell (i, j) (corner luminances `w`) where the
    /// direction has `sin_theta`: the cell's probability times the bilinear density in it
    /// (`env_density`).
    fn density(&self, i: usize, j: usize, f: Vec2, w: [f32; 4], sin_theta: f32) -> f32 {
        if sin_theta <= 0.0 {
            return 0.0;
        }
        let row = self.row_cdf(j);
        let p = (self.marginal[j + 1] - self.marginal[j]) * (row[i + 1] - row[i]) * bilinear_pdf(f, w);
        let rows = self.height as usize - 1;
        p * (self.width as usize * rows) as f32 / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin_theta)
    }

    /// A world direction for `u`, the radiance along it and its solid-angle density: the CPU
    /// twin of `env_sample`. The radiance and the density are those of the drawn point of the
    /// cell, from the corners the draw read, as the shader computes them.
    pub fn sample(&self, u: Vec2) -> EnvSample {
        let rows = self.height as usize - 1;
        let j = find_interval(&self.marginal, u.y).min(rows - 1);
        let (m0, m1) = (self.marginal[j], self.marginal[j + 1]);
        let fy = ((u.y - m0) / (m1 - m0)).clamp(0.0, 1.0);
        let row = self.row_cdf(j);
        let i = find_interval(row, u.x).min(self.width as usize - 1);
        let (c0, c1) = (row[i], row[i + 1]);
        let fx = ((u.x - c0) / (c1 - c0)).clamp(0.0, 1.0);
        // Within the cell: y from the bilinear's marginal, then x given y.
        let cell = self.cell(i, j);
        let w = self.corner_luminance(&cell);
        let fy = sample_linear(fy, w[0] + w[1], w[2] + w[3]);
        let fx = sample_linear(fx, mix(w[0], w[2], fy), mix(w[1], w[3], fy));
        let x = i as f32 + fx;
        let y = j as f32 + fy;
        let uv = Vec2::new(((x + 0.5) / self.width as f32).fract(), y / rows as f32);
        let dir = rotate_y(uv_to_direction(uv), self.rotation_deg);
        let sin_theta = (std::f32::consts::PI * y / rows as f32).sin();
        let radiance = cell[0].lerp(cell[1], fx).lerp(cell[2].lerp(cell[3], fx), fy);
        EnvSample { dir, radiance, pdf: self.density(i, j, Vec2::new(fx, fy), w, sin_theta) }
    }

    /// The solid-angle density with which [`Self::sample`] draws world direction `d`: the CPU
    /// twin of the density `env_lookup` gives an escaping ray.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let local = rotate_y(d, -self.rotation_deg);
        let uv = direction_to_uv(local);
        let (x, y) = grid_position(uv, self.width, self.height);
        let rows = self.height as usize - 1;
        let (i, j) = ((x as usize).min(self.width as usize - 1), (y as usize).min(rows - 1));
        let f = (Vec2::new(x, y) - Vec2::new(i as f32, j as f32)).clamp(Vec2::ZERO, Vec2::ONE);
        let sin_theta = (1.0 - local.y * local.y).max(0.0).sqrt();
        self.density(i, j, f, self.corner_luminance(&self.cell(i, j)), sin_theta)
    }

    /// What `GpuFrame` says of the map.
    pub fn frame_fields(&self) -> EnvFrame {
        let (s, c) = self.rotation_deg.to_radians().sin_cos();
        EnvFrame { width: self.width, height: self.height, rotation_cos: c, rotation_sin: s, compensation: self.compensation }
    }
}

/// A direction drawn from the map ([`EnvLight::sample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnvSample {
    /// World direction, unit.
    pub dir: Vec3,
    /// The (scaled) radiance arriving along it.
    pub radiance: Vec3,
    /// Its solid-angle density.
    pub pdf: f32,
}

/// The map's fields of the frame uniform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnvFrame {
    pub width: u32,
    pub height: u32,
    pub rotation_cos: f32,
    pub rotation_sin: f32,
    /// [`EnvLight::compensation`].
    pub compensation: f32,
}

impl EnvFrame {
    /// No environment map.
    pub const NONE: EnvFrame = EnvFrame { width: 0, height: 0, rotation_cos: 1.0, rotation_sin: 0.0, compensation: 0.0 };
}

const _: () = assert!(BINDING_ENV_CDF == BINDING_ENV_TEXELS + 1);

#[cfg(test)]
mod tests {
    use super::*;

    /// A map with a smooth sky and a small bright sun.
    fn sunny(w: u32, h: u32) -> EnvMap {
        let mut texels = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let sun = if (x as i32 - 5).abs() <= 1 && (y as i32 - 3).abs() <= 1 { 500.0 } else { 0.0 };
                let sky = 0.2 + 0.8 * (y as f32 / (h - 1) as f32);
                texels.push([sky + sun, sky + 0.5 * sun, sky]);
            }
        }
        EnvMap::from_texels("sunny.exr", w, h, texels).unwrap()
    }

    #[test]
    fn density_integrates_to_one_and_matches_the_samples() {
        let map = sunny(32, 17);
        let light = EnvLight::new(&map, 1.0, 30.0);
        // Integral of the pdf over the sphere by a fine (theta, phi) grid.
        let n = 400;
        let mut total = 0.0f64;
        for a in 0..n {
            let theta = PI * (a as f64 + 0.5) / n as f64;
            for b in 0..2 * n {
                let phi = PI * (b as f64 + 0.5) / n as f64;
                let d = Vec3::new((theta.sin() * phi.cos()) as f32, theta.cos() as f32, (theta.sin() * phi.sin()) as f32);
                total += light.pdf(d) as f64 * theta.sin() * (PI / n as f64).powi(2);
            }
        }
        assert!((total - 1.0).abs() < 0.01, "pdf integrates to {total}");
        // Sampled directions: their pdf is the pdf the sampler reports, and the sun's cells get
        // about the share the distribution gives them.
        let mut in_sun = 0;
        let count = 20000;
        for k in 0..count {
            // The R2 sequence (Roberts 2018): well spread points in the unit square.
            let u = Vec2::new((0.5 + k as f64 * 0.754_877_666).fract() as f32, (0.5 + k as f64 * 0.569_840_291).fract() as f32);
            let EnvSample { dir: d, radiance, pdf } = light.sample(u);
            assert!((d.length() - 1.0).abs() < 1e-4 && pdf > 0.0, "{d} {pdf}");
            let local = rotate_y(d, -30.0);
            // The radiance and density of the drawn point are those a lookup along the drawn
            // direction finds (which goes back to the grid through atan and acos, so not to
            // the bit): the same corners, in the same order, at the same point.
            let looked_up = map.radiance(local);
            assert!((radiance - looked_up).abs().max_element() <= 1e-4 * (1.0 + looked_up.max_element()), "{d}: drawn {radiance}, looked up {looked_up}");
            // The lookup's sin(theta) = sqrt(1 - y^2) loses f32 digits near the poles: a
            // relative error of about 1e-7 / sin^2(theta).
            let tolerance = 1e-3 + 1e-7 / (1.0 - d.y * d.y);
            assert!((pdf - light.pdf(d)).abs() <= tolerance * pdf, "{d}: drawn density {pdf}, looked up {}", light.pdf(d));
            let (x, y) = grid_position(direction_to_uv(local), 32, 17);
            if (3.0..7.0).contains(&x) && (1.0..5.0).contains(&y) {
                in_sun += 1;
            }
        }
        assert!(in_sun as f32 / count as f32 > 0.8, "only {in_sun} of {count} samples near the sun");
    }

    #[test]
    fn sample_linear_inverts_the_linear_cdf() {
        for (a, b) in [(1.0f32, 1.0f32), (0.0, 3.0), (5.0, 0.0), (0.2, 7.0), (1e4, 1e-3)] {
            for k in 0..100 {
                let u = (k as f32 + 0.5) / 100.0;
                let x = sample_linear(u, a, b);
                // CDF of (1 - x) a + x b over [0, 1].
                let cdf = (a * x + 0.5 * (b - a) * x * x) / (0.5 * (a + b));
                assert!((0.0..1.0).contains(&x) && (cdf - u).abs() < 1e-4, "a {a} b {b} u {u}: x {x}, cdf {cdf}");
            }
        }
        assert_eq!(sample_linear(0.3, 0.0, 0.0), 0.3);
        // Weights whose squares overflow f32: the same draw as their scaled-down twins.
        for u in [0.1f32, 0.5, 0.9] {
            let (x, small) = (sample_linear(u, 1e30, 3e30), sample_linear(u, 1.0, 3.0));
            assert!(x.is_finite() && (x - small).abs() < 1e-6, "u {u}: {x} vs {small}");
        }
        assert_eq!(bilinear_pdf(Vec2::new(0.5, 0.5), [0.0; 4]), 0.0);
        assert!((bilinear_pdf(Vec2::new(0.0, 0.0), [1.0, 0.0, 0.0, 0.0]) - 4.0).abs() < 1e-6);
        assert!((bilinear_pdf(Vec2::new(0.25, 0.5), [3e38, 3e38, 3e38, 0.0]) - bilinear_pdf(Vec2::new(0.25, 0.5), [3.0, 3.0, 3.0, 0.0])).abs() < 1e-6);
    }

    /// A sun one texel wide, on the equator, lights its four cells from one corner each. Drawn
    /// in proportion to the bilinear radiance, every sample there carries the same radiance
    /// over density but for the factor sin(theta) / sin(theta at the cell's centre) (the cells'
    /// centres share one sin(theta) here); drawn uniformly over the cell, that ratio would run
    /// from 0 (far corner) to 4 times its mean.
    #[test]
    fn a_one_texel_sun_is_sampled_as_its_radiance_falls_off() {
        let (w, h) = (16u32, 9u32);
        let texels = (0..w * h).map(|k| if k == 4 * w + 7 { [1000.0; 3] } else { [0.0; 3] }).collect();
        let map = EnvMap::from_texels("sun.exr", w, h, texels).unwrap();
        let light = EnvLight::new(&map, 1.0, 0.0);
        let (mut lo, mut hi) = (f32::MAX, 0.0f32);
        for k in 0..4000 {
            let u = Vec2::new((0.5 + k as f64 * 0.754_877_666).fract() as f32, (0.5 + k as f64 * 0.569_840_291).fract() as f32);
            let EnvSample { dir: d, radiance, pdf } = light.sample(u);
            let l = radiance.x;
            assert!(pdf > 0.0 && l > 0.0, "a sample off the sun: {d} radiance {l} pdf {pdf}");
            let sin_theta = (1.0 - d.y * d.y).sqrt();
            let ratio = l / pdf / sin_theta;
            lo = lo.min(ratio);
            hi = hi.max(ratio);
        }
        assert!(hi / lo < 1.001, "radiance x sin(theta) over density ranges {lo} to {hi}");
    }

    /// MIS compensation: the sky below the map's mean is left to BSDF sampling (density 0
    /// there), the sun keeps its samples, and a constant map, with nothing above its mean, is
    /// sampled as before (uniformly over the sphere).
    #[test]
    fn the_compensated_map_leaves_the_dim_sky_to_bsdf_sampling() {
        let map = sunny(32, 17);
        let light = EnvLight::new(&map, 2.0, 0.0);
        assert!(light.compensation > 0.0);
        let sky = uv_to_direction(Vec2::new((20.0 + 0.5) / 32.0, 12.0 / 16.0));
        assert!(2.0 * luminance(map.radiance(sky).to_array()) < light.compensation, "the test needs a sky darker than the mean");
        assert_eq!(light.pdf(sky), 0.0, "a sky darker than the mean is not light-sampled");
        let sun = uv_to_direction(Vec2::new((5.0 + 0.5) / 32.0, 3.0 / 16.0));
        assert!(light.pdf(sun) > 0.0);
        let constant = EnvLight::new(&EnvMap::from_texels("c.exr", 64, 33, vec![[0.5, 1.0, 2.0]; 64 * 33]).unwrap(), 1.0, 0.0);
        assert_eq!(constant.compensation, 0.0);
        // Near the equator, where a row's sin(theta) at its centre is the direction's.
        let d = Vec3::new(0.9, 0.01, -0.3).normalize();
        assert!((constant.pdf(d) * 4.0 * std::f32::consts::PI - 1.0).abs() < 2e-2, "uniform density {}", constant.pdf(d));
    }

    #[test]
    fn mean_radiance_of_a_constant_map_is_the_constant() {
        let map = EnvMap::from_texels("c.exr", 8, 5, vec![[0.5, 1.0, 2.0]; 40]).unwrap();
        let light = EnvLight::new(&map, 2.0, 0.0);
        assert!((light.mean_radiance - Vec3::new(1.0, 2.0, 4.0)).abs().max_element() < 1e-4, "{}", light.mean_radiance);
        let want = 4.0 * PI * (7.0 / 3.0);
        assert!((light.mean_integral - want).abs() < 1e-3 * want, "{} vs {want}", light.mean_integral);
    }
}
