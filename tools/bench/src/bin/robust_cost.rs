//! What the robust intersection tests cost and what they buy: rays/s of the robust `trace`
//! shader against the textbook one (`trace_plain`: unpadded slabs, Möller-Trumbore with an
//! epsilon) on the same rays, and how many rays each lets leak out of closed meshes.
//! A benchmark, not a test.
//!
//! Usage: cargo run --release -p vkrt-bench --bin vkrt-robust-cost -- [SCENE...]
//! (default scenes: scenes/bench/conference.yaml scenes/bench/sponza.yaml)

use anyhow::Result;
use glam::Vec3;
use std::time::Instant;
use vkrt::gpu::{Context, ContextOptions};
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::GpuRay;
use vkrt::pipeline::shaders;
use vkrt::prepare::{build_bvh, GpuBvh, PrepareOptions};
use vkrt::query::{rays, RayQuery};
use vkrt_bench::args;
use vkrt_bench::closed_meshes::{icosphere, subdivided_cube, torus};

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

/// Best of three: rays per second through `query`, upload and read-back included.
fn rays_per_second(query: &RayQuery, rays: &[GpuRay]) -> Result<f64> {
    let mut best = f64::INFINITY;
    for _ in 0..3 {
        let t = Instant::now();
        query.trace(rays, false)?;
        best = best.min(t.elapsed().as_secs_f64());
    }
    Ok(rays.len() as f64 / best)
}

fn run() -> Result<()> {
    let Some(scenes) = args::scenes_or_default("vkrt-robust-cost") else { return Ok(()) };
    let ctx = Context::new(&ContextOptions::from_env())?;
    println!("device: {}\n", ctx.info.name);
    println!("| scene | rays | robust M rays/s | plain M rays/s | robust / plain |");
    println!("|---|---|---:|---:|---:|");
    for path in &scenes {
        let scene = vkrt::scene::load_scene(std::path::Path::new(path))?;
        let gpu = GpuBvh::upload(&ctx, &build_bvh(&scene, &PrepareOptions::default())?.0)?;
        let robust = RayQuery::new(&ctx, &gpu)?;
        let plain = RayQuery::with_shader(&ctx, &gpu, shaders::TRACE_PLAIN)?;
        for (kind, set) in [("primary 640x480", rays::primary(&scene, 640, 480)?), ("incoherent 300k", rays::incoherent(&scene, 300_000, 1))] {
            let r = rays_per_second(&robust, &set)?;
            let p = rays_per_second(&plain, &set)?;
            println!("| {path} | {kind} | {:.2} | {:.2} | {:.2} |", r / 1e6, p / 1e6, r / p);
        }
    }
    println!("\n| mesh | scale | offset | rays from inside | robust leaks | plain leaks |");
    println!("|---|---:|---|---:|---:|---:|");
    let meshes = [("icosphere(4)", icosphere(4)), ("cube(16)", subdivided_cube(16)), ("torus(96x48)", torus(1.0, 0.4, 96, 48))];
    for (name, mesh) in &meshes {
        for (scale, offset) in [(1.0f32, Vec3::ZERO), (1e-3, Vec3::ZERO), (1e3, Vec3::new(1e5, -3e4, 7e4))] {
            let scene = vkrt_bench::procedural::scene_of(mesh.to_triangles(scale, offset, 0));
            let centre = if name.starts_with("torus") { Vec3::X * scale + offset } else { offset };
            // Rays aimed exactly at every vertex and edge midpoint: where leaks happen.
            let world: Vec<Vec3> = mesh.positions.iter().map(|&p| p * scale + offset).collect();
            let mut targets = world.clone();
            targets.extend(mesh.edges().iter().map(|&(a, b)| (world[a as usize] + world[b as usize]) * 0.5));
            let set: Vec<GpuRay> =
                targets.iter().map(|&t| GpuRay { origin: centre.to_array(), tmin: 0.0, direction: (t - centre).to_array(), tmax: f32::INFINITY }).collect();
            let gpu = GpuBvh::upload(&ctx, &build_bvh(&scene, &PrepareOptions::default())?.0)?;
            let leaks = |q: &RayQuery| -> Result<usize> { Ok(q.trace(&set, false)?.iter().filter(|h| h.prim == PRIM_NONE).count()) };
            let robust = leaks(&RayQuery::new(&ctx, &gpu)?)?;
            let plain = leaks(&RayQuery::with_shader(&ctx, &gpu, shaders::TRACE_PLAIN)?)?;
            println!("| {name} | {scale:e} | {offset} | {} | {robust} | {plain} |", set.len());
        }
    }
    Ok(())
}
