//! Which light the path tracer samples next: every emitter (emissive triangle, point, spot or
//! directional light) gets a selection weight equal to the power it emits, and an alias table
//! (Vose 1991) picks one in constant time on the GPU.
//!
//! Power (the units are those of `scene::Light`, path tracer column), with mean() the average
//! of the RGB channels:
//! - emissive triangle: pi * area * mean(Ke) (a Lambertian emitter of radiance Ke, front face);
//! - point light: 4 pi * mean(I) (radiant intensity I in every direction);
//! - spot light: intensity 4 pi r^2 I max(0, cos) integrated over the sphere = 4 pi^2 r^2 mean(I);
//! - cone light: the falloff f of `scene::Light::Cone` integrated over the sphere,
//!   2 pi mean(I) integral_{cos_outer}^{1} f(c) dc = 2 pi mean(I) ((1 - cos_inner) + (cos_inner -
//!   cos_outer) / 3) (f is 1 above cos_inner and a squared linear ramp, integrating to a third of
//!   its width, below);
//! - directional light: mean(E) * pi R^2, its irradiance E over the disk of the scene's
//!   bounding sphere (radius R), the most it can deliver to the scene.
//!
//! The shader recomputes a triangle's area density pi * mean(Ke) / total from its material
//! when a BSDF-sampled ray hits it (for MIS), so it needs no map from primitive to entry.

use super::scene_buffers::SceneBuffers;
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuLight, GpuLightPick};
use std::f32::consts::PI;

/// The selection table and the normaliser the shader needs.
#[derive(Debug, Clone, PartialEq)]
pub struct LightTable {
    pub picks: Vec<GpuLightPick>,
    /// Sum of all weights (0 when nothing emits).
    pub total_weight: f64,
}

fn mean(v: [f32; 3]) -> f32 {
    (v[0] + v[1] + v[2]) / 3.0
}

/// The selection weight of one point, spot or directional light.
pub fn light_weight(light: &GpuLight, scene_radius: f32) -> f32 {
    let i = mean(light.intensity).max(0.0);
    match light.kind {
        LIGHT_POINT => 4.0 * PI * i,
        LIGHT_SPOT => 4.0 * PI * PI * light.radius * light.radius * i,
        LIGHT_CONE => {
            let (cos_inner, cos_outer) = (light.radius, light.cos_outer);
            2.0 * PI * i * ((1.0 - cos_inner).max(0.0) + (cos_inner - cos_outer).max(0.0) / 3.0)
        }
        _ => i * PI * scene_radius * scene_radius,
    }
}

impl LightTable {
    /// The table over `buffers.emitters` followed by `buffers.lights`, in that order.
    pub fn new(buffers: &SceneBuffers, scene_radius: f32) -> Self {
        let weights: Vec<f64> = buffers
            .emitters
            .iter()
            .map(|e| (PI * e.area * mean(e.radiance).max(0.0)) as f64)
            .chain(buffers.lights.iter().map(|l| light_weight(l, scene_radius) as f64))
            .map(|w| if w.is_finite() { w } else { 0.0 })
            .collect();
        let total_weight: f64 = weights.iter().sum();
        Self { picks: alias_table(&weights, total_weight), total_weight }
    }
}

impl LightTable {
    /// The table of `picks` (summing to `total_weight`) with one entry appended, of weight
    /// `extra` (an environment map, added after the scene was prepared), and the entries in
    /// `dropped` given weight 0 (a default light the map replaces). The old entries' weights
    /// are their pmf times the old total.
    pub fn with_extra(picks: &[GpuLightPick], total_weight: f64, extra: f64, dropped: &[usize]) -> Self {
        let weights: Vec<f64> = picks
            .iter()
            .enumerate()
            .map(|(i, p)| if dropped.contains(&i) { 0.0 } else { p.pmf as f64 * total_weight })
            .chain(std::iter::once(if extra.is_finite() { extra.max(0.0) } else { 0.0 }))
            .collect();
        let total_weight: f64 = weights.iter().sum();
        Self { picks: alias_table(&weights, total_weight), total_weight }
    }
}

