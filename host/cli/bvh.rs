//! `vkrt bvh`: every builder x layout on each scene: build time, nodes, bytes, SAH cost, and for
//! primary, shadow and diffuse-bounce rays the measured nodes visited and triangles tested per
//! ray (the GPU's counters) and rays/s on the GPU. `--heatmap` draws nodes visited per pixel.
//! A scene with instances gets a row per builder and two-level layout for its two-level BVH too
//! (`two-level-threaded`, `two-level-multi-order`, ...: `accel::two_level`, every layout), and
//! the table a line
//! per such row with each level's counts.

use crate::accel::two_level::{self, LevelCounts};
use crate::accel::{self, LayoutKind};
use crate::bvh::{self, stats::stats, validate::validate, BuildConfig, BuilderKind};
use crate::gpu::Context;
use crate::gpu_abi::{GpuHit, GpuRay};
use crate::output::heatmap;
use crate::prepare::{build_two_level, walks_two_levels, GpuBvh, PrepareOptions};
use crate::query::{rays, RayQuery};
use crate::scene::{triangle_boxes, Scene};
use anyhow::{anyhow, Context as _, Result};
use clap::{Args, ValueEnum};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Timed runs per ray set; the fastest counts.
const TIMED_RUNS: usize = 3;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// A Markdown table.
    Table,
    Csv,
    Json,
}

#[derive(Debug, Args)]
pub struct BvhArgs {
    /// Scene files (.obj, lab .yaml, glTF .gltf/.glb).
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Primary rays: one per pixel of a WIDTH x HEIGHT camera image (also the heat map's size).
    #[arg(long, default_value_t = 384)]
    pub width: u32,
    /// Height of the primary-ray image (and the heat map).
    #[arg(long, default_value_t = 384)]
    pub height: u32,
    /// Builds timed per builder; the best is reported (single-threaded).
    #[arg(long, default_value_t = 3)]
    pub repeat: u32,
    /// Write nodes visited per pixel of the primary rays as a PNG heat map with a legend; with
    /// several scenes, one file each, named OUT-SCENE.png.
    #[arg(long, value_name = "OUT.png")]
    pub heatmap: Option<PathBuf>,
    /// Builder the heat map shows.
    #[arg(long, value_enum, default_value_t = BuilderKind::default())]
    pub heatmap_builder: BuilderKind,
    /// Layout the heat map shows.
    #[arg(long, value_enum, default_value_t = LayoutKind::Threaded)]
    pub heatmap_layout: LayoutKind,
    /// Only these builders (default: all).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub builders: Vec<BuilderKind>,
    /// Only these layouts (default: all).
    #[arg(long, value_enum, value_delimiter = ',')]
    pub layouts: Vec<LayoutKind>,
    #[command(flatten)]
    pub device: super::DeviceArgs,
}

/// Per-ray counters and throughput of one ray set.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RayStats {
    pub nodes_per_ray: f64,
    pub tris_per_ray: f64,
    pub rays_per_second: f64,
}

/// One line of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub scene: String,
    pub triangles: usize,
    pub builder: BuilderKind,
    pub layout: LayoutKind,
    pub build_ms: f64,
    /// Nodes of the tree (each layout stores them its own way; `bytes` says at what cost).
    pub nodes: usize,
    /// GPU bytes of nodes + triangles in this layout.
    pub bytes: usize,
    pub sah: f32,
    pub primary: RayStats,
    pub shadow: RayStats,
    pub diffuse: RayStats,
    /// A scene with instances also gets a row for its two-level BVH in each layout that lays
    /// one out (`accel::two_level::LAYOUTS`): `nodes` and `bytes` are both levels' (every
    /// order's), `sah` the top level's.
    pub two_level: Option<LevelCounts>,
}

impl Row {
    /// The layout column: the layout's name, or `two-level-` and it.
    pub fn layout_name(&self) -> String {
        match self.two_level {
            Some(_) => format!("two-level-{}", self.layout.name()),
            None => self.layout.name().to_string(),
        }
    }
}

/// Time and count one ray set (upload, traversal, read-back): the best of `TIMED_RUNS`, since
/// the machine may be shared and a short run is easily disturbed.
fn measure(query: &RayQuery, rays: &[GpuRay], any_hit: bool) -> Result<(RayStats, Vec<GpuHit>)> {
    let mut seconds = f64::INFINITY;
    let mut hits = Vec::new();
    for _ in 0..TIMED_RUNS {
        let t = Instant::now();
        hits = query.trace(rays, any_hit)?;
        seconds = seconds.min(t.elapsed().as_secs_f64());
    }
    let n = rays.len().max(1) as f64;
    Ok((
        RayStats {
            nodes_per_ray: hits.iter().map(|h| f64::from(h.nodes_visited)).sum::<f64>() / n,
            tris_per_ray: hits.iter().map(|h| f64::from(h.tris_tested)).sum::<f64>() / n,
            rays_per_second: rays.len() as f64 / seconds.max(1e-9),
        },
        hits,
    ))
}

