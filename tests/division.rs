//! The ray setup's correctly rounded division (`div_rn`, shaders/include/division.glsl), run on
//! the device by shaders/test/division_probe.comp with the correction forced on: every quotient
//! in its range is the CPU's IEEE one, bit for bit, including on lavapipe, whose own division is
//! already IEEE (so the correction must leave a rounded quotient unchanged), and from quotients
//! and reciprocals put 2 ulps off (what a device whose division is off starts from: the probe
//! emulates one on lavapipe). On such a device (NVIDIA's) this is what makes the GPU's ray
//! setup the CPU twin's.

mod common;

use ash::vk;
use vkrt::gpu::commands::submit_and_wait;
use vkrt::gpu::Buffer;
use vkrt::gpu_abi::constants::*;
use vkrt::gpu_abi::GpuPush;
use vkrt::pipeline::{BindingKind, ComputePipeline};

/// (div_rn(a, b), the device's a / b, the correction from 2 ulps above, from 2 ulps below) for
/// each pair, with the correction forced `on`.
fn divide_on_device(pairs: &[[f32; 2]], on: bool) -> Vec<[f32; 4]> {
    let ctx = common::gpu_context();
    let data: Vec<[f32; 4]> = pairs.iter().map(|p| [p[0], p[1], 0.0, 0.0]).collect();
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let buf = Buffer::with_data(&ctx, "division pairs", &data, storage).unwrap();
    let bindings = [(BINDING_ACCUM, BindingKind::Storage)];
    let constants = [(SPEC_CORRECT_DIVISION, on as u32)];
    let push_size = std::mem::size_of::<GpuPush>() as u32;
    let pipeline = ComputePipeline::specialized(&ctx, "division probe", &common::probe_spirv("division_probe"), &bindings, push_size, &constants).unwrap();
    pipeline.bind(BINDING_ACCUM, &buf).unwrap();
    let push = GpuPush { ray_count: pairs.len() as u32, ..bytemuck::Zeroable::zeroed() };
    // Three pairs per invocation (one per vec3 lane).
    let groups = [(pairs.len() as u32).div_ceil(3 * ctx.workgroups.d1), 1, 1];
    submit_and_wait(&ctx, "division probe", |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups)).unwrap();
    let out: Vec<[f32; 4]> = buf.read_as(pairs.len()).unwrap();
    common::assert_no_validation_messages(&ctx);
    out
}

/// Random pairs over the range the ray setup meets (direction components, their ratios,
/// triangle determinants of tiny and huge scenes), both signs, and the hard cases: exact
/// quotients, b a power of two, b with an all-ones mantissa (where one Newton step on the
/// reciprocal is known to be delicate), a = b.
fn pairs() -> Vec<[f32; 2]> {
    let mut rng = common::Pcg::new(17);
    let mut v = Vec::new();
    let random = |rng: &mut common::Pcg, lo: f32, hi: f32| {
        let x = 2f32.powf(rng.range(lo, hi)) * (1.0 + rng.f32());
        if rng.next_u32() % 2 == 0 {
            x
        } else {
            -x
        }
    };
    for _ in 0..400_000 {
        v.push([random(&mut rng, -12.0, 12.0), random(&mut rng, -12.0, 12.0)]);
    }
    for _ in 0..100_000 {
        v.push([1.0, random(&mut rng, -40.0, 40.0)]);
    }
    let all_ones = f32::from_bits(0x3fff_ffff); // 1.9999999
    for k in -20..20 {
        let s = 2f32.powi(k);
        for a in [1.0f32, 3.0, 0.1, 1.0e-3, 7.0e5, all_ones] {
            v.push([a, s]);
            v.push([a, all_ones * s]);
            v.push([a * s, a]);
            v.push([-a, 3.0 * s]);
        }
    }
    v
}

#[test]
fn corrected_division_is_the_ieee_quotient() {
    let pairs = pairs();
    let got = divide_on_device(&pairs, true);
    let mut own_off = 0;
    let mut checked = 0;
    for (p, g) in pairs.iter().zip(&got) {
        let ieee = p[0] / p[1];
        own_off += (g[1] != ieee) as usize;
        // div_rn leaves quotients, reciprocals and dividends outside [1e-18, 1e18] to the device.
        let y = 1.0 / p[1];
        let ordinary = |x: f32| (1e-18..=1e18).contains(&x.abs());
        if !ordinary(ieee) || !ordinary(y) || p[0].abs() < 1e-18 {
            continue;
        }
        checked += 1;
        assert_eq!(g[0].to_bits(), ieee.to_bits(), "div_rn({:e}, {:e}) = {:e}, IEEE {:e} (the device's own {:e})", p[0], p[1], g[0], ieee, g[1]);
        for (from, got) in [("2 ulps above", g[2]), ("2 ulps below", g[3])] {
            assert_eq!(got.to_bits(), ieee.to_bits(), "{:e} / {:e} corrected from {from}: {:e}, IEEE {:e}", p[0], p[1], got, ieee);
        }
    }
    assert!(checked > 490_000, "only {checked} pairs in range");
    eprintln!("{own_off} of {} of the device's own quotients differ from IEEE", pairs.len());
}

/// Off, the probe is the device's own division (what lavapipe runs: nothing to correct).
#[test]
fn uncorrected_division_is_the_devices_own() {
    let pairs = pairs();
    let got = divide_on_device(&pairs[..10_000], false);
    for (p, g) in pairs.iter().zip(&got) {
        assert_eq!(g[0].to_bits(), g[1].to_bits(), "{:e} / {:e}: uncorrected {:e}, own {:e}", p[0], p[1], g[0], g[1]);
    }
}