/// Vose's alias method: entry i keeps itself with probability `threshold`, else `alias`.
fn alias_table(weights: &[f64], total: f64) -> Vec<GpuLightPick> {
    let n = weights.len();
    if n == 0 || total <= 0.0 {
        return weights.iter().map(|_| GpuLightPick { pmf: 0.0, alias: 0, threshold: 1.0, alias_pmf: 0.0 }).collect();
    }
    // Scaled so that the average entry is 1.
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut picks: Vec<GpuLightPick> =
        (0..n).map(|i| GpuLightPick { pmf: (weights[i] / total) as f32, alias: i as u32, threshold: 1.0, alias_pmf: 0.0 }).collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| scaled[i] < 1.0);
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        picks[s].threshold = scaled[s] as f32;
        picks[s].alias = l as u32;
        scaled[l] -= 1.0 - scaled[s];
        if scaled[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // What is left is 1 up to rounding: those entries always keep themselves.
    for i in small.into_iter().chain(large) {
        picks[i].threshold = 1.0;
    }
    for i in 0..n {
        picks[i].alias_pmf = picks[picks[i].alias as usize].pmf;
    }
    picks
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The probability that the alias table picks each entry, summed exactly.
    fn selection_probabilities(picks: &[GpuLightPick]) -> Vec<f64> {
        let n = picks.len() as f64;
        let mut p = vec![0.0; picks.len()];
        for (i, e) in picks.iter().enumerate() {
            p[i] += e.threshold as f64 / n;
            p[e.alias as usize] += (1.0 - e.threshold as f64) / n;
        }
        p
    }

    #[test]
    fn alias_table_picks_each_entry_by_weight() {
        let weights = [1.0, 0.0, 7.0, 2.0, 0.5, 13.0];
        let total: f64 = weights.iter().sum();
        let picks = alias_table(&weights, total);
        for (i, p) in selection_probabilities(&picks).iter().enumerate() {
            let want = weights[i] / total;
            assert!((p - want).abs() < 1e-6, "entry {i}: picked with {p}, weight says {want}");
            assert!((picks[i].pmf as f64 - want).abs() < 1e-6, "entry {i}: pmf {}", picks[i].pmf);
            // The shader reads the alias's pmf from the entry it landed on.
            assert_eq!(picks[i].alias_pmf, picks[picks[i].alias as usize].pmf, "entry {i}: alias_pmf");
        }
        assert!(picks.iter().any(|p| p.threshold < 1.0), "no entry uses its alias: the check above is empty");
    }

    #[test]
    fn an_extra_entry_joins_by_weight_and_dropped_ones_leave() {
        let weights = [1.0, 3.0, 4.0];
        let picks = alias_table(&weights, 8.0);
        let t = LightTable::with_extra(&picks, 8.0, 4.0, &[1]);
        let p = selection_probabilities(&t.picks);
        let want = [1.0 / 9.0, 0.0, 4.0 / 9.0, 4.0 / 9.0];
        for k in 0..4 {
            assert!((p[k] - want[k]).abs() < 1e-6 && (t.picks[k].pmf as f64 - want[k]).abs() < 1e-6, "entry {k}: {}", p[k]);
        }
        assert!((t.total_weight - 9.0).abs() < 1e-9);
    }

    #[test]
    fn cone_power_is_its_falloff_integrated_over_the_sphere() {
        let (cos_inner, cos_outer) = (0.9f32, 0.6f32);
        let light = GpuLight { position: [0.0; 3], kind: LIGHT_CONE, direction: [0.0, 0.0, -1.0], radius: cos_inner, intensity: [2.0; 3], cos_outer };
        // Midpoint rule over cos in [-1, 1]: power = 2 pi I integral f(c) dc.
        let n = 200_000;
        let integral: f64 = (0..n)
            .map(|k| {
                let c = -1.0 + (k as f64 + 0.5) * 2.0 / n as f64;
                crate::scene::Light::cone_falloff(c as f32, cos_inner, cos_outer) as f64 * 2.0 / n as f64
            })
            .sum();
        let want = 2.0 * std::f64::consts::PI * 2.0 * integral;
        let got = light_weight(&light, 1.0) as f64;
        assert!((got / want - 1.0).abs() < 1e-4, "cone power {got}, integral {want}");
    }

    #[test]
    fn empty_and_zero_tables_pick_nothing() {
        assert!(alias_table(&[], 0.0).is_empty());
        assert!(alias_table(&[0.0, 0.0], 0.0).iter().all(|p| p.pmf == 0.0));
    }
}