/// Every requested builder x layout on one scene.
pub fn scene_rows(ctx: &Context, path: &Path, scene: &Scene, args: &BvhArgs) -> Result<Vec<Row>> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let builders = if args.builders.is_empty() { BuilderKind::ALL.to_vec() } else { args.builders.clone() };
    let layouts = if args.layouts.is_empty() { LayoutKind::ALL.to_vec() } else { args.layouts.clone() };
    let config = BuildConfig::default();
    // The one-level rows walk the instances' copies placed; a scene of more copies than a
    // one-level tree takes gets its two-level rows only.
    let expanded = match scene.expanded() {
        Ok(e) => Some(e),
        Err(e) if layouts.iter().any(|&l| walks_two_levels(scene, l)) => {
            eprintln!("vkrt bvh: {name}: only the two-level rows: {e}");
            None
        }
        Err(e) => return Err(anyhow!("{name}: {e}")),
    };
    let (boxes, centroids) = expanded.as_ref().map(|e| triangle_boxes(&e.triangles)).unwrap_or_default();

    // The ray sets, shared by every builder x layout: primary rays, and shadow and bounce rays
    // from their hits (found with the CPU twin of a binned-SAH threaded tree, two-level for a
    // scene with instances).
    let primary = rays::primary(scene, args.width, args.height)?;
    let reference = match &expanded {
        Some(e) if scene.instances.is_empty() => {
            accel::flatten(&bvh::build(BuilderKind::Sah, &boxes, &centroids, &config), &e.triangles, LayoutKind::Threaded)?
        }
        _ => build_two_level(scene, &PrepareOptions { builder: BuilderKind::Sah, ..PrepareOptions::default() })?.0,
    };
    let primary_hits: Vec<GpuHit> = primary.iter().map(|r| reference.trace(r, false)).collect();
    let (shadow, diffuse) = rays::secondary(scene, &primary, &primary_hits, 1);
    drop(reference);
    let placed = scene.placed_triangles() as usize;

    let mut rows = Vec::new();
    for &builder in &builders {
        if let Some(e) = &expanded {
            let mut build_ms = f64::INFINITY;
            let mut tree = bvh::Bvh::default();
            for _ in 0..args.repeat.max(1) {
                let t = Instant::now();
                tree = bvh::build(builder, &boxes, &centroids, &config);
                build_ms = build_ms.min(t.elapsed().as_secs_f64() * 1e3);
            }
            validate(&tree, &boxes).map_err(|e| anyhow!("{} tree of {name} is invalid: {e}", builder.name()))?;
            let s = stats(&tree);
            for &layout in &layouts {
                let flat = accel::flatten(&tree, &e.triangles, layout)?;
                let gpu = GpuBvh::upload(ctx, &flat)?;
                let query = RayQuery::new(ctx, &gpu)?;
                query.warm_up()?;
                let (p, hits) = measure(&query, &primary, false)?;
                let (sh, _) = measure(&query, &shadow, true)?;
                let (d, _) = measure(&query, &diffuse, false)?;
                if let Some(out) = &args.heatmap {
                    if builder == args.heatmap_builder && layout == args.heatmap_layout {
                        let out = heatmap_path(out, path, args.scenes.len() > 1);
                        let counts: Vec<u32> = hits.iter().map(|h| h.nodes_visited).collect();
                        heatmap::write(&out, &counts, args.width, args.height, "nodes visited per ray")?;
                        eprintln!("heat map of nodes visited ({} / {}): {}", builder.name(), layout.name(), out.display());
                    }
                }
                rows.push(Row {
                    scene: name.clone(),
                    triangles: placed,
                    builder,
                    layout,
                    build_ms,
                    nodes: s.nodes,
                    bytes: flat.bytes(),
                    sah: s.sah_cost,
                    primary: p,
                    shadow: sh,
                    diffuse: d,
                    two_level: None,
                });
            }
        }
        for &layout in layouts.iter().filter(|&&l| walks_two_levels(scene, l)) {
            rows.push(two_level_row(ctx, &name, scene, builder, layout, args, [&primary, &shadow, &diffuse])?);
        }
    }
    Ok(rows)
}

/// The row of a scene's two-level BVH built by `builder` in `layout`, on the same ray sets.
#[allow(clippy::too_many_arguments)]
fn two_level_row(
    ctx: &Context,
    name: &str,
    scene: &Scene,
    builder: BuilderKind,
    layout: LayoutKind,
    args: &BvhArgs,
    [primary, shadow, diffuse]: [&[GpuRay]; 3],
) -> Result<Row> {
    let mut build_ms = f64::INFINITY;
    let mut built = None;
    for _ in 0..args.repeat.max(1) {
        let t = Instant::now();
        built = Some(two_level::build(&two_level::meshes(scene), builder, &BuildConfig::default(), layout)?);
        build_ms = build_ms.min(t.elapsed().as_secs_f64() * 1e3);
    }
    let (nodes, triangles) = built.ok_or_else(|| anyhow!("no two-level build"))?;
    let counts = nodes.counts(triangles.len());
    let flat = nodes.into_flat(triangles);
    let gpu = GpuBvh::upload(ctx, &flat)?;
    let query = RayQuery::new(ctx, &gpu)?;
    query.warm_up()?;
    Ok(Row {
        scene: name.to_string(),
        triangles: scene.placed_triangles() as usize,
        builder,
        layout,
        build_ms,
        nodes: flat.node_count(),
        bytes: flat.bytes(),
        sah: counts.top_sah,
        primary: measure(&query, primary, false)?.0,
        shadow: measure(&query, shadow, true)?.0,
        diffuse: measure(&query, diffuse, false)?.0,
        two_level: Some(counts),
    })
}

