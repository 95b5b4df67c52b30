//! Builds every BVH builder over each scene given and prints a Markdown table: build time
//! (best of several single-threaded builds), SAH cost (tinybvh's normalisation), node count,
//! depth and bytes of the flat layout. A benchmark, not a test.
//!
//! Usage: cargo run --release -p vkrt-bench --bin vkrt-bvh-report -- SCENE... [--repeat N]

use anyhow::{Context as _, Result};
use std::time::Instant;
use vkrt::bvh::{self, stats::stats, validate::validate, BuildConfig, BuilderKind};

fn main() -> std::process::ExitCode {
    vkrt::error::exit_code(run())
}

fn run() -> Result<()> {
    let mut scenes = Vec::new();
    let mut repeat = 5usize;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        if a == "--repeat" {
            repeat = args.next().context("--repeat needs a number")?.parse().context("--repeat")?;
        } else if a == "-h" || a == "--help" {
            println!("usage: vkrt-bvh-report SCENE... [--repeat N]");
            return Ok(());
        } else {
            scenes.push(std::path::PathBuf::from(a));
        }
    }
    if scenes.is_empty() {
        anyhow::bail!("no scene given; usage: vkrt-bvh-report SCENE... [--repeat N]");
    }
    println!("| scene | triangles | builder | build ms (best of {repeat}) | SAH cost | nodes | depth | flat bytes |");
    println!("|---|---:|---|---:|---:|---:|---:|---:|");
    for path in &scenes {
        let scene = vkrt::scene::load_scene(path)?;
        let (boxes, centroids) = vkrt::scene::triangle_boxes(&scene.triangles);
        for builder in BuilderKind::ALL {
            let config = BuildConfig::default();
            let mut best = f64::INFINITY;
            let mut tree = bvh::Bvh::default();
            for _ in 0..repeat.max(1) {
                let t = Instant::now();
                tree = bvh::build(builder, &boxes, &centroids, &config);
                best = best.min(t.elapsed().as_secs_f64() * 1e3);
            }
            validate(&tree, &boxes).map_err(|e| anyhow::anyhow!("{builder:?} tree of {} is invalid: {e}", path.display()))?;
            let s = stats(&tree);
            let flat = vkrt::accel::flatten(&tree, &scene.triangles, vkrt::accel::LayoutKind::Threaded)?;
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            println!(
                "| {name} | {} | {builder:?} | {best:.1} | {:.2} | {} | {} | {:.1} MiB |",
                scene.triangles.len(),
                s.sah_cost,
                s.nodes,
                s.max_depth,
                flat.bytes() as f64 / (1024.0 * 1024.0)
            );
        }
    }
    Ok(())
}
