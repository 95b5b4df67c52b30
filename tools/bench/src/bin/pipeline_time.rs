//! How long the driver takes to make each tracing pipeline ready: vkCreateComputePipelines plus
//! a first one-workgroup dispatch that returns at once (zeroed frame and push constants). On
//! lavapipe most of the cost is in that first dispatch, where llvmpipe runs LLVM code
//! generation, and it grows with the number of places the traversal loop is inlined.
//! A benchmark, not a test.
//!
//! Usage: MESA_SHADER_CACHE_DISABLE=true cargo run --release -p vkrt-bench --bin vkrt-pipeline-time -- [REPEAT] [VARIANT...]
//! (default: best of 3 for every whitted, path and trace variant). Without the cache switch,
//! Mesa's on-disk shader cache answers every run after the first.

use anyhow::Result;
use ash::vk;
use std::time::Instant;
use vkrt::gpu::commands::submit_and_wait;
use vkrt::gpu::{Buffer, Context, ContextOptions, MemoryLocation, TexelFormat};
use vkrt::gpu_abi::constants::*;
use vkrt::integrator::frame::INTEGRATOR_BINDINGS;
use vkrt::integrator::path::params::PATH_BINDINGS;
use vkrt::pipeline::{shaders, BindingKind, ComputePipeline};
use vkrt_bench::args;

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

fn run() -> Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let repeat = args::leading_count(&mut args, 3);
    let names: Vec<&str> = if args.is_empty() {
        shaders::ALL.iter().map(|(n, _)| *n).filter(|n| n.starts_with("whitted") || n.starts_with("path") || n.starts_with("trace")).collect()
    } else {
        args.iter().map(String::as_str).collect()
    };
    // Every binding any tracing shader declares, of the kind the integrators bind (the rays and
    // hits of trace.comp are storage buffers); unused ones cost nothing.
    let kind_of = |b: u32| INTEGRATOR_BINDINGS.iter().chain(PATH_BINDINGS).find(|e| e.0 == b).map_or(BindingKind::Storage, |e| e.1);
    let bindings: Vec<(u32, BindingKind)> = (0..=BINDING_UVS).chain([BINDING_TANGENTS]).map(|b| (b, kind_of(b))).collect();
    let ctx = Context::new(&ContextOptions::from_env())?;
    println!("device: {}\n", ctx.info.name);
    // Zeroed buffers: frame.width = 0 and ray_count = 0 make every invocation return at once.
    let buffers = bindings
        .iter()
        .map(|&(b, kind)| {
            let usage = match kind {
                BindingKind::Uniform => vk::BufferUsageFlags::UNIFORM_BUFFER,
                BindingKind::Texels => vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
                BindingKind::Storage => vk::BufferUsageFlags::STORAGE_BUFFER,
            };
            let buf = Buffer::new(&ctx, "dummy", 256, usage, MemoryLocation::Device)?;
            buf.clear()?;
            // Views before buffers in the tuple: dropped first.
            let format = if b == BINDING_TEXELS { TexelFormat::R32Uint } else { TexelFormat::Rgba32Uint };
            let view = if kind == BindingKind::Texels { Some(buf.texel_view(format)?) } else { None };
            Ok((b, view, buf))
        })
        .collect::<Result<Vec<_>>>()?;
    let push = [0u8; std::mem::size_of::<vkrt::gpu_abi::GpuPush>()];
    println!("| variant | SPIR-V bytes | create + first dispatch ms (best of {repeat}) |");
    println!("|---|---:|---:|");
    // Interleaved: round r creates every variant once, so a slow spell hits all of them.
    let mut best = vec![f64::INFINITY; names.len()];
    for _ in 0..repeat {
        for (i, name) in names.iter().enumerate() {
            let spv = shaders::ALL.iter().find(|(n, _)| n == name).map(|(_, s)| *s).ok_or_else(|| anyhow::anyhow!("no shader variant '{name}'"))?;
            let t = Instant::now();
            let pipeline = ComputePipeline::new(&ctx, name, spv, &bindings, std::mem::size_of::<vkrt::gpu_abi::GpuPush>() as u32)?;
            for (b, view, buf) in &buffers {
                match view {
                    Some(v) => pipeline.bind_texels(*b, v)?,
                    None => pipeline.bind(*b, buf)?,
                }
            }
            submit_and_wait(&ctx, "first dispatch", |cmd| pipeline.record_dispatch(cmd, &push, [1, 1, 1]))?;
            best[i] = best[i].min(t.elapsed().as_secs_f64());
            drop(pipeline);
        }
    }
    for (i, name) in names.iter().enumerate() {
        let bytes = shaders::ALL.iter().find(|(n, _)| n == name).map_or(0, |(_, s)| s.len());
        println!("| {name} | {bytes} | {:.0} |", best[i] * 1e3);
    }
    Ok(())
}