fn heatmap_path(out: &Path, scene: &Path, per_scene: bool) -> PathBuf {
    if !per_scene {
        return out.to_path_buf();
    }
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let scene_stem = scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    out.with_file_name(format!("{stem}-{scene_stem}.png"))
}

pub fn run(args: &BvhArgs) -> Result<()> {
    if args.width == 0 || args.height == 0 {
        anyhow::bail!("--width and --height must be positive");
    }
    let ctx = args.device.context()?;
    let mut rows = Vec::new();
    for path in &args.scenes {
        let scene = crate::scene::load_scene(path)?;
        rows.extend(scene_rows(&ctx, path, &scene, args).with_context(|| format!("comparing BVHs on {}", path.display()))?);
    }
    ctx.check_validation().context("Vulkan validation")?;
    print!("{}", format_rows(&rows, args.format, &ctx.info.name));
    Ok(())
}

const COLUMNS: [&str; 17] = [
    "scene",
    "triangles",
    "builder",
    "layout",
    "build_ms",
    "nodes",
    "bytes",
    "sah",
    "primary_nodes",
    "primary_tris",
    "primary_mrays",
    "shadow_nodes",
    "shadow_tris",
    "shadow_mrays",
    "diffuse_nodes",
    "diffuse_tris",
    "diffuse_mrays",
];

fn values(r: &Row) -> [String; 17] {
    let f1 = |x: f64| format!("{x:.1}");
    let f2 = |x: f64| format!("{x:.2}");
    let m = |s: &RayStats| format!("{:.2}", s.rays_per_second / 1e6);
    [
        r.scene.clone(),
        r.triangles.to_string(),
        r.builder.name().to_string(),
        r.layout_name(),
        f1(r.build_ms),
        r.nodes.to_string(),
        r.bytes.to_string(),
        f2(f64::from(r.sah)),
        f1(r.primary.nodes_per_ray),
        f2(r.primary.tris_per_ray),
        m(&r.primary),
        f1(r.shadow.nodes_per_ray),
        f2(r.shadow.tris_per_ray),
        m(&r.shadow),
        f1(r.diffuse.nodes_per_ray),
        f2(r.diffuse.tris_per_ray),
        m(&r.diffuse),
    ]
}

/// The rows as a Markdown table, CSV (header + one line per row) or a JSON array of objects.
/// Rays/s are in millions (`*_mrays`), counters are per ray.
pub fn format_rows(rows: &[Row], format: Format, device: &str) -> String {
    let mut s = String::new();
    match format {
        Format::Table => {
            let _ = writeln!(s, "device: {device}; nodes/tris = visited/tested per ray; M rays/s include upload and read-back");
            let _ = writeln!(s, "| {} |", COLUMNS.join(" | "));
            let _ = writeln!(s, "|{}", "---|".repeat(COLUMNS.len()));
            for r in rows {
                let _ = writeln!(s, "| {} |", values(r).join(" | "));
            }
            for r in rows {
                if let Some(c) = &r.two_level {
                    let _ = writeln!(
                        s,
                        "{} / {} / {}: {} instances of {} meshes; top level {} nodes (its SAH {:.2}); bottom levels {} nodes over {} triangles (the copies hold {})",
                        r.scene,
                        r.builder.name(),
                        r.layout_name(),
                        c.instances,
                        c.meshes,
                        c.top_nodes,
                        c.top_sah,
                        c.bottom_nodes,
                        c.bottom_triangles,
                        r.triangles
                    );
                }
            }
        }
        Format::Csv => {
            let _ = writeln!(s, "{}", COLUMNS.join(","));
            for r in rows {
                let v = values(r).map(|x| if x.contains([',', '"']) { format!("\"{}\"", x.replace('"', "\"\"")) } else { x });
                let _ = writeln!(s, "{}", v.join(","));
            }
        }
        Format::Json => {
            s.push_str("[\n");
            for (i, r) in rows.iter().enumerate() {
                let fields: Vec<String> = COLUMNS
                    .iter()
                    .zip(values(r))
                    .enumerate()
                    .map(|(k, (c, v))| {
                        // Columns 0, 2 and 3 are names; the others are numbers.
                        if matches!(k, 0 | 2 | 3) {
                            format!("\"{c}\": {}", json_string(&v))
                        } else {
                            format!("\"{c}\": {v}")
                        }
                    })
                    .collect();
                let _ = writeln!(s, "  {{{}}}{}", fields.join(", "), if i + 1 < rows.len() { "," } else { "" });
            }
            s.push_str("]\n");
        }
    }
    s
}

fn json_string(v: &str) -> String {
    let mut out = String::from("\"");
    for c in v.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
