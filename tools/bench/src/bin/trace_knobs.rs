//! Rays/s of the `trace` shader as the BVH's leaf size and layout change, on the same rays,
//! measured interleaved (round r times every configuration once; best of the rounds), so that
//! the development machine's speed swings hit every configuration alike. A benchmark, not a test.
//!
//! Usage: cargo run --release -p vkrt-bench --bin vkrt-trace-knobs -- [ROUNDS] [SCENE...]
//! (default: 3 rounds on scenes/bench/conference.yaml)

use anyhow::Result;
use std::time::Instant;
use vkrt::accel::{FlatBvh, LayoutKind};
use vkrt::bvh::BuildConfig;
use vkrt::gpu::{Context, ContextOptions};
use vkrt::prepare::{build_bvh, GpuBvh, PrepareOptions};
use vkrt::query::{rays, RayQuery};
use vkrt_bench::args;

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

fn run() -> Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let rounds = args::leading_count(&mut args, 3);
    if args.is_empty() {
        args = vec!["scenes/bench/conference.yaml".into()];
    }
    let ctx = Context::new(&ContextOptions::from_env())?;
    println!("device: {}\n", ctx.info.name);
    println!("| scene | layout | max leaf | rays | M rays/s (best of {rounds}) | nodes/ray | tris/ray |");
    println!("|---|---|---:|---|---:|---:|---:|");
    for path in &args {
        let scene = vkrt::scene::load_scene(std::path::Path::new(path))?;
        let sets = [("primary 640x480", rays::primary(&scene, 640, 480)?), ("incoherent 300k", rays::incoherent(&scene, 300_000, 1))];
        let mut configs = Vec::new();
        for layout in [LayoutKind::Threaded, LayoutKind::ParentLink] {
            for leaf in [1u32, 2, 4, 8] {
                let config = BuildConfig { max_leaf_size: leaf, ..BuildConfig::default() };
                let options = PrepareOptions { layout, build: config, ..PrepareOptions::default() };
                let flat: FlatBvh = build_bvh(&scene, &options)?.0;
                configs.push((layout, leaf, flat));
            }
        }
        let gpus = configs.iter().map(|(_, _, f)| GpuBvh::upload(&ctx, f)).collect::<Result<Vec<_>>>()?;
        let queries = gpus.iter().map(|g| RayQuery::new(&ctx, g)).collect::<Result<Vec<_>>>()?;
        for (kind, set) in &sets {
            let mut best = vec![f64::INFINITY; queries.len()];
            let mut counters = vec![(0.0, 0.0); queries.len()];
            for _ in 0..rounds {
                for (i, q) in queries.iter().enumerate() {
                    let t = Instant::now();
                    let hits = q.trace(set, false)?;
                    best[i] = best[i].min(t.elapsed().as_secs_f64());
                    let n = hits.len().max(1) as f64;
                    counters[i] = (hits.iter().map(|h| h.nodes_visited as f64).sum::<f64>() / n, hits.iter().map(|h| h.tris_tested as f64).sum::<f64>() / n);
                }
            }
            for (i, (layout, leaf, _)) in configs.iter().enumerate() {
                let mrays = set.len() as f64 / best[i] / 1e6;
                println!("| {path} | {} | {leaf} | {kind} | {mrays:.2} | {:.1} | {:.2} |", layout.name(), counters[i].0, counters[i].1);
            }
        }
    }
    Ok(())
}
