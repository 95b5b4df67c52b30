//! The path tracer's samplers (shaders/include/sampler.glsl), run on the GPU by
//! shaders/test/sampler_probe.comp:
//! - Sobol: every 2D pair of every pixel is a (0,2)-sequence after scrambling and shuffling:
//!   its first 2^m points put exactly one point in each elementary interval of area 2^-m
//!   (Owen scrambling and Burley's index shuffle keep this; Burley 2020, JCGT 9(4));
//! - Z-ordered Sobol: each pixel's pairs are such nets too, and every aligned square of
//!   2^a x 2^a pixels (a run of 4^a cells in Z order) together draws a finer net, which is
//!   what makes neighbours' errors cancel (Ahmed & Wonka 2020);
//! - every sampler: values lie in [0, 1), and pixels and pairs are decorrelated (no two
//!   pixels or pairs draw the same sequence).

mod common;

use ash::vk;
use vkrt::gpu::commands::submit_and_wait;
use vkrt::gpu::{Buffer, MemoryLocation};
use vkrt::gpu_abi::constants::*;
use vkrt::gpu_abi::GpuPush;
use vkrt::pipeline::{BindingKind, ComputePipeline};

/// Samples per pixel: 2^LOG_N.
const LOG_N: u32 = 8;
const N: u32 = 1 << LOG_N;
const PIXELS: u32 = 64;
/// 2D draws per sample (PROBE_PAIRS in the shader).
const PAIRS: usize = 4;

/// draws[pixel][sample][pair] = (x, y).
fn run_probe(kind: u32, seed: u32) -> Vec<Vec<[[f32; 2]; PAIRS]>> {
    let ctx = common::gpu_context();
    let count = (N * PIXELS) as u64;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let out = Buffer::new(&ctx, "probe output", count * (PAIRS as u64) * 8, storage, MemoryLocation::Device).unwrap();
    let bindings = [(BINDING_ACCUM, BindingKind::Storage)];
    let pipeline =
        ComputePipeline::new(&ctx, "sampler probe", &common::probe_spirv("sampler_probe"), &bindings, std::mem::size_of::<GpuPush>() as u32).unwrap();
    pipeline.bind(BINDING_ACCUM, &out).unwrap();
    let push = GpuPush { sample_count: N, total_spp: PIXELS, sample_base: seed, ray_count: kind, ..bytemuck::Zeroable::zeroed() };
    let groups = [(count as u32).div_ceil(ctx.workgroups.d1), 1, 1];
    submit_and_wait(&ctx, "sampler probe", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups)).unwrap();
    let raw: Vec<[f32; 2]> = out.read_as(count as usize * PAIRS).unwrap();
    common::assert_no_validation_messages(&ctx);
    raw.chunks_exact(PAIRS * N as usize).map(|pixel| pixel.chunks_exact(PAIRS).map(|s| [s[0], s[1], s[2], s[3]]).collect()).collect()
}

/// Elementary intervals of area 2^-m (2^a by 2^(m-a) cells, every a) that the points miss or
/// share; 0 for a (0,m,2)-net.
fn net_defects(points: &[[f32; 2]], m: u32) -> usize {
    let mut defects = 0;
    for a in 0..=m {
        let (nx, ny) = (1usize << a, 1usize << (m - a));
        let mut cells = vec![0u32; nx * ny];
        for p in points {
            let cx = (p[0] as f64 * nx as f64) as usize;
            let cy = (p[1] as f64 * ny as f64) as usize;
            cells[cy.min(ny - 1) * nx + cx.min(nx - 1)] += 1;
        }
        defects += cells.iter().filter(|&&c| c != 1).count();
    }
    defects
}

#[test]
fn sobol_pairs_are_scrambled_0_2_sequences() {
    let draws = run_probe(SAMPLER_SOBOL, 7);
    for (pixel, samples) in draws.iter().enumerate() {
        for pair in 0..PAIRS {
            let points: Vec<[f32; 2]> = samples.iter().map(|s| s[pair]).collect();
            for m in 0..=LOG_N {
                let prefix = &points[..1 << m];
                assert_eq!(net_defects(prefix, m), 0, "pixel {pixel}, pair {pair}: the first 2^{m} points are not a (0,{m},2)-net");
            }
        }
    }
}

/// Pixels `first .. first + run` of the probe, pair `pair`, all their points.
fn run_points(draws: &[Vec<[[f32; 2]; PAIRS]>], first: usize, run: usize, pair: usize) -> Vec<[f32; 2]> {
    draws[first..first + run].iter().flatten().map(|s| s[pair]).collect()
}

#[test]
fn zsobol_pixels_and_squares_of_pixels_are_nets() {
    let draws = run_probe(SAMPLER_ZSOBOL, 7);
    for pair in 0..PAIRS {
        for (cell, samples) in draws.iter().enumerate() {
            let points: Vec<[f32; 2]> = samples.iter().map(|s| s[pair]).collect();
            for m in 0..=LOG_N {
                assert_eq!(net_defects(&points[..1 << m], m), 0, "cell {cell}, pair {pair}: the first 2^{m} points are not a (0,{m},2)-net");
            }
        }
        for a in 1..=3u32 {
            let run = 1usize << (2 * a);
            for first in (0..PIXELS as usize).step_by(run) {
                let m = LOG_N + 2 * a;
                assert_eq!(net_defects(&run_points(&draws, first, run, pair), m), 0, "cells {first}..+{run}, pair {pair}: not a (0,{m},2)-net");
            }
        }
    }
    // The property is Z order's: pixels with their own sequences (sobol) jointly are not nets.
    let own = run_probe(SAMPLER_SOBOL, 7);
    let defects: usize = (0..PIXELS as usize).step_by(4).map(|first| net_defects(&run_points(&own, first, 4, 0), LOG_N + 2)).sum();
    assert!(defects > 0, "sobol's independent pixels form nets together too: the check cannot tell");
}

#[test]
fn draws_are_in_the_unit_square_and_decorrelated() {
    for kind in [SAMPLER_SOBOL, SAMPLER_INDEPENDENT, SAMPLER_ZSOBOL] {
        let draws = run_probe(kind, 3);
        let mut seen = std::collections::HashSet::new();
        for samples in &draws {
            for pair in 0..PAIRS {
                let seq: Vec<[u32; 2]> = samples.iter().map(|s| [s[pair][0].to_bits(), s[pair][1].to_bits()]).collect();
                for s in samples {
                    assert!(s[pair].iter().all(|&x| (0.0..1.0).contains(&x)), "kind {kind}: {:?} outside [0, 1)", s[pair]);
                }
                assert!(seen.insert(seq), "kind {kind}: two pixels or pairs draw the same sequence");
            }
        }
    }
}

#[test]
fn another_seed_draws_other_points() {
    let a = run_probe(SAMPLER_SOBOL, 1);
    let b = run_probe(SAMPLER_SOBOL, 2);
    let same = a.iter().flatten().zip(b.iter().flatten()).filter(|(x, y)| x == y).count();
    assert!(same * 100 < a.len() * N as usize, "{same} of {} samples equal across seeds", a.len() * N as usize);
}
