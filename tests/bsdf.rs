//! The path tracer's BSDFs (shaders/include/bsdf.glsl), run on the GPU by
//! shaders/test/bsdf_probe.comp: for every lobe and three outgoing angles,
//! - the density a sample reports equals bsdf_eval's density at that direction;
//! - bsdf_eval's density integrates (over uniform directions) to the probability of drawing a
//!   non-delta sample, so the two agree on normalisation;
//! - the directions drawn follow bsdf_eval's density, bin by bin (a z-score per bin);
//! - no sample gains energy (albedo <= 1), and the dielectric reflects with Fresnel's odds;
//! - f(wo, wi) = f(wi, wo) (reciprocity) at the uniform directions;
//!
//! and the same for glTF metallic-roughness materials, whose measured albedos are stated.

mod common;

use ash::vk;
use glam::Vec3;
use std::f64::consts::PI;
use vkrt::gpu::commands::submit_and_wait;
use vkrt::gpu::{Buffer, MemoryLocation};
use vkrt::gpu_abi::constants::*;
use vkrt::gpu_abi::GpuPush;
use vkrt::pipeline::{BindingKind, ComputePipeline};
use vkrt::prepare::scene_buffers::gpu_material;
use vkrt::scene::{Material, MetallicRoughness};

const SAMPLES: u32 = 1 << 16;
const ANGLES: [f64; 3] = [0.95, 0.6, 0.2];

fn materials() -> Vec<(&'static str, Material)> {
    let m = |diffuse: f32, specular: f32, shininess: f32, illum: u32| Material {
        diffuse: Vec3::splat(diffuse),
        specular: Vec3::splat(specular),
        shininess,
        illum,
        ..Material::default()
    };
    vec![
        ("lambert", m(0.8, 0.0, 1.0, 1)),
        ("glossy Ns 20", m(0.0, 1.0, 20.0, 2)),
        ("lambert + glossy Ns 200", m(0.6, 0.3, 200.0, 2)),
        ("rough glossy Ns 1", m(0.0, 0.9, 1.0, 2)),
        ("lambert + mirror", m(0.5, 0.4, 1.0, 3)),
        ("glass", m(0.0, 0.0, 1.0, 7)),
    ]
}

struct Probe {
    wi: [f64; 3],
    pdf_sampled: f64,
    pdf_eval: f64,
    weight: f64,
    delta: bool,
    ok: bool,
    u: [f64; 3],
    pdf_u: f64,
    /// f(wo, u) and f(u, wo), channel means.
    f_ou: f64,
    f_uo: f64,
}

fn run_probe(mats: &[Material]) -> Vec<Probe> {
    let ctx = common::gpu_context();
    let gpu_mats: Vec<_> = mats.iter().map(gpu_material).collect();
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let mat_buf = Buffer::with_data(&ctx, "materials", &gpu_mats, storage).unwrap();
    let count = mats.len() as u64 * ANGLES.len() as u64 * SAMPLES as u64;
    let out = Buffer::new(&ctx, "probe output", count * 64, storage, MemoryLocation::Device).unwrap();
    let bindings = [(BINDING_MATERIALS, BindingKind::Storage), (BINDING_ACCUM, BindingKind::Storage)];
    let pipeline = ComputePipeline::new(&ctx, "bsdf probe", &common::probe_spirv("bsdf_probe"), &bindings, std::mem::size_of::<GpuPush>() as u32).unwrap();
    pipeline.bind(BINDING_MATERIALS, &mat_buf).unwrap();
    pipeline.bind(BINDING_ACCUM, &out).unwrap();
    let push = GpuPush { sample_count: SAMPLES, sample_base: 1234, ..bytemuck::Zeroable::zeroed() };
    let groups = [(count as u32).div_ceil(ctx.workgroups.d1), 1, 1];
    submit_and_wait(&ctx, "bsdf probe", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups)).unwrap();
    let raw: Vec<[f32; 4]> = out.read_as(count as usize * 4).unwrap();
    common::assert_no_validation_messages(&ctx);
    let d = |v: [f32; 4]| [v[0] as f64, v[1] as f64, v[2] as f64];
    raw.chunks_exact(4)
        .map(|c| Probe {
            wi: d(c[0]),
            pdf_sampled: c[0][3] as f64,
            pdf_eval: c[1][0] as f64,
            weight: c[1][1] as f64,
            delta: c[1][2] > 0.5,
            ok: c[1][3] > 0.5,
            u: d(c[2]),
            pdf_u: c[2][3] as f64,
            f_ou: c[3][0] as f64,
            f_uo: c[3][1] as f64,
        })
        .collect()
}

