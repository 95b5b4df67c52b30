//! Does subgroup-coherent ("packet") traversal pay on this device? rays/s of the per-ray
//! threaded walk (`trace`) against the packet walk of the same BVH (`trace_packet`,
//! shaders/include/traverse_packet.glsl; Wald, Slusallek, Benthin & Wagner 2001) on the same
//! rays, interleaved (threaded, packet, threaded, ...) best of three, and a check that both give
//! the same hits. A benchmark, not a test.
//!
//! Ray sets: primary rays in scanline order and in 4x2 pixel tiles (8 consecutive rays, one
//! lavapipe subgroup, cover a 4x2 block), shadow rays (any hit) toward the first light from the
//! primary hits in both orders, and incoherent rays.
//!
//! Usage: cargo run --release --bin vkrt-packet-cost -- [SCENE...]
//! (default scenes: scenes/bench/conference.yaml scenes/bench/sponza.yaml)

#[path = "args.rs"]
mod args;

use anyhow::{bail, Result};
use std::time::Instant;
use vkrt::bench::rays;
use vkrt::bvh::{BuildConfig, BuilderKind};
use vkrt::gpu::{Context, ContextOptions};
use vkrt::integrator::gpu_scene::{GpuScene, PreparedScene};
use vkrt::integrator::ray_query::RayQuery;
use vkrt::layout::GpuRay;
use vkrt::pipeline::shaders;

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
/// Tile of the tiled primary order: TILE_W * TILE_H = 8, lavapipe's subgroup size on AVX2.
const TILE_W: u32 = 4;
const TILE_H: u32 = 2;

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

/// Scanline-ordered rays of a `width` x `height` image reordered tile by tile (row-major
/// tiles, row-major pixels inside a tile); both dimensions must be multiples of the tile.
fn tiled(scanline: &[GpuRay], width: u32, height: u32) -> Vec<GpuRay> {
    let mut out = Vec::with_capacity(scanline.len());
    for ty in (0..height).step_by(TILE_H as usize) {
        for tx in (0..width).step_by(TILE_W as usize) {
            for y in ty..ty + TILE_H {
                for x in tx..tx + TILE_W {
                    out.push(scanline[(y * width + x) as usize]);
                }
            }
        }
    }
    out
}

/// Interleaved best of three: (threaded, packet) rays per second, upload and read-back
/// included. Fails if the two disagree on any hit.
fn compare(threaded: &RayQuery, packet: &RayQuery, rays: &[GpuRay], any_hit: bool) -> Result<(f64, f64)> {
    let (mut bt, mut bp) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        let t = Instant::now();
        let ht = threaded.trace(rays, any_hit)?;
        bt = bt.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let hp = packet.trace(rays, any_hit)?;
        bp = bp.min(t.elapsed().as_secs_f64());
        let differ = ht
            .iter()
            .zip(&hp)
            .filter(|(a, b)| if any_hit { (a.prim == vkrt::layout::constants::PRIM_NONE) != (b.prim == vkrt::layout::constants::PRIM_NONE) } else { a.prim != b.prim || a.t != b.t })
            .count();
        if differ != 0 {
            bail!("packet and threaded traversal disagree on {differ} of {} rays", rays.len());
        }
    }
    Ok((rays.len() as f64 / bt, rays.len() as f64 / bp))
}

/// Mean nodes visited per ray: the packet's visits against the ray's own.
fn mean_nodes(query: &RayQuery, rays: &[GpuRay], any_hit: bool) -> Result<f64> {
    let hits = query.trace(rays, any_hit)?;
    Ok(hits.iter().map(|h| h.nodes_visited as f64).sum::<f64>() / hits.len().max(1) as f64)
}

fn run() -> Result<()> {
    let Some(scenes) = args::scenes_or_default("vkrt-packet-cost") else { return Ok(()) };
    let ctx = Context::new(&ContextOptions::from_env())?;
    println!("device: {}\n", ctx.info.name);
    println!("| scene | rays | threaded M rays/s | packet M rays/s | packet / threaded | nodes/ray threaded | nodes/ray packet |");
    println!("|---|---|---:|---:|---:|---:|---:|");
    for path in &scenes {
        let scene = vkrt::scene::load_scene(std::path::Path::new(path))?;
        let prepared = PreparedScene::new(&scene, BuilderKind::Sah, &BuildConfig::default())?;
        let gpu = GpuScene::upload(&ctx, &prepared)?;
        let threaded = RayQuery::with_shader(&ctx, &gpu, shaders::TRACE)?;
        let packet = RayQuery::with_shader(&ctx, &gpu, shaders::TRACE_PACKET)?;
        let primary = rays::primary(&scene, WIDTH, HEIGHT)?;
        let primary_tiled = tiled(&primary, WIDTH, HEIGHT);
        let (shadow, _) = rays::secondary(&scene, &primary, &threaded.trace(&primary, false)?, 7);
        let (shadow_tiled, _) = rays::secondary(&scene, &primary_tiled, &threaded.trace(&primary_tiled, false)?, 7);
        let sets = [
            ("primary 640x480 scanline", primary, false),
            ("primary 640x480 4x2 tiles", primary_tiled, false),
            ("shadow (any hit) scanline", shadow, true),
            ("shadow (any hit) 4x2 tiles", shadow_tiled, true),
            ("incoherent 300k", rays::incoherent(&scene, 300_000, 1), false),
        ];
        for (kind, set, any_hit) in &sets {
            let (t, p) = compare(&threaded, &packet, set, *any_hit)?;
            let (nt, np) = (mean_nodes(&threaded, set, *any_hit)?, mean_nodes(&packet, set, *any_hit)?);
            println!("| {path} | {kind} | {:.2} | {:.2} | {:.2} | {nt:.1} | {np:.1} |", t / 1e6, p / 1e6, p / t);
        }
    }
    Ok(())
}
