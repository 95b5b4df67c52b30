//! `vkrt trace`: batch ray queries without rendering. Rays come from an `.npy` file of shape
//! (N, 8) and hits go to an `.npy` structured array (format in `output::npy`), both streamed in
//! batches of [`FILE_BATCH`] rays so that files of any size need bounded memory.

use crate::accel::{multi_order, LayoutKind};
use crate::bvh::{BuildConfig, BuilderKind};
use crate::gpu::TexelFormat;
use crate::gpu_abi::constants::PRIM_NONE;
use crate::gpu_abi::{GpuNode, GpuWideNode};
use crate::output::npy::{HitWriter, RayReader};
use crate::prepare::{build_walk, GpuBvh, PrepareOptions};
use crate::query::{RayOrder, RayQuery};
use anyhow::{Context as _, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;

/// Rays read, traced and written per round: 1M rays are 32 MiB in and 32 MiB of GPU hits out.
pub const FILE_BATCH: usize = 1 << 20;

#[derive(Debug, Args)]
pub struct TraceArgs {
    /// Scene file (.obj, lab .yaml, glTF .gltf/.glb). Hit `prim` is the index in its triangle order (file
    /// order, after degenerate triangles are dropped).
    pub scene: PathBuf,
    /// Rays: float32 .npy of shape (N, 8): origin xyz, tmin, direction xyz, tmax.
    #[arg(long, value_name = "RAYS.npy")]
    pub rays: PathBuf,
    /// Hits: .npy structured array (t f4 +inf on a miss, prim u4 0xFFFFFFFF on a miss, u, v f4).
    #[arg(short, long, visible_alias = "out", value_name = "HITS.npy")]
    pub output: PathBuf,
    /// BVH builder.
    #[arg(long, value_enum, default_value_t = BuilderKind::default())]
    pub builder: BuilderKind,
    /// BVH layout the shader walks [default: multi-order, the fastest measured on both camera
    /// and incoherent rays (BENCHMARKS.md); threaded where six orders of the tree might not fit
    /// the device's texel buffers. A scene with instances (the lab YAML's `Instances`, glTF
    /// meshes placed more than once) is walked through a two-level BVH, one tree per mesh
    /// under a tree of instances, in multi-order or threaded levels; another layout walks the
    /// copies expanded].
    #[arg(long, value_enum)]
    pub layout: Option<LayoutKind>,
    /// Put every triangle in the BVH, none in the triangle list that the scene's few largest
    /// triangles (a room's walls) otherwise join, tested by every ray before its walk.
    #[arg(long)]
    pub no_triangle_list: bool,
    /// Any-hit (shadow) queries: stop at the first hit found, not the closest.
    #[arg(long)]
    pub any_hit: bool,
    /// Tracing order: `auto` sorts each batch of incoherent rays by direction and origin (so
    /// the device's SIMD lanes walk alike) and leaves coherent ones as they are; `given` never
    /// sorts, `sorted` always does. Hits come out in file order either way.
    #[arg(long, value_enum, default_value_t = RayOrder::Auto)]
    pub order: RayOrder,
    #[command(flatten)]
    pub device: super::DeviceArgs,
}

/// What a `vkrt trace` run measured.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct TraceReport {
    pub rays: u64,
    pub hits: u64,
    /// Ray upload + traversal + hit read-back, summed over batches (no file I/O, no build).
    pub gpu_seconds: f64,
    pub nodes_visited: u64,
    pub tris_tested: u64,
    /// Rays traced in sorted order (`--order`).
    pub reordered: u64,
    /// The device's own time in the trace dispatches (timestamps), if it has them.
    pub device_seconds: Option<f64>,
}

/// The layout `vkrt trace` walks unless `--layout` says. A one-level BVH: multi-order, which
/// traced both camera and incoherent rays fastest on lavapipe (Conference, Sibenik, Sponza:
/// 1.05-1.37x threaded's rays/s, medians of 5 alternating rounds, BENCHMARKS.md). A
/// `two_level` BVH (a scene with instances): wide levels, which traced them fastest (three
/// instanced scenes: 0.93-1.13x multi-order levels' rays/s, first in 11 of 12 cells of two runs;
/// 1.08-1.50x threaded levels',
/// docs/experiments/two-level-layouts.md). Either as long as the worst case of its nodes fits
/// one texel buffer of the device (`max_texel_buffer_elements` 16-byte texels): a binary
/// tree over n items has at most 2 n - 1 nodes (and its wide collapse no more), in six orders
/// of 2 texels or in wide nodes of 8. Beyond that (about 5.6 M triangles on lavapipe)
/// threaded, which needs 2. For a two-level BVH `triangles` counts each mesh's triangles once
/// and adds its instances: its trees hold at most 2 n - 1 nodes over n items each, so at most
/// 2 (triangles + instances) - 1 in all.
pub fn default_layout(triangles: usize, max_texel_buffer_elements: u32, two_level: bool) -> LayoutKind {
    let texel = TexelFormat::Rgba32Uint.bytes();
    let (layout, texels_per_node) = if two_level {
        (LayoutKind::Wide, (std::mem::size_of::<GpuWideNode>() as u64).div_ceil(texel))
    } else {
        (LayoutKind::MultiOrder, multi_order::ORDERS as u64 * (std::mem::size_of::<GpuNode>() as u64).div_ceil(texel))
    };
    let worst_nodes = 2 * triangles.max(1) as u64 - 1;
    if worst_nodes * texels_per_node <= u64::from(max_texel_buffer_elements) {
        layout
    } else {
        LayoutKind::Threaded
    }
}