/// Bin of a direction in the upper hemisphere: 8 bins in cos(theta), 8 in phi.
fn bin(w: [f64; 3]) -> Option<usize> {
    if w[2] <= 0.0 {
        return None;
    }
    let t = ((w[2] * 8.0) as usize).min(7);
    let phi = w[1].atan2(w[0]) + PI;
    let p = ((phi / (2.0 * PI) * 8.0) as usize).min(7);
    Some(t * 8 + p)
}

fn fresnel(cos_i: f64, eta: f64) -> f64 {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

#[test]
fn sampling_and_evaluation_agree_for_every_lobe() {
    check_lobes(&materials(), |_, _, albedo| albedo <= 1.0 + 1e-3);
}

/// glTF 2.0 metallic-roughness materials (base colour, metallic, roughness).
fn metallic_roughness_materials() -> Vec<(&'static str, Material)> {
    let m = |base: Vec3, metallic: f32, roughness: f32| Material {
        diffuse: base,
        metallic_roughness: Some(MetallicRoughness { metallic, roughness, texture: None }),
        ..Material::default()
    };
    vec![
        ("metal, roughness 0", m(Vec3::ONE, 1.0, 0.0)),
        ("metal, roughness 0.2", m(Vec3::ONE, 1.0, 0.2)),
        ("metal, roughness 0.5", m(Vec3::ONE, 1.0, 0.5)),
        ("black metal, roughness 0.4", m(Vec3::ZERO, 1.0, 0.4)),
        ("dielectric, roughness 1", m(Vec3::ONE, 0.0, 1.0)),
        ("dielectric, roughness 0.3", m(Vec3::splat(0.8), 0.0, 0.3)),
        ("half metal, roughness 0.6", m(Vec3::new(0.9, 0.5, 0.2), 0.5, 0.6)),
    ]
}

#[test]
fn metallic_roughness_sampling_evaluation_and_albedo() {
    // The metal lobe (GGX, Schlick Fresnel tinted by the base colour) loses, never gains,
    // energy, and a smooth white one keeps nearly all. glTF's dielectric fresnel_mix (Lambert
    // weighted by 1 - F(wo.h), plus GGX weighted by F) is not energy conserving: seen at grazing
    // angles a fairly smooth one its albedo goes above 1 (1.009 for base 0.8, roughness 0.3, cos 0.2
    // on lavapipe), so the bound there is what the
    // specification's model gives (measured on lavapipe: see the printed albedos).
    check_lobes(&metallic_roughness_materials(), |name, cos_o, albedo| {
        let metal = name.contains("metal") && !name.contains("half");
        if metal {
            let lossless = name == "metal, roughness 0";
            albedo <= 1.0 + 1e-3 && (!lossless || albedo >= 0.97)
        } else {
            albedo <= if cos_o < 0.5 { 1.1 } else { 1.0 + 1e-3 }
        }
    });
}

/// Every check of the module's header on `named`; `albedo_ok(name, cos_o, albedo)` says which
/// albedos the material may have.
fn check_lobes(named: &[(&'static str, Material)], albedo_ok: impl Fn(&str, f64, f64) -> bool) {
    let mats: Vec<Material> = named.iter().map(|(_, m)| m.clone()).collect();
    let probes = run_probe(&mats);
    let n = SAMPLES as usize;
    for (mi, (name, mat)) in named.iter().enumerate() {
        for (ai, cos_o) in ANGLES.iter().enumerate() {
            let set = &probes[(mi * ANGLES.len() + ai) * n..][..n];
            let what = format!("{name}, cos(theta_o) {cos_o}");
            // 1. Reported and evaluated densities agree, sample by sample.
            for p in set.iter().filter(|p| p.ok && !p.delta) {
                assert!(
                    (p.pdf_sampled - p.pdf_eval).abs() <= 1e-3 * p.pdf_eval + 1e-6,
                    "{what}: sampled pdf {} vs evaluated {} at {:?}",
                    p.pdf_sampled,
                    p.pdf_eval,
                    p.wi
                );
            }
            // 2. No energy gain: the mean weight (albedo estimate) is at most 1 (or what
            // `albedo_ok` allows).
            let albedo = set.iter().map(|p| p.weight).sum::<f64>() / n as f64;
            eprintln!("{what}: albedo {albedo:.4}");
            assert!(albedo_ok(name, *cos_o, albedo), "{what}: albedo {albedo}");
            // Reciprocity: f(wo, u) = f(u, wo) wherever both are above the surface.
            for p in set.iter().filter(|p| p.u[2] > 0.0) {
                assert!((p.f_ou - p.f_uo).abs() <= 2e-3 * p.f_ou.max(p.f_uo) + 1e-6, "{what}: f(wo, u) {} but f(u, wo) {} at u {:?}", p.f_ou, p.f_uo, p.u);
            }
            // A near-delta lobe (GGX alpha 1e-3) covers too little of the sphere for uniform
            // directions to integrate or bin its density: only 1, 2 and reciprocity hold there.
            if mat.metallic_roughness.is_some_and(|mr| mr.roughness < 0.05) {
                continue;
            }
            // 3. Normalisation: the evaluated pdf integrates to P(non-delta sample drawn).
            let integral = set.iter().map(|p| p.pdf_u).sum::<f64>() * 4.0 * PI / n as f64;
            let smooth_fraction = set.iter().filter(|p| p.ok && !p.delta).count() as f64 / n as f64;
            let sd = (set.iter().map(|p| (p.pdf_u * 4.0 * PI).powi(2)).sum::<f64>() / n as f64).sqrt() / (n as f64).sqrt();
            assert!(
                (integral - smooth_fraction).abs() <= 5.0 * sd + 0.01,
                "{what}: pdf integrates to {integral:.4} (+-{sd:.4}), samples are non-delta with odds {smooth_fraction:.4}"
            );
            // 4. Histogram of drawn directions against the evaluated density.
            let mut observed = [0.0f64; 64];
            let mut expected = [0.0f64; 64];
            let mut expected_var = [0.0f64; 64];
            for p in set {
                if p.ok && !p.delta {
                    if let Some(b) = bin(p.wi) {
                        observed[b] += 1.0;
                    }
                }
                if let Some(b) = bin(p.u) {
                    let v = p.pdf_u * 4.0 * PI; // per-sample estimate of the bin's share of n
                    expected[b] += v;
                    expected_var[b] += v * v;
                }
            }
            for b in 0..64 {
                let z = (observed[b] - expected[b]) / (observed[b] + expected_var[b]).sqrt().max(1.0);
                assert!(z.abs() < 5.0, "{what}: bin {b}: {} drawn, density says {:.1} (z = {z:.1})", observed[b], expected[b]);
            }
            // 5. The dielectric reflects with Fresnel's probability (entering, eta = 1 / Ni).
            if mat.is_dielectric() {
                let reflected = set.iter().filter(|p| p.ok && p.wi[2] > 0.0).count() as f64 / n as f64;
                let f = fresnel(*cos_o, 1.0 / mat.ior as f64);
                let sd = (f * (1.0 - f) / n as f64).sqrt();
                assert!((reflected - f).abs() <= 5.0 * sd + 1e-4, "{what}: reflects {reflected:.4}, Fresnel says {f:.4}");
            }
        }
    }
}