pub fn run(args: &TraceArgs) -> Result<TraceReport> {
    let mut reader = RayReader::open(&args.rays)?;
    let scene = crate::scene::load_scene(&args.scene)?;
    let ctx = args.device.context()?;
    // A scene with instances walks its two-level BVH, both levels in the layout.
    let layout = match args.layout {
        Some(l) => l,
        None => {
            // Every triangle once, and a two-level BVH's instances (the scene's own triangles,
            // if any, are one more).
            let instances: usize = scene.instances.iter().map(|g| g.placements.len()).sum();
            let own = usize::from(instances > 0 && !scene.triangles.is_empty());
            let triangles = scene.triangles.len() + scene.instances.iter().map(|g| g.mesh.len()).sum::<usize>();
            default_layout(triangles + instances + own, ctx.info.max_texel_buffer_elements, instances > 0)
        }
    };
    let options = PrepareOptions { builder: args.builder, layout, build: BuildConfig::default(), triangle_list: !args.no_triangle_list };
    let (flat, build_times) = build_walk(&scene, &options)?;
    let walk = super::walk_name(layout, flat.nodes.instances().len());
    let bvh = GpuBvh::upload(&ctx, &flat)?;
    let mut query = RayQuery::new(&ctx, &bvh)?;
    query.order = args.order;
    query.warm_up()?;
    let mut writer = HitWriter::create(&args.output, reader.count())?;
    let mut report = TraceReport::default();
    loop {
        let rays = reader.next_batch(FILE_BATCH)?;
        if rays.is_empty() {
            break;
        }
        let t = Instant::now();
        let hits = query.trace(&rays, args.any_hit).context("tracing a batch of rays")?;
        report.gpu_seconds += t.elapsed().as_secs_f64();
        report.rays += rays.len() as u64;
        for h in &hits {
            report.hits += u64::from(h.prim != PRIM_NONE);
            report.nodes_visited += u64::from(h.nodes_visited);
            report.tris_tested += u64::from(h.tris_tested);
        }
        writer.write(&hits)?;
    }
    report.reordered = query.rays_reordered();
    report.device_seconds = query.device_seconds();
    writer.finish()?;
    ctx.check_validation().context("Vulkan validation")?;
    let per_ray = |x: u64| x as f64 / report.rays.max(1) as f64;
    let device_rate = report
        .device_seconds
        .filter(|&s| s > 0.0)
        .map_or(String::new(), |s| format!("; traversal alone {:.3} M rays/s by device timestamps", report.rays as f64 / s / 1e6));
    eprintln!(
        "traced {} rays ({} hit, {} in sorted order) on {} with {} / {}: {:.3} M rays/s (upload, sorting, traversal and read-back; build {:.0} ms not counted{device_rate}; {} rays per submission at the end), {:.1} nodes visited and {:.2} triangles tested per ray",
        report.rays,
        report.hits,
        report.reordered,
        ctx.info.name,
        args.builder.name(),
        walk,
        report.rays as f64 / report.gpu_seconds.max(1e-9) / 1e6,
        build_times.bvh() * 1e3,
        query.batch_rays(),
        per_ray(report.nodes_visited),
        per_ray(report.tris_tested)
    );
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_layout_is_multi_order_or_wide_levels_while_they_fit_the_texel_buffer() {
        // lavapipe: 2^27 texels of 16 bytes; a 32-byte node is two, six orders of 2n - 1 nodes.
        let lavapipe = 1u32 << 27;
        assert_eq!(default_layout(0, lavapipe, false), LayoutKind::MultiOrder);
        assert_eq!(default_layout(331_179, lavapipe, false), LayoutKind::MultiOrder);
        // 12 (2n - 1) <= 2^27 holds up to n = 5,592,405 and fails past it.
        assert_eq!(default_layout(5_592_405, lavapipe, false), LayoutKind::MultiOrder);
        assert_eq!(default_layout(5_592_406, lavapipe, false), LayoutKind::Threaded);
        assert_eq!(default_layout(10_000_000, lavapipe, false), LayoutKind::Threaded);
        // Vulkan's minimum limit, 65,536 texels: 12 (2n - 1) <= 65,536 up to n = 2,731.
        assert_eq!(default_layout(2_731, 65_536, false), LayoutKind::MultiOrder);
        assert_eq!(default_layout(2_732, 65_536, false), LayoutKind::Threaded);
        // Two levels: 128-byte wide nodes, 8 texels each: 8 (2n - 1) <= 2^27 up to n = 8,388,608.
        assert_eq!(default_layout(100_000, lavapipe, true), LayoutKind::Wide);
        assert_eq!(default_layout(8_388_608, lavapipe, true), LayoutKind::Wide);
        assert_eq!(default_layout(8_388_609, lavapipe, true), LayoutKind::Threaded);
    }
}
